// Threads of the BLAS/LAPACK library behind fricrom's large dense kernels.
//
// OpenBLAS threads every large call by default. The harmonic-balance engine alternates short BLAS
// calls (LU of a ~10³ condensed Jacobian) with its own single-threaded work, and there the spin
// of idle OpenBLAS threads costs more than the threads gain
// (docs/decisions/0007-one-blas-thread.md). The CLI therefore runs its harmonic-balance commands
// with one thread unless OPENBLAS_NUM_THREADS is set; MPI ranks want one per rank for the same
// reason.
#pragma once

namespace fricrom {

// Sets the thread count of OpenBLAS (looked up at run time). Returns false when the BLAS in use
// offers no such control (reference BLAS is single-threaded anyway). Setting one thread also
// stops OpenBLAS's idle worker pool, which otherwise spins for ~0.1 s after start-up. Call it
// before starting threads of one's own. Throws for threads < 1.
bool SetBlasThreads(int threads);

}  // namespace fricrom
