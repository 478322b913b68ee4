// fricrom command-line tool; see README.md and docs/ for the commands.
#include "app/commands.h"
#include "app/mpi_units.h"
#include "fricrom/blas_core.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

int main(int argc, char** argv) {
  // OpenBLAS's SSE3 fallback on CPUs it does not know costs ~25 % of an FE bound: start again
  // with its AVX2 kernels where it fell back (fricrom/blas_core.h).
  fricrom::RestartWithRecommendedBlasCore(argv);
#if defined(__GLIBC__)
  // The engine allocates and frees MiB-sized temporaries (dense Jacobians, receptance blocks)
  // every Newton iteration. Above glibc's mmap threshold each is mapped and unmapped again, and
  // every reuse pays for fresh zeroed pages: 9 s of system time in a 44 s FE bound curve on 2
  // threads, 0.7 s with these kept in the heap (peak memory +2 %).
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
  fricrom::app::MpiSession mpi(&argc, &argv);  // only under mpirun (app/mpi_units.h)
  return mpi.Finish(fricrom::app::Run(argc, argv));
}
