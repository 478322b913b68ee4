// ImproveBounds: bound runs from solutions found by other routes, on the paper's lumped system.
#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "test_models.h"

namespace fricrom {
namespace {

constexpr double kFreq = 266.0;  // near the resonance: the response spreads over α

// A deliberately local result: one seed (α = 0), one optimiser iteration, no sample check.
BoundsOptions Weak() {
  BoundsOptions o;
  o.alpha_seeds = {Eigen::VectorXd::Zero(testing::BaselineH1().num_alpha())};
  o.max_iterations = 1;
  o.check_samples = 0;
  return o;
}

// The corner of the α box with the smallest response and its solution (independent of the
// bounds). At 266 Hz α = 0 is a KKT point of both directions (a plateau), a corner is lower.
KnownSolution SmallestCorner(double* amplitude) {
  const int n = testing::BaselineH1().num_alpha();
  KnownSolution best;
  *amplitude = 1e300;
  for (int m = 0; m < (1 << n); ++m) {
    Eigen::VectorXd a(n);
    for (int k = 0; k < n; ++k) a[k] = ((m >> k) & 1) ? 1.0 : -1.0;
    const FrfPoint p =
        SolveAtFrequency(testing::BaselineH1(), a, kFreq, Eigen::VectorXd(), FrfOptions{});
    if (p.status == SolverStatus::kConverged && p.amplitude < *amplitude) {
      *amplitude = p.amplitude;
      best = {p.x, a};
    }
  }
  return best;
}

TEST(ImproveBounds, ASolutionBelowALocalMinimumLowersIt) {
  BoundsResult r = ComputeBounds(testing::BaselineH1(), kFreq, Weak());
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  double corner = 0.0;
  const KnownSolution k = SmallestCorner(&corner);
  ASSERT_LT(corner, r.min.amplitude * 0.9) << "the weak minimum should be local here";
  const double max_before = r.max.amplitude;
  EXPECT_EQ(ImproveBounds(testing::BaselineH1(), kFreq, Weak(), {k}, &r), 1);
  ASSERT_TRUE(r.min.IsUsable());
  EXPECT_LE(r.min.amplitude, corner * (1 + 1e-12));
  EXPECT_EQ(r.max.amplitude, max_before);
  // The lowered bound is a harmonic-balance solution at its α, checked independently.
  HbmEvaluation e;
  testing::BaselineH1().Evaluate(r.min.x, 2 * std::numbers::pi * kFreq, r.min.alpha, HbmRequest{},
                                 &e);
  EXPECT_LE(e.residual.norm(), 1e-6 * testing::BaselineH1().ResidualScale());
  EXPECT_DOUBLE_EQ(r.min.amplitude, testing::BaselineH1().Amplitude(r.min.x));
  EXPECT_LE(r.min.alpha.cwiseAbs().maxCoeff(), 1.0);
  // It reaches the thorough computation's minimum (2.0376e-4 m, every seed and the sample check).
  const BoundsResult full = ComputeBounds(testing::BaselineH1(), kFreq, BoundsOptions{});
  ASSERT_TRUE(full.IsUsable());
  EXPECT_LE(r.min.amplitude, full.min.amplitude * (1 + 1e-6));
}

// A known solution that neither Newton nor the residual homotopy can use (its x is not a
// number): with cold_start its α is solved by the seeds' cold routes and the run from there
// lowers the weak minimum as above; without, it is dropped and nothing changes.
// A run from a known solution that stops at its iteration limit, with no run in its direction
// converging, still widens the bound held before with its feasible last iterate.
TEST(ImproveBounds, AnUnfinishedRunBeyondTheBoundWidensIt) {
  const std::vector<Eigen::VectorXd> seeds = DefaultAlphaSeeds(testing::BaselineH1().num_alpha());
  BoundsOptions o;
  o.max_iterations = 1;
  o.check_samples = 0;
  o.alpha_seeds = {seeds[3]};  // a KKT start in both directions
  BoundsResult r = ComputeBounds(testing::BaselineH1(), kFreq, o);
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  o.alpha_seeds = {seeds[1]};  // its runs need more than one iteration
  const BoundsResult alone = ComputeBounds(testing::BaselineH1(), kFreq, o);
  ASSERT_EQ(alone.max.status, BoundStatus::kMaxIterations) << alone.BriefReport();
  const double y_unfinished = testing::BaselineH1().Amplitude(alone.max.x);
  ASSERT_GT(y_unfinished, r.max.amplitude * (1 + 1e-3));
  const FrfPoint start =
      SolveAtFrequency(testing::BaselineH1(), seeds[1], kFreq, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(start.status, SolverStatus::kConverged);
  ASSERT_LT(start.amplitude, y_unfinished);  // the run moved: its start alone would not do
  KnownSolution k{start.x, seeds[1]};
  k.run_min = false;
  EXPECT_EQ(ImproveBounds(testing::BaselineH1(), kFreq, o, {k}, &r), 1);
  ASSERT_TRUE(r.max.IsUsable()) << r.max.message;
  EXPECT_DOUBLE_EQ(r.max.amplitude, y_unfinished);
  EXPECT_FALSE(r.max.stationary);
  EXPECT_TRUE(r.min.stationary);
}

TEST(ImproveBounds, AnUnusableKnownSolutionIsStartedColdOrDropped) {
  double corner = 0.0;
  KnownSolution k = SmallestCorner(&corner);
  k.x.setConstant(std::numeric_limits<double>::quiet_NaN());
  const BoundsResult weak = ComputeBounds(testing::BaselineH1(), kFreq, Weak());
  ASSERT_TRUE(weak.IsUsable()) << weak.BriefReport();
  BoundsResult cold = weak, dropped = weak;
  EXPECT_EQ(ImproveBounds(testing::BaselineH1(), kFreq, Weak(), {k}, &cold), 1);
  EXPECT_LE(cold.min.amplitude, corner * (1 + 1e-12));
  k.cold_start = false;
  EXPECT_EQ(ImproveBounds(testing::BaselineH1(), kFreq, Weak(), {k}, &dropped), 0);
  EXPECT_EQ(dropped.min.amplitude, weak.min.amplitude);
  EXPECT_EQ(dropped.max.amplitude, weak.max.amplitude);
  EXPECT_EQ(dropped.optimizer_runs, weak.optimizer_runs);
}

// An unusable known solution with start_short_of_alpha where plain Newton at its α fails and
// the α homotopy from 0 reaches it (both asserted: the α path, which comes before the
// continuations in frequency, is then the start's route): 267 Hz, next to the resonance, at
// an α where a search over 20 random α found plain Newton failing (7 of 20 there). The run from
// there gives a usable minimum, a harmonic-balance solution checked here, no higher than the
// known α's own response.
TEST(ImproveBounds, AStartOnTheAlphaPathGivesAUsableBound) {
  const HbmSystem& sys = testing::BaselineH1();
  const double f = 267.0, omega = 2 * std::numbers::pi * f;
  KnownSolution k;
  k.alpha = Eigen::Vector4d(-0.5, -0.92, -0.96, -0.13);
  FrfOptions plain;
  plain.use_fallbacks = false;
  ASSERT_NE(SolveAtFrequency(sys, k.alpha, f, Eigen::VectorXd(), plain).status,
            SolverStatus::kConverged)
      << "plain Newton solves this alpha: the alpha path is not reached";
  double lambda = 0.0;
  int evaluations = 0;
  Eigen::VectorXd x_path;
  FrfOptions path;
  path.fallback_max_points = 200;
  ASSERT_TRUE(ContinueTowardsAlpha(sys, k.alpha, omega, path, &lambda, &x_path, &evaluations));
  const FrfPoint at_alpha = SolveAtFrequency(sys, k.alpha, f, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(at_alpha.status, SolverStatus::kConverged);
  k.x = Eigen::VectorXd::Constant(sys.num_unknowns(), std::numeric_limits<double>::quiet_NaN());
  k.run_max = false;
  k.start_short_of_alpha = true;
  BoundsOptions o;
  o.check_samples = 0;
  BoundsResult r;
  r.freq_hz = f;
  EXPECT_EQ(ImproveBounds(sys, f, o, {k}, &r), 1);
  ASSERT_TRUE(r.min.IsUsable()) << r.min.message;
  EXPECT_FALSE(r.max.IsUsable());
  EXPECT_LE(r.min.amplitude, at_alpha.amplitude * (1 + 1e-9));
  HbmEvaluation e;
  sys.Evaluate(r.min.x, omega, r.min.alpha, HbmRequest{}, &e);
  EXPECT_LE(e.residual.norm(), 1e-6 * sys.ResidualScale());
  EXPECT_DOUBLE_EQ(r.min.amplitude, sys.Amplitude(r.min.x));
}

TEST(ImproveBounds, AStartInsideTheBoundsChangesNothing) {
  BoundsResult r = ComputeBounds(testing::BaselineH1(), kFreq, BoundsOptions{});
  ASSERT_TRUE(r.IsUsable());
  const BoundsResult before = r;
  // The bounds' own optimum as a known solution: nothing to gain.
  EXPECT_EQ(
      ImproveBounds(testing::BaselineH1(), kFreq, BoundsOptions{}, {{r.max.x, r.max.alpha}}, &r),
      0);
  EXPECT_EQ(r.max.amplitude, before.max.amplitude);
  EXPECT_EQ(r.min.amplitude, before.min.amplitude);
  EXPECT_EQ(r.max.alpha, before.max.alpha);
  EXPECT_EQ(ImproveBounds(testing::BaselineH1(), kFreq, BoundsOptions{}, {}, &r), 0);
}

TEST(ImproveBounds, RejectsMismatchedInput) {
  BoundsResult r = ComputeBounds(testing::BaselineH1(), kFreq, Weak());
  const int n = testing::BaselineH1().num_unknowns(), na = testing::BaselineH1().num_alpha();
  const KnownSolution short_x{Eigen::VectorXd::Zero(n - 1), Eigen::VectorXd::Zero(na)};
  EXPECT_THROW(ImproveBounds(testing::BaselineH1(), kFreq, Weak(), {short_x}, &r),
               std::invalid_argument);
  const KnownSolution ok{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(na)};
  EXPECT_THROW(ImproveBounds(testing::BaselineH1(), kFreq + 1.0, Weak(), {ok}, &r),
               std::invalid_argument);
  EXPECT_THROW(ImproveBounds(testing::BaselineH1(), kFreq, Weak(), {ok}, nullptr),
               std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
