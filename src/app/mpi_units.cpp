#include "app/mpi_units.h"

// The C API only: OpenMPI's mpi.h otherwise pulls in the removed C++ bindings.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace fricrom::app {
namespace {

bool g_active = false;

// Debian's sequential MUMPS (linked through Ipopt) exports its own C stubs MPI_Init,
// MPI_Comm_rank, MPI_Finalize and MPI_Wtime (rank always 0, finalise a no-op), and the dynamic
// linker binds our calls to them. These two go through the standard profiling names (PMPI_*),
// which only the real MPI library defines; the other calls we make are not stubbed.
int CommRank() {
  int r = 0;
  PMPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

// A worker keeps one unit in hand besides the one it computes: it asks for the next unit as it
// starts a unit, so the answer is waiting when it finishes. Without that, a worker waited ~2 ms
// per unit for rank 0's main thread, which shares a core with rank 0's own worker (40-value
// lumped sweep on 2 ranks: 33-44 ms of 0.67 s).
enum Tag : int {
  kRequest = 1,  // worker -> root: "one more unit, please" (an int, unused)
  kDone = 2,     // worker -> root: an int, the unit it finished; its result text follows
  kResult = 3,   // worker -> root: the finished unit's result text
  kAssign = 4,   // root -> worker: an int, the next unit (-1: no more, stop)
  kFailed = 5,   // worker -> root: the text of the exception its unit threw
};

bool LaunchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}

std::string ReceiveText(int source, int tag) {
  MPI_Status st;
  MPI_Probe(source, tag, MPI_COMM_WORLD, &st);
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  std::string text(static_cast<size_t>(n), '\0');
  MPI_Recv(text.data(), n, MPI_CHAR, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return text;
}

void SendText(const std::string& text, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, tag, MPI_COMM_WORLD);
}

// Rank > 0: ask for a unit; then, for each unit received, ask for the next one, compute, send
// the result, and take the answer; until the answer is a stop. Every request gets exactly one
// answer, so a stop ends the exchange; after a failure the worker drops units until the stop.
void Work(const std::function<std::string(int)>& compute) {
  const auto request = [] {
    const int ask = -1;
    MPI_Send(&ask, 1, MPI_INT, 0, kRequest, MPI_COMM_WORLD);
  };
  const auto answer = [] {
    int unit = -1;
    MPI_Recv(&unit, 1, MPI_INT, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return unit;
  };
  request();
  for (int unit = answer(); unit >= 0; unit = answer()) {
    request();
    std::string result;
    try {
      result = compute(unit);
    } catch (const std::exception& e) {
      SendText(e.what(), kFailed);
      while (answer() >= 0) {
      }
      return;
    }
    MPI_Send(&unit, 1, MPI_INT, 0, kDone, MPI_COMM_WORLD);
    SendText(result, kResult);
  }
}

// All ranks on this node (OpenMPI tells before MPI_Init): its ob1 messaging layer over shared
// memory (`vader`, and `self`) starts in a fraction of the time its default UCX layer and the TCP
// probing take (two ranks here: 0.33 s with the defaults, 0.10 s the command alone), and our
// messages are a few bytes per unit. A setting of the user's always wins.
void PreferSharedMemoryOnOneNode() {
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const char* all = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (local == nullptr || all == nullptr || std::string(local) != all) return;
  if (std::getenv("OMPI_MCA_pml") == nullptr) setenv("OMPI_MCA_pml", "ob1", 0);
  if (std::getenv("OMPI_MCA_btl") == nullptr) setenv("OMPI_MCA_btl", "self,vader", 0);
}

// OpenMPI's PMIx client (PMIx 4.2 in Debian 12) talks to the launcher over a loopback TCP
// connection without TCP_NODELAY: a short message sent while the previous one is unacknowledged
// waits for the launcher's delayed ACK, 40 ms, at every PMIx fence (MPI_Finalize measured 46 ms
// per rank, 4 ms with the option). After MPI_Init the process's TCP sockets are MPI's (fricrom
// opens none), so they all get the option; it only changes the latency of small writes.
void DisableNagleOnMpiSockets() {
  for (int fd = 0; fd < 1024; ++fd) {
    int type = 0;
    socklen_t len = sizeof type;
    if (getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &len) != 0 || type != SOCK_STREAM) continue;
    sockaddr_storage addr{};
    socklen_t addr_len = sizeof addr;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &addr_len) != 0) continue;
    if (addr.ss_family != AF_INET && addr.ss_family != AF_INET6) continue;
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }
}

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  if (!LaunchedByMpi()) return;
  PreferSharedMemoryOnOneNode();
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  DisableNagleOnMpiSockets();
  g_active = true;
}

MpiSession::~MpiSession() {
  if (g_active) PMPI_Finalize();
  g_active = false;
}

