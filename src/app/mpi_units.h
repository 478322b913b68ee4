// Units of work over MPI ranks (mpirun -np N fricrom sweep ...). MPI is started only when the
// process was launched by an MPI launcher (OMPI_/PMI_/PMIX_ variables), so the binary run alone
// behaves exactly as without MPI and never prints MPI's start-up messages.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace fricrom::app {

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);  // MPI_Init_thread under a launcher, else nothing
  ~MpiSession();                        // MPI_Finalize
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  // Ends the run with `code`: with several ranks a failure on any rank aborts the whole job
  // (the others may be waiting for it) with that exit status.
  int Finish(int code);
};

int MpiRank();  // 0 without MPI
int MpiSize();  // 1 without MPI

// Rank 0's value of `v` on every rank (v unchanged without MPI).
double BroadcastFromRoot(double v);
// Rank 0's `text` on every rank (collective: every rank calls it; text unchanged without MPI).
std::string BroadcastText(const std::string& text);

// Computes the `pending` units (indices) on every rank with dynamic load balancing: each rank
// asks rank 0 for the next unit when it is free; rank 0 computes units as well (on a second
// thread; its main thread serves the others). On rank 0, finished(i, result) is called once per
// unit, one call at a time, with the text compute(i) returned on whichever rank ran it; on the
// other ranks `pending` and `finished` are not used. Returns on every rank when all are done.
// Needs MpiSize() > 1.
void DistributeUnits(const std::vector<int>& pending,
                     const std::function<std::string(int)>& compute,
                     const std::function<void(int, const std::string&)>& finished);

}  // namespace fricrom::app
