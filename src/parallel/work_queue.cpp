#include "fricrom/work_queue.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace fricrom {

int WorkerThreads(int requested, int units) {
  int n = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
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