int MpiSession::Finish(int code) {
  if (g_active && code != 0 && MpiSize() > 1) MPI_Abort(MPI_COMM_WORLD, code);
  return code;
}

int MpiRank() { return g_active ? CommRank() : 0; }

int MpiSize() {
  int n = 1;
  if (g_active) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

double BroadcastFromRoot(double v) {
  if (g_active) MPI_Bcast(&v, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return v;
}

std::string BroadcastText(const std::string& text) {
  if (!g_active) return text;
  unsigned long long n = text.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  if (n > static_cast<unsigned long long>(std::numeric_limits<int>::max())) {
    throw std::runtime_error("BroadcastText: text longer than 2 GiB");
  }
  std::string out = CommRank() == 0 ? text : std::string(static_cast<size_t>(n), '\0');
  MPI_Bcast(out.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  return out;
}

namespace {

// Rank 0's main thread: answers the workers' requests (Work) and hands their results to
// `finish`. A worker asking while it still computes gets a unit at once only while at least as
// many units remain as there are ranks; near the end its request waits for its result, so that
// no unit sits in a busy worker's hand while another rank has nothing to do.
void ServeWorkers(const std::function<int()>& take, const std::function<size_t()>& left,
                  const std::function<void(int, const std::string&)>& finish,
                  const std::function<void(std::exception_ptr)>& fail) {
  const int size = MpiSize();
  std::vector<int> in_hand(static_cast<size_t>(size), 0);       // units sent, result not back yet
  std::vector<bool> waiting(static_cast<size_t>(size), false);  // a request not yet answered
  std::vector<bool> stopped(static_cast<size_t>(size), false);  // sent its stop
  const auto assign = [&](int to) {
    const int unit = take();
    MPI_Send(&unit, 1, MPI_INT, to, kAssign, MPI_COMM_WORLD);
    waiting[to] = false;
    if (unit < 0) {
      stopped[to] = true;
    } else {
      ++in_hand[to];
    }
  };
  const auto settled = [&](int w) { return stopped[w] && in_hand[w] == 0; };
  int running = size - 1;
  while (running > 0) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    const int from = st.MPI_SOURCE;
    const bool was_settled = settled(from);
    if (st.MPI_TAG == kFailed) {
      const std::string what = ReceiveText(from, kFailed);
      fail(std::make_exception_ptr(
          std::runtime_error("rank " + std::to_string(from) + ": " + what)));
      in_hand[from] = 0;
      if (!stopped[from]) assign(from);  // take() now returns -1: the stop the worker waits for
    } else if (st.MPI_TAG == kDone) {
      int done = -1;
      MPI_Recv(&done, 1, MPI_INT, from, kDone, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      const std::string result = ReceiveText(from, kResult);
      --in_hand[from];
      if (waiting[from]) assign(from);  // before the write: the worker computes meanwhile
      finish(done, result);
    } else {
      int ask = 0;
      MPI_Recv(&ask, 1, MPI_INT, from, kRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      waiting[from] = true;
      const size_t queued = left();
      if (in_hand[from] == 0 || queued == 0 || queued >= static_cast<size_t>(size)) assign(from);
    }
    if (!was_settled && settled(from)) --running;
  }
}

}  // namespace

void DistributeUnits(const std::vector<int>& pending,
                     const std::function<std::string(int)>& compute,
                     const std::function<void(int, const std::string&)>& finished) {
  if (MpiSize() < 2) throw std::logic_error("DistributeUnits needs several MPI ranks");
  if (MpiRank() != 0) return Work(compute);
  // Rank 0: a local worker thread takes units from the same queue as the remote ranks; only
  // this (main) thread calls MPI (MPI_THREAD_FUNNELED).
  std::mutex lock;
  size_t next = 0;
  std::exception_ptr error;
  auto take = [&]() {
    const std::lock_guard<std::mutex> g(lock);
    return (error || next >= pending.size()) ? -1 : pending[next++];
  };
  // `finished` (a journal append with fsync) runs under its own lock, never under the queue's:
  // a rank asking for its next unit does not wait for another unit's disk write.
  std::mutex finish_lock;
  auto fail = [&](std::exception_ptr e) {
    const std::lock_guard<std::mutex> g(lock);
    if (!error) error = e;
  };
  auto finish = [&](int unit, const std::string& result) {
    try {
      const std::lock_guard<std::mutex> g(finish_lock);
      finished(unit, result);
    } catch (...) {
      fail(std::current_exception());
    }
  };
  std::thread local([&] {
    for (int unit = take(); unit >= 0; unit = take()) {
      try {
        finish(unit, compute(unit));
      } catch (...) {
        fail(std::current_exception());
      }
    }
  });
  auto left = [&]() -> size_t {
    const std::lock_guard<std::mutex> g(lock);
    return error ? 0 : pending.size() - next;
  };
  ServeWorkers(take, left, finish, fail);
  local.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace fricrom::app
