// The CPU kernels of the BLAS/LAPACK library behind fricrom's dense kernels (OpenBLAS).
//
// Debian 12's OpenBLAS (0.3.21) picks its kernels at load time from the CPU model, and a CPU
// newer than it knows gets its fallback, "Prescott": SSE3 kernels on a machine with AVX2, FMA
// and AVX-512, a third slower on fricrom's dense kernels
// (docs/decisions/0006-openblas-core-restart.md). OpenBLAS reads the choice from OPENBLAS_CORETYPE
// when it loads, so the CLI and the benchmarks start themselves again with it set where
// RecommendedBlasCore() says so.
#pragma once

#include <string>

namespace fricrom {

// The core OpenBLAS dispatches to ("Haswell", "Zen", "Prescott", ...), looked up at run time;
// "" when the BLAS in use is not OpenBLAS (or was built for one core only).
std::string BlasCoreName();

// Whether this CPU runs AVX2 and FMA instructions (what OpenBLAS's Haswell kernels use).
bool CpuHasAvx2Fma();

// The OpenBLAS core to force for `detected` on a CPU with (or without) AVX2 + FMA: "Haswell"
// where `detected` is OpenBLAS's fallback for an unknown CPU ("Prescott") and the CPU runs
// AVX2 + FMA; "" (keep what OpenBLAS chose) otherwise. Pure: the decision, testable anywhere.
std::string BlasCoreOverride(const std::string& detected, bool cpu_has_avx2_fma);

// BlasCoreOverride for this process, or "" where OPENBLAS_CORETYPE is set already (the user's
// choice, or a start that forced it: a restart never repeats).
std::string RecommendedBlasCore();

// For a program's main(), before anything else: where RecommendedBlasCore() names a core, sets
// OPENBLAS_CORETYPE to it (and FRICROM_BLAS_CORE_DETECTED to what OpenBLAS had chosen) and
// executes the same program again with the same arguments (/proc/self/exe; the process and its
// id stay, so mpirun and shells see nothing). Returns only where nothing was to be done or the
// restart failed (the run then goes on with the detected kernels). FRICROM_KEEP_BLAS_CORE=1
// switches it off.
void RestartWithRecommendedBlasCore(char** argv);

// What the run uses, for --version and output manifests: "OpenBLAS Haswell", "OpenBLAS Haswell
// (forced; OpenBLAS chose Prescott)", or "not OpenBLAS".
std::string BlasCoreReport();

}  // namespace fricrom
