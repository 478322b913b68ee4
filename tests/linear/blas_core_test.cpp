// The OpenBLAS core override (fricrom/blas_core.h): only OpenBLAS's fallback for an unknown CPU is
// replaced, and only by kernels the CPU runs. The restart itself is tested through the CLI
// (tests/app/cli_test.cpp, Cli.VersionNamesTheBlasCoreItRunsOn).
#include "fricrom/blas_core.h"

#include <gtest/gtest.h>

#include <string>

namespace {

TEST(BlasCore, OnlyTheFallbackOnAnAvx2CpuIsOverridden) {
  EXPECT_EQ(fricrom::BlasCoreOverride("Prescott", true), "Haswell");
  EXPECT_EQ(fricrom::BlasCoreOverride("PRESCOTT", true), "Haswell");
  // Without AVX2 + FMA the fallback is the right choice.
  EXPECT_EQ(fricrom::BlasCoreOverride("Prescott", false), "");
  // A core OpenBLAS recognised is its own informed choice.
  for (const char* core : {"Haswell", "SkylakeX", "Zen", "Cooperlake", "Sandybridge"}) {
    EXPECT_EQ(fricrom::BlasCoreOverride(core, true), "") << core;
  }
  // Not OpenBLAS (reference BLAS, or no BLAS core to report).
  EXPECT_EQ(fricrom::BlasCoreOverride("", true), "");
}

TEST(BlasCore, ReportNamesTheLibrary) {
  const std::string core = fricrom::BlasCoreName();
  const std::string report = fricrom::BlasCoreReport();
  if (core.empty()) {
    EXPECT_EQ(report, "not OpenBLAS");
  } else {
    EXPECT_EQ(report.rfind("OpenBLAS " + core, 0), 0u) << report;
  }
}

}  // namespace
