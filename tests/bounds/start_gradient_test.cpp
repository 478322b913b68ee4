// A reduced-space run started from its seed's KKT-check gradient (bounds/bound_runs.h).
#include <gtest/gtest.h>

#include "lumped_run_start.h"

namespace fricrom::bounds_detail {
namespace {

// On the lumped benchmark the KKT check and a run's own first gradient factorise the same
// Jacobian in double precision, so a run given the check's gradient (times its sign) is the run
// that computes its own, bit for bit, in both directions. Given the gradient without the run's
// sign, the minimum run would start uphill and end elsewhere: the test sees the sign.
TEST(StartGradient, RunsFromTheKktChecksGradientEqualRunsFromTheirOwn) {
  const testing_runs::LumpedRunStart lumped = testing_runs::LumpedRunAt269Hz();
  const FrfPoint& p = lumped.start;
  const Eigen::Vector4d& a0 = lumped.a0;
  ASSERT_EQ(p.status, SolverStatus::kConverged) << p.message;
  RunSetup s = lumped.setup;
  StartGradient start;
  const std::array<bool, 2> kkt = StartIsKktPoint(s, p.x, a0, 1e-9, {1.0, -1.0}, &start);
  ASSERT_FALSE(kkt[0] || kkt[1]);
  ASSERT_TRUE(start.lu != nullptr);
  for (double sign : {1.0, -1.0}) {
    s.sign = sign;
    const BoundSolution own = RunReduced(s, p.x, a0, 0, 200, 1e-7);
    const BoundSolution given = RunReduced(s, p.x, a0, 0, 200, 1e-7, &start);
    ASSERT_TRUE(own.IsUsable()) << own.message;
    ASSERT_GT(own.iterations, 0);
    EXPECT_EQ(given.amplitude, own.amplitude) << "sign " << sign;
    EXPECT_EQ(given.alpha, own.alpha) << "sign " << sign;
    EXPECT_EQ(given.iterations, own.iterations) << "sign " << sign;
  }
  s.sign = 1.0;
  StartGradient unsigned_start = start;
  unsigned_start.g = -start.g;
  unsigned_start.lambda = -start.lambda;
  const BoundSolution own = RunReduced(s, p.x, a0, 0, 200, 1e-7);
  const BoundSolution wrong = RunReduced(s, p.x, a0, 0, 200, 1e-7, &unsigned_start);
  EXPECT_NE(wrong.amplitude, own.amplitude);
}

}  // namespace
}  // namespace fricrom::bounds_detail
