// The OpenBLAS core override (fricrom/blas_core.h): only OpenBLAS's fallback for an unknown CPU is
// replaced, and only by kernels the CPU runs. The restart itself is tested through the CLI
// (tests/app/cli_test.cpp, Cli.VersionNamesTheBlasCoreItRunsOn).
#include "fricrom/blas_core.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
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

// A core set in the environment is the user's choice, or the mark of a restart that set it:
// nothing is recommended then, so a restart never repeats itself.
TEST(BlasCore, NothingIsRecommendedOnceOpenblasCoretypeIsSet) {
  const char* before = std::getenv("OPENBLAS_CORETYPE");
  const std::optional<std::string> saved =
      before ? std::optional<std::string>(before) : std::nullopt;
  ASSERT_EQ(setenv("OPENBLAS_CORETYPE", "Prescott", 1), 0);
  EXPECT_EQ(fricrom::RecommendedBlasCore(), "");
  fricrom::RestartWithRecommendedBlasCore(nullptr);  // no argv: returns at once
  if (saved) {
    setenv("OPENBLAS_CORETYPE", saved->c_str(), 1);
  } else {
    unsetenv("OPENBLAS_CORETYPE");
  }
  // Without it, the recommendation is the pure rule applied to this machine.
  if (!saved) {
    EXPECT_EQ(fricrom::RecommendedBlasCore(),
              fricrom::BlasCoreOverride(fricrom::BlasCoreName(), fricrom::CpuHasAvx2Fma()));
  }
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
