#include "fricrom/work_queue.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace fricrom {

int UsableCores() {
  // The process's CPU affinity, not the machine's core count: under `mpirun` (which binds each
  // rank to a core by default) or `srun --cpus-per-task` a rank may run on fewer cores than the
  // node has, and one thread per node core would share them (mpirun -np 1 on the 8-point FE
  // curve: 2 threads on 1 core, 9.2 s against 7.9 s on 1 thread).
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

int WorkerThreads(int requested, int units) {
  const int n = requested > 0 ? requested : UsableCores();
  return std::max(1, std::min(n, units));
}

void RunWorkUnits(const std::vector<int>& pending, int threads,
                  const std::function<void(int)>& unit, const std::function<void(int)>& finished) {
  const int n = static_cast<int>(pending.size());
  if (n == 0) return;
  const int workers = WorkerThreads(threads, n);
  if (workers == 1) {
    for (int i : pending) {
      unit(i);
      finished(i);
    }
    return;
  }
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  std::mutex lock;
  std::exception_ptr first_error;
  auto work = [&] {
    for (;;) {
      if (stop.load()) return;
      const int k = next.fetch_add(1);
      if (k >= n) return;
      try {
        unit(pending[k]);
        const std::lock_guard<std::mutex> guard(lock);
        if (!first_error) finished(pending[k]);
      } catch (...) {
        const std::lock_guard<std::mutex> guard(lock);
        if (!first_error) first_error = std::current_exception();
        stop.store(true);
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace fricrom
