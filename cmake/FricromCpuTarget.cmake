# Instruction set of the build. By default, where the compiler and the building machine both
# support it, the whole project (library, CLI, tests, benchmarks: one setting, so Eigen's
# alignment and packet sizes agree across translation units) is compiled for x86-64-v3 (AVX2,
# FMA, BMI2; every x86-64 server since ~2015): less time on the FE bounds
# (docs/decisions/0013-x86-64-v3-build.md). -DFRICROM_PORTABLE=ON builds for any x86-64 instead, for binaries that
# must run on other machines. -ffp-contract=off keeps each scalar expression rounded as written
# (no fused multiply-adds the source does not ask for): results differ from the portable build
# only where Eigen's wider packets reorder sums.
option(FRICROM_PORTABLE "Build for any x86-64 (no AVX2/FMA even where this machine has them)" OFF)
set(FRICROM_CPU_TARGET "portable")
if(NOT FRICROM_PORTABLE AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$"
   AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  include(CheckCXXSourceRuns)
  set(CMAKE_REQUIRED_FLAGS "-march=x86-64-v3")
  # Runs only if this machine executes x86-64-v3 code and reports the features it relies on.
  check_cxx_source_runs([[
    int main() {
      __builtin_cpu_init();
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
             __builtin_cpu_supports("bmi2") ? 0 : 1;
    }]] FRICROM_MACHINE_RUNS_X86_64_V3)
  unset(CMAKE_REQUIRED_FLAGS)
  if(FRICROM_MACHINE_RUNS_X86_64_V3)
    add_compile_options(-march=x86-64-v3 -ffp-contract=off)
    set(FRICROM_CPU_TARGET "x86-64-v3")
  endif()
endif()
message(STATUS "fricrom: instruction set ${FRICROM_CPU_TARGET} (-DFRICROM_PORTABLE=ON for any x86-64)")
