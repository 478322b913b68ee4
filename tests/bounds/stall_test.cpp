// The reduced-space run's stall test (BoundsOptions::stall_change, bounds/bound_runs.h).
#include <gtest/gtest.h>

#include <string>

#include "lumped_run_start.h"

namespace fricrom::bounds_detail {
namespace {

// A stalled run ends on its best iterate: the run without the test, cut at the same iteration
// (which also ends on its best), is the same point bit for bit; the stall test only decides
// where the nonmonotone path stops. The run left to its own tests goes at least as far.
TEST(StallTest, AStalledRunEndsOnTheBestIterateOfTheSamePath) {
  const testing_runs::LumpedRunStart lumped = testing_runs::LumpedRunAt269Hz();
  const FrfPoint& p = lumped.start;
  const Eigen::Vector4d& a0 = lumped.a0;
  ASSERT_EQ(p.status, SolverStatus::kConverged) << p.message;
  RunSetup s = lumped.setup;
  int stalled_runs = 0;
  for (double sign : {1.0, -1.0}) {
    s.sign = sign;
    s.stall_window = 0;
    const BoundSolution free = RunReduced(s, p.x, a0, 0, 200, 1e-7);
    ASSERT_TRUE(free.IsUsable()) << free.message;
    s.stall_window = 3;
    s.stall_change = 0.05;  // loose enough to stop these short runs
    const BoundSolution stalled = RunReduced(s, p.x, a0, 0, 200, 1e-7);
    ASSERT_TRUE(stalled.IsUsable()) << stalled.message;
    if (stalled.message.find("stalled") == std::string::npos) continue;
    ++stalled_runs;
    EXPECT_EQ(stalled.status, BoundStatus::kConverged);
    EXPECT_NE(stalled.message.find("<= 0.05 in 3 iterations"), std::string::npos)
        << stalled.message;
    EXPECT_LT(stalled.iterations, free.iterations);
    s.stall_window = 0;
    const BoundSolution cut = RunReduced(s, p.x, a0, 0, stalled.iterations, 1e-7);
    EXPECT_EQ(cut.status, BoundStatus::kMaxIterations) << cut.message;
    EXPECT_EQ(cut.amplitude, stalled.amplitude) << "sign " << sign;
    EXPECT_EQ(cut.alpha, stalled.alpha) << "sign " << sign;
    // Minimising (sign +1) the free run ends lower, maximising higher (or on the same point).
    EXPECT_LE(sign * free.amplitude, sign * stalled.amplitude * (1.0 + 1e-12)) << "sign " << sign;
  }
  EXPECT_GT(stalled_runs, 0) << "no run stalled: the test checks nothing";
}

}  // namespace
}  // namespace fricrom::bounds_detail
