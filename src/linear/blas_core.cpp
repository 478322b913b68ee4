// The BLAS core OpenBLAS dispatches to, and where fricrom overrides it (fricrom/blas_core.h).
#include "fricrom/blas_core.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <string>

namespace fricrom {

std::string BlasCoreName() {
  using CoreName = char* (*)();
  void* symbol = dlsym(RTLD_DEFAULT, "openblas_get_corename");
  if (symbol == nullptr) return "";
  const char* name = reinterpret_cast<CoreName>(symbol)();
  return name == nullptr ? "" : name;
}

bool CpuHasAvx2Fma() {
#if defined(__x86_64__) || defined(__i386__)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

std::string BlasCoreOverride(const std::string& detected, bool cpu_has_avx2_fma) {
  // Only OpenBLAS's fallback is overridden: a core it recognised is its own informed choice.
  // OpenBLAS spells core names in its own case ("Prescott", "PRESCOTT" in its kernel symbols).
  std::string lower;
  for (char c : detected) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "prescott" && cpu_has_avx2_fma ? "Haswell" : "";
}

std::string RecommendedBlasCore() {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return "";
  return BlasCoreOverride(BlasCoreName(), CpuHasAvx2Fma());
}

void RestartWithRecommendedBlasCore(char** argv) {
  if (argv == nullptr || argv[0] == nullptr) return;
  const char* keep = std::getenv("FRICROM_KEEP_BLAS_CORE");
  if (keep != nullptr && std::string(keep) == "1") return;
  const std::string core = RecommendedBlasCore();
  if (core.empty()) return;
  const std::string detected = BlasCoreName();
  // The environment must say it before OpenBLAS loads: its dispatch table is fixed by then.
  if (setenv("OPENBLAS_CORETYPE", core.c_str(), 1) != 0) return;
  setenv("FRICROM_BLAS_CORE_DETECTED", detected.c_str(), 1);
  execv("/proc/self/exe", argv);
  // No restart (no /proc?): go on as detected, and say so in the report.
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv("FRICROM_BLAS_CORE_DETECTED");
}

std::string BlasCoreReport() {
  const std::string core = BlasCoreName();
  if (core.empty()) return "not OpenBLAS";
  std::string report = "OpenBLAS " + core;
  const char* detected = std::getenv("FRICROM_BLAS_CORE_DETECTED");
  if (detected != nullptr && *detected != '\0') {
    report += std::string(" (forced; OpenBLAS chose ") + detected + ")";
  }
  return report;
}

}  // namespace fricrom
