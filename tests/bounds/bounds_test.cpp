#include "fricrom/bounds.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

std::string Regimes(const std::vector<ContactRegime>& regimes) {
  std::string s;
  for (ContactRegime r : regimes) s += (s.empty() ? "" : ", ") + ToString(r);
  return s;
}

// Independent check of a bound: R = 0, α inside the box, amplitude consistent with x.
void ExpectAdmissible(const HbmSystem& sys, double freq_hz, const BoundSolution& s) {
  ASSERT_EQ(s.x.size(), sys.num_unknowns());
  ASSERT_EQ(s.alpha.size(), sys.num_contacts());
  EXPECT_LE(s.alpha.cwiseAbs().maxCoeff(), 1.0);
  HbmEvaluation e;
  sys.Evaluate(s.x, kTwoPi * freq_hz, s.alpha, HbmRequest{}, &e);
  EXPECT_LE(e.residual.norm(), 1e-6 * sys.ResidualScale());
  EXPECT_DOUBLE_EQ(s.amplitude, sys.Amplitude(s.x));
  EXPECT_EQ(s.regimes.size(), static_cast<size_t>(sys.num_contacts()));
}

class BaselineBounds : public ::testing::TestWithParam<double> {};

// (a) Both bounds converge, are admissible and ordered.
TEST_P(BaselineBounds, BothBoundsConvergeAndAreOrdered) {
  const double f = GetParam();
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), f, BoundsOptions{});
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_EQ(r.min.status, BoundStatus::kConverged);
  EXPECT_EQ(r.max.status, BoundStatus::kConverged);
  EXPECT_LE(r.min.amplitude, r.max.amplitude);
  EXPECT_DOUBLE_EQ(r.freq_hz, f);
  EXPECT_EQ(r.seeds_tried, 5);
  EXPECT_GE(r.seeds_converged, 1);
  EXPECT_GE(r.spread_min, 0.0);
  EXPECT_GE(r.spread_max, 0.0);
  ExpectAdmissible(testing::BaselineH1(), f, r.min);
  ExpectAdmissible(testing::BaselineH1(), f, r.max);
  EXPECT_GE(r.robustness(), 0.0);
  EXPECT_LE(r.robustness(), 1.0);
  std::printf("[bounds] %.0f Hz: y_min %.6e m [%s], y_max %.6e m [%s], R %.4f\n", f,
              r.min.amplitude, Regimes(r.min.regimes).c_str(), r.max.amplitude,
              Regimes(r.max.regimes).c_str(), r.robustness());
}

// (b) Sampling certificate: every converged harmonic-balance solution at a sampled α (the 16
// corners of the box and seeded random points) lies within the computed bounds.
TEST_P(BaselineBounds, SampledResponsesLieWithinTheBounds) {
  const double f = GetParam();
  const HbmSystem& sys = testing::BaselineH1();
  const BoundsResult r = ComputeBounds(sys, f, BoundsOptions{});
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();

  std::vector<Eigen::VectorXd> samples;
  for (int m = 0; m < 16; ++m) {
    Eigen::VectorXd a(4);
    for (int c = 0; c < 4; ++c) a[c] = ((m >> c) & 1) ? 1.0 : -1.0;
    samples.push_back(a);
  }
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 0; k < 14; ++k) {
    Eigen::VectorXd a(4);
    for (int c = 0; c < 4; ++c) a[c] = uniform(rng);
    samples.push_back(a);
  }
  int failed = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const Eigen::VectorXd& a : samples) {
    const FrfPoint p = SolveAtFrequencies(sys, a, {f}, FrfOptions{}).back();
    if (p.status != SolverStatus::kConverged) {
      ++failed;
      continue;
    }
    lo = std::min(lo, p.amplitude);
    hi = std::max(hi, p.amplitude);
    EXPECT_GE(p.amplitude, r.min.amplitude * (1 - 1e-6)) << "alpha " << a.transpose();
    EXPECT_LE(p.amplitude, r.max.amplitude * (1 + 1e-6)) << "alpha " << a.transpose();
  }
  const int n = static_cast<int>(samples.size());
  EXPECT_LT(failed, 0.2 * n) << failed << " of " << n << " sampled solves failed";
  RecordProperty("sampled_solves", n);
  RecordProperty("sampled_failures", failed);
  std::printf(
      "[bounds] %.0f Hz certificate: %d samples, %d failed, sampled range [%.6e, %.6e], "
      "bounds [%.6e, %.6e]\n",
      f, n, failed, lo, hi, r.min.amplitude, r.max.amplitude);
}

INSTANTIATE_TEST_SUITE_P(Frequencies, BaselineBounds, ::testing::Values(262.0, 266.0),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return std::to_string(static_cast<int>(info.param)) + "Hz";
                         });

// (c) Near resonance the baseline has a response scatter (paper Fig. 9): the inner contacts 2, 3
// stick over the whole period while the outer contacts 1, 4 alternate stick and slip.
TEST(Bounds, BaselineHasAScatterNearResonance) {
  const double f = 266.0;
  const auto t0 = std::chrono::steady_clock::now();
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), f, BoundsOptions{});
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_GT(r.max.amplitude - r.min.amplitude, 0.01 * r.max.amplitude) << r.BriefReport();
  EXPECT_LT(r.robustness(), 0.99);
  // The minimum response dissipates more: larger loss factor (paper Table 1).
  EXPECT_GT(r.min.loss_factor, r.max.loss_factor);
  const std::vector<ContactRegime> hybrid = {ContactRegime::kStickSlip, ContactRegime::kFullStick,
                                             ContactRegime::kFullStick, ContactRegime::kStickSlip};
  EXPECT_TRUE(r.min.regimes == hybrid || r.max.regimes == hybrid)
      << "min: " << Regimes(r.min.regimes) << "; max: " << Regimes(r.max.regimes);
  RecordProperty("compute_bounds_ms", std::to_string(ms));
  std::printf("[bounds] %s\n[bounds] ComputeBounds took %.2f ms\n", r.BriefReport().c_str(), ms);
}

TEST(Bounds, ProgressCountsSeedsAndSamplesUpToTheirTotals) {
  BoundsOptions o;
  std::vector<std::pair<int, int>> seeds, samples;
  o.progress = [&](const std::string& stage, int done, int total) {
    (stage == "seeds" ? seeds : samples).emplace_back(done, total);
  };
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), 266.0, o);
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  ASSERT_FALSE(seeds.empty());
  EXPECT_EQ(seeds.front(), std::make_pair(1, 5));  // after the first of the 5 default seeds
  EXPECT_EQ(seeds[4], std::make_pair(5, 5));
  ASSERT_EQ(static_cast<int>(samples.size()), o.check_samples);
  for (int i = 0; i < o.check_samples; ++i) {
    EXPECT_EQ(samples[i], std::make_pair(i + 1, o.check_samples));
  }
}

// At 262 Hz every contact sticks over the whole period (type b1): α moves the static state only
// and the dynamic response is unique.
TEST(Bounds, FullStickResponseIsUniqueBelowResonance) {
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), 262.0, BoundsOptions{});
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_NEAR(r.min.amplitude, r.max.amplitude, 1e-6 * r.max.amplitude);
  for (ContactRegime g : r.max.regimes) EXPECT_EQ(g, ContactRegime::kFullStick);
}

// (d) With μ = 1e9 every contact sticks at α = 0 and the dynamic response does not depend on the
// static state as long as they all keep sticking. Note that α scales T(0) = α μ N(0): away from
// α ≈ 0 the tangential preloads are astronomically large, the harmonic-balance starts of the
// other default seeds do not converge (counted as start failures), and tiny seeds (|α| ~ 1e-8)
// already reach static states with lift-off and a different response. The bounds over the
// converged seeds coincide.
TEST(Bounds, EverythingSticksWithHugeFriction) {
  const Case cs = testing::LoadBaseline({{"mu", 1e9}});
  const HbmSystem sys(cs.model, HbmOptions{1, 128});
  const BoundsResult r = ComputeBounds(sys, 266.0, BoundsOptions{});
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_GE(r.seeds_converged, 1);
  EXPECT_NEAR(r.min.amplitude, r.max.amplitude, 1e-6 * r.max.amplitude) << r.BriefReport();
  EXPECT_NEAR(r.robustness(), 1.0, 1e-6);
  for (ContactRegime g : r.min.regimes) EXPECT_EQ(g, ContactRegime::kFullStick);
  for (ContactRegime g : r.max.regimes) EXPECT_EQ(g, ContactRegime::kFullStick);
  // The full-stick linear solution is then the exact first harmonic.
  const Eigen::VectorXd lin = sys.StickLinearSolution(kTwoPi * 266.0);
  EXPECT_NEAR(r.max.amplitude, sys.Amplitude(lin), 1e-6 * r.max.amplitude);
  std::printf("[bounds] mu = 1e9: y %.6e m, %d of %d seed starts failed\n", r.max.amplitude,
              r.start_failures, r.seeds_tried);
}

// From a start on a slope of the response over α the optimiser must actually move: down for the
// minimum, up for the maximum.
TEST(Bounds, OptimiserImprovesOnASlopedStart) {
  const double f = 266.0;
  const Eigen::VectorXd seed = Eigen::VectorXd::Constant(4, 0.5);
  const FrfPoint start = SolveAtFrequencies(testing::BaselineH1(), seed, {f}, FrfOptions{}).back();
  ASSERT_EQ(start.status, SolverStatus::kConverged);
  BoundsOptions opt;
  opt.alpha_seeds = {seed};
  opt.check_samples = 0;  // the optimiser alone
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), f, opt);
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_EQ(r.optimizer_runs, 2);
  EXPECT_LT(r.min.amplitude, start.amplitude * (1 - 1e-3)) << r.BriefReport();
  EXPECT_GT(r.max.amplitude, start.amplitude * (1 + 1e-3)) << r.BriefReport();
  EXPECT_GT(r.min.iterations, 0);
  ExpectAdmissible(testing::BaselineH1(), f, r.min);
  ExpectAdmissible(testing::BaselineH1(), f, r.max);
}

// The paper's objective (Table 1): extreme loss factors give the same response bounds here.
TEST(Bounds, LossFactorObjectiveFindsTheSameBounds) {
  BoundsOptions opt;
  const BoundsResult amp = ComputeBounds(testing::BaselineH1(), 266.0, opt);
  opt.objective = BoundsOptions::kLossFactor;
  const BoundsResult eta = ComputeBounds(testing::BaselineH1(), 266.0, opt);
  ASSERT_TRUE(amp.IsUsable()) << amp.BriefReport();
  ASSERT_TRUE(eta.IsUsable()) << eta.BriefReport();
  EXPECT_NEAR(eta.min.amplitude, amp.min.amplitude, 1e-6 * amp.max.amplitude);
  EXPECT_NEAR(eta.max.amplitude, amp.max.amplitude, 1e-6 * amp.max.amplitude);
  EXPECT_GE(eta.min.loss_factor, eta.max.loss_factor);
}

// A run that fails is counted and never chosen as a bound.
TEST(Bounds, FailedRunsAreCountedNotUsed) {
  BoundsOptions opt;
  opt.max_iterations = 1;  // nothing that needs the optimiser can converge
  opt.alpha_seeds = {Eigen::VectorXd::Constant(4, 0.5)};
  const BoundsResult r = ComputeBounds(testing::BaselineH1(), 266.0, opt);
  EXPECT_EQ(r.min_failures + r.max_failures, 2);
  EXPECT_EQ(r.seeds_converged, 0);
  EXPECT_FALSE(r.IsUsable());
  EXPECT_EQ(r.min.status, BoundStatus::kMaxIterations);
  EXPECT_TRUE(std::isnan(r.robustness()));
}

// A run stopped at its iteration limit ends on a feasible point; where that point lies beyond
// every converged run it becomes the bound, marked not stationary (the FE cascade's curve lost
// 5-6 % of y_max at two frequencies to such runs). Alone it is no bound.
TEST(Bounds, UnfinishedRunsWidenAConvergedBound) {
  const double f = 266.0;
  const HbmSystem& sys = testing::BaselineH1();
  const std::vector<Eigen::VectorXd> seeds = DefaultAlphaSeeds(4);
  const Eigen::VectorXd& kkt_start = seeds[3];   // both runs start at a KKT point: converged
  const Eigen::VectorXd& needs_runs = seeds[1];  // needs more than one iteration
  BoundsOptions o;
  o.max_iterations = 1;
  o.check_samples = 0;
  o.alpha_seeds = {needs_runs};
  const BoundsResult unfinished = ComputeBounds(sys, f, o);
  ASSERT_EQ(unfinished.max.status, BoundStatus::kMaxIterations) << unfinished.BriefReport();
  EXPECT_FALSE(unfinished.IsUsable());
  const double y_unfinished = sys.Amplitude(unfinished.max.x);
  o.alpha_seeds = {kkt_start};
  const BoundsResult converged = ComputeBounds(sys, f, o);
  ASSERT_TRUE(converged.IsUsable()) << converged.BriefReport();
  EXPECT_TRUE(converged.max.stationary);
  ASSERT_GT(y_unfinished, converged.max.amplitude * (1 + 1e-3));
  for (const auto& order : {std::vector<Eigen::VectorXd>{kkt_start, needs_runs},
                            std::vector<Eigen::VectorXd>{needs_runs, kkt_start}}) {
    o.alpha_seeds = order;
    const BoundsResult both = ComputeBounds(sys, f, o);
    ASSERT_TRUE(both.IsUsable()) << both.BriefReport();
    EXPECT_DOUBLE_EQ(both.max.amplitude, y_unfinished) << both.BriefReport();
    EXPECT_FALSE(both.max.stationary);
    EXPECT_NE(both.max.message.find("beyond every converged run"), std::string::npos);
    EXPECT_GE(both.max_failures, 1);  // still counted as a run that did not converge
    EXPECT_NEAR(both.spread_max, y_unfinished - converged.max.amplitude, 1e-12 * y_unfinished);
    ExpectAdmissible(sys, f, both.max);
    // The unfinished minimum lies above the converged one: the minimum stays stationary.
    EXPECT_DOUBLE_EQ(both.min.amplitude, converged.min.amplitude);
    EXPECT_TRUE(both.min.stationary);
  }
}

// The nonmonotone line search (BoundsOptions::line_search_memory) only changes how a run gets to
// its optimum: on the paper's benchmark, where the default seeds reach the bounds either way, both
// searches give the same bounds, each a stationary point.
TEST(Bounds, NonmonotoneAndMonotoneSearchesAgreeOnTheLumpedBenchmark) {
  for (double f : {262.0, 266.0, 270.0}) {
    BoundsOptions monotone, nonmonotone;
    monotone.line_search_memory = 1;
    nonmonotone.line_search_memory = 10;
    const BoundsResult a = ComputeBounds(testing::BaselineH1(), f, monotone);
    const BoundsResult b = ComputeBounds(testing::BaselineH1(), f, nonmonotone);
    ASSERT_TRUE(a.IsUsable() && b.IsUsable()) << a.BriefReport() << b.BriefReport();
    EXPECT_NEAR(b.min.amplitude, a.min.amplitude, 1e-6 * a.max.amplitude) << f;
    EXPECT_NEAR(b.max.amplitude, a.max.amplitude, 1e-6 * a.max.amplitude) << f;
    EXPECT_TRUE(b.min.stationary && b.max.stationary) << b.BriefReport();
  }
}

// A nonmonotone run may pass through worse iterates, but it ends on its best one: with a longer
// iteration budget (the same path, further) a run's maximum never falls. At 269 Hz the run from
// ½·1 has iterates below earlier ones (by ~3e-6: this test fails if a run ends on its last).
TEST(Bounds, NonmonotoneRunsEndOnTheirBestIterate) {
  BoundsOptions o;
  o.alpha_seeds = {DefaultAlphaSeeds(4)[1]};
  o.check_samples = 0;
  o.stop_dominated_runs = false;
  o.line_search_memory = 10;
  double previous = 0.0;
  for (int iterations = 1; iterations <= 40; ++iterations) {
    o.max_iterations = iterations;
    const BoundsResult r = ComputeBounds(testing::BaselineH1(), 269.0, o);
    const double y = testing::BaselineH1().Amplitude(r.max.x);
    ASSERT_TRUE(std::isfinite(y)) << iterations;
    EXPECT_GE(y, previous * (1 - 1e-12)) << iterations << " iterations";
    previous = y;
  }
}

// BoundsOptions::minimum_stop_m ends a minimising run once the response is at or below it. At
// 268 Hz the minimum run from this seed takes two iterations; with the stop above every response
// it ends after its first: a feasible, non-stationary point above the full run's minimum (a
// stopped run is a prefix of its full run). The maximum run is untouched.
TEST(Bounds, MinimumStopEndsMinimisingRunsAtTheStop) {
  BoundsOptions o;
  o.check_samples = 0;
  o.alpha_seeds = {Eigen::Vector4d(-0.7, 0.2, 0.6, -0.1)};
  const BoundsResult full = ComputeBounds(testing::BaselineH1(), 268.0, o);
  ASSERT_TRUE(full.IsUsable()) << full.BriefReport();
  ASSERT_TRUE(full.min.stationary);
  ASSERT_EQ(full.min.iterations, 2) << full.min.message;
  o.minimum_stop_m = 10.0 * full.max.amplitude;
  const BoundsResult stopped = ComputeBounds(testing::BaselineH1(), 268.0, o);
  ASSERT_TRUE(stopped.IsUsable()) << stopped.BriefReport();
  ExpectAdmissible(testing::BaselineH1(), 268.0, stopped.min);
  EXPECT_EQ(stopped.min.iterations, 1);
  EXPECT_GT(stopped.min.amplitude, full.min.amplitude * (1 + 1e-9));
  EXPECT_FALSE(stopped.min.stationary);
  EXPECT_NE(stopped.min.message.find("negligible"), std::string::npos) << stopped.min.message;
  EXPECT_EQ(stopped.max.amplitude, full.max.amplitude);
  EXPECT_EQ(stopped.max.alpha, full.max.alpha);
}

// (e) Contract violations.
TEST(Bounds, OptionsValidation) {
  std::string err;
  EXPECT_TRUE(BoundsOptions{}.IsValid(&err)) << err;
  BoundsOptions o;
  o.max_iterations = 0;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("max_iterations"), std::string::npos);
  o = BoundsOptions{};
  o.tolerance = 0.0;
  EXPECT_FALSE(o.IsValid(&err));
  o.tolerance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("tolerance"), std::string::npos);
  o = BoundsOptions{};
  o.alpha_seeds = {Eigen::Vector4d::Zero(), Eigen::Vector3d::Zero()};
  EXPECT_FALSE(o.IsValid(&err));
  o.alpha_seeds = {Eigen::Vector4d(0.0, 1.5, 0.0, 0.0)};
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("[-1, 1]"), std::string::npos);
  o.alpha_seeds = {Eigen::Vector4d(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)};
  EXPECT_FALSE(o.IsValid(&err));
  o = BoundsOptions{};
  o.objective = static_cast<BoundsOptions::Objective>(7);  // fixed underlying type: well-defined
  EXPECT_FALSE(o.IsValid(&err));
  o = BoundsOptions{};
  o.method = static_cast<BoundsOptions::Method>(9);
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("method"), std::string::npos);
  for (double bad : {-0.1, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    o = BoundsOptions{};
    o.stall_change = bad;
    EXPECT_FALSE(o.IsValid(&err)) << bad;
    EXPECT_NE(err.find("stall_change"), std::string::npos) << err;
  }
  o = BoundsOptions{};
  o.stall_window = -1;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("stall_window"), std::string::npos) << err;
  o = BoundsOptions{};
  o.stall_change = 0.0;
  o.stall_window = 0;
  EXPECT_TRUE(o.IsValid(&err)) << err;
  o = BoundsOptions{};
  o.check_samples = -1;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("check_samples"), std::string::npos);

  o = BoundsOptions{};
  for (int memory : {0, -1, 101}) {
    o.line_search_memory = memory;
    EXPECT_FALSE(o.IsValid(&err)) << memory;
    EXPECT_NE(err.find("line_search_memory"), std::string::npos);
  }

  o = BoundsOptions{};
  for (double ratio : {-0.1, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    o.negligible_minimum = ratio;
    EXPECT_FALSE(o.IsValid(&err)) << ratio;
    EXPECT_NE(err.find("negligible_minimum"), std::string::npos);
  }
  o = BoundsOptions{};
  for (double stop : {-1e-6, std::numeric_limits<double>::infinity()}) {
    o.minimum_stop_m = stop;
    EXPECT_FALSE(o.IsValid(&err)) << stop;
    EXPECT_NE(err.find("minimum_stop_m"), std::string::npos);
  }

  o = BoundsOptions{};
  o.max_iterations = -3;
  EXPECT_THROW(ComputeBounds(testing::BaselineH1(), 266.0, o), std::invalid_argument);
  EXPECT_THROW(ComputeBounds(testing::BaselineH1(), 0.0, BoundsOptions{}), std::invalid_argument);
  EXPECT_THROW(ComputeBounds(testing::BaselineH1(), -5.0, BoundsOptions{}), std::invalid_argument);
  EXPECT_THROW(ComputeBounds(testing::BaselineH1(), std::numeric_limits<double>::quiet_NaN(),
                             BoundsOptions{}),
               std::invalid_argument);
  o = BoundsOptions{};
  o.alpha_seeds = {Eigen::Vector3d::Zero()};  // the baseline has 4 contacts
  EXPECT_THROW(ComputeBounds(testing::BaselineH1(), 266.0, o), std::invalid_argument);
}

// Seeds grow with the interfaces and the requested random count, never as 2^nα.
TEST(Bounds, SeedGroupsAndRandomSeedsAreAddedAndCounted) {
  BoundsOptions o;
  o.seed_groups = {0, 0, 1, 1, 2, 2};  // three interfaces of two α each
  o.random_seeds = 7;
  SeedCounts counts;
  const auto seeds = AlphaSeeds(6, o, &counts);
  EXPECT_EQ(counts.base, 5);
  EXPECT_EQ(counts.group_patterns, 6);
  EXPECT_EQ(counts.random, 7);
  ASSERT_EQ(seeds.size(), 18u);
  Eigen::VectorXd first_on(6), last_off(6);
  first_on << 1, 1, -1, -1, -1, -1;
  last_off << 1, 1, 1, 1, -1, -1;
  EXPECT_EQ(seeds[5], first_on);
  EXPECT_EQ(seeds[10], last_off);
  for (size_t i = 11; i < seeds.size(); ++i) {
    EXPECT_LE(seeds[i].cwiseAbs().maxCoeff(), 1.0);
    EXPECT_GT(seeds[i].cwiseAbs().minCoeff(), 0.0);  // random, not a pattern
  }
  // Reproducible, and independent of the check samples' stream.
  EXPECT_EQ(AlphaSeeds(6, o).back(), seeds.back());
  // A pattern equal to a base seed counts once: two groups of one α give ±(1, −1) = the
  // alternating corners of the default set.
  o = BoundsOptions{};
  o.seed_groups = {0, 1};
  EXPECT_EQ(AlphaSeeds(2, o, &counts).size(), 5u);
  EXPECT_EQ(counts.group_patterns, 0);
  o.seed_groups = {0, 1, 2};
  EXPECT_THROW(AlphaSeeds(2, o), std::invalid_argument);
  o.seed_groups = {0, -1};
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("seed_groups"), std::string::npos);
  o = BoundsOptions{};
  o.random_seeds = -1;
  EXPECT_FALSE(o.IsValid(&error));
}

// The extra seeds reach the optimisation: the result counts them, and the bounds do not get
// worse (more seeds, each a local optimisation; the best is kept).
TEST(Bounds, ExtraSeedsAreTriedAndReported) {
  BoundsOptions o;
  o.check_samples = 0;
  const BoundsResult plain = ComputeBounds(testing::BaselineH1(), 266.0, o);
  o.seed_groups = {0, 1, 2, 3};
  o.random_seeds = 3;
  const BoundsResult more = ComputeBounds(testing::BaselineH1(), 266.0, o);
  EXPECT_EQ(more.seed_counts.base, 5);
  EXPECT_EQ(more.seed_counts.group_patterns, 8);
  EXPECT_EQ(more.seed_counts.random, 3);
  EXPECT_EQ(more.seeds_tried, 16);
  ASSERT_TRUE(plain.IsUsable() && more.IsUsable());
  EXPECT_LE(more.min.amplitude, plain.min.amplitude * (1 + 1e-9));
  EXPECT_GE(more.max.amplitude, plain.max.amplitude * (1 - 1e-9));
}

TEST(Bounds, DefaultSeedsAndStatusNames) {
  const auto four = DefaultAlphaSeeds(4);
  ASSERT_EQ(four.size(), 5u);
  EXPECT_TRUE(four[0].isZero());
  EXPECT_EQ(four[3], Eigen::Vector4d(1, -1, 1, -1));
  EXPECT_EQ(four[4], Eigen::Vector4d(-1, 1, -1, 1));
  EXPECT_EQ(DefaultAlphaSeeds(1).size(), 5u);  // 0, ±0.5, ±1
  EXPECT_EQ(DefaultAlphaSeeds(0).size(), 1u);
  EXPECT_THROW(DefaultAlphaSeeds(-1), std::invalid_argument);
  EXPECT_EQ(ToString(BoundStatus::kConverged), "converged");
  EXPECT_EQ(ToString(BoundStatus::kMaxIterations), "max-iterations");
  EXPECT_EQ(ToString(BoundStatus::kInfeasible), "infeasible");
  EXPECT_EQ(ToString(BoundStatus::kFailed), "failed");
  for (auto m : {BoundsOptions::kFullSpace, BoundsOptions::kReducedSpace, BoundsOptions::kBoth}) {
    BoundsOptions::Method back = BoundsOptions::kBoth;
    ASSERT_TRUE(FromString(ToString(m), &back));
    EXPECT_EQ(back, m);
  }
  BoundsOptions::Method unused;
  EXPECT_FALSE(FromString("newton", &unused));
}

// Two independent optimisers, full-space Ipopt and the reduced-space projected gradient, find the
// same bounds (they share only the seeds and the harmonic-balance residual).
TEST(Bounds, FullSpaceAndReducedSpaceAgree) {
  for (const auto& [param, value] : std::vector<std::pair<std::string, double>>{
           {"gamma", 0.0}, {"gamma", 0.3}, {"beta", 0.05}, {"beta", 0.175}}) {
    const Case cs = testing::LoadBaseline({{param, value}});
    HbmSystem sys(cs.model, HbmOptions{1, 128});
    BoundsOptions full, reduced;
    full.method = BoundsOptions::kFullSpace;
    reduced.method = BoundsOptions::kReducedSpace;
    const BoundsResult a = ComputeBounds(sys, 266.1, full);
    const BoundsResult b = ComputeBounds(sys, 266.1, reduced);
    ASSERT_TRUE(a.IsUsable()) << param << "=" << value << "\n" << a.BriefReport();
    ASSERT_TRUE(b.IsUsable()) << param << "=" << value << "\n" << b.BriefReport();
    EXPECT_NEAR(a.min.amplitude, b.min.amplitude, 1e-6 * a.max.amplitude) << param << "=" << value;
    EXPECT_NEAR(a.max.amplitude, b.max.amplitude, 1e-6 * a.max.amplitude) << param << "=" << value;
  }
}

// Issue 9, defect 10: at gamma = 0.5, 272 Hz full-space Ipopt stops at a local minimum
// (1.0677e-4 m) that fixed-alpha solves on a 5^4 grid beat. A bound that a sample beats is not a
// bound: the default (reduced space + sample check) must enclose every grid sample, and the
// sample check must improve Ipopt's bound.
TEST(Bounds, DefaultBoundsEncloseAnAlphaGrid) {
  const Case cs = testing::LoadBaseline({{"gamma", 0.5}});
  HbmSystem sys(cs.model, HbmOptions{1, 128});
  const double f = 272.0;
  const BoundsResult b = ComputeBounds(sys, f, BoundsOptions{});
  ASSERT_TRUE(b.IsUsable()) << b.BriefReport();
  ExpectAdmissible(sys, f, b.min);
  ExpectAdmissible(sys, f, b.max);
  const std::vector<double> levels = {-1.0, -0.5, 0.0, 0.5, 1.0};
  double grid_min = INFINITY, grid_max = 0.0;
  int solved = 0;
  Eigen::VectorXd warm = b.min.x;
  for (int i = 0; i < 625; ++i) {
    Eigen::Vector4d a(levels[i % 5], levels[i / 5 % 5], levels[i / 25 % 5], levels[i / 125]);
    const FrfPoint p = SolveAtFrequency(sys, a, f, warm, FrfOptions{});
    if (p.status != SolverStatus::kConverged) continue;
    ++solved;
    grid_min = std::min(grid_min, p.amplitude);
    grid_max = std::max(grid_max, p.amplitude);
  }
  EXPECT_EQ(solved, 625);
  EXPECT_LE(b.min.amplitude, grid_min * (1 + 1e-9));
  EXPECT_GE(b.max.amplitude, grid_max * (1 - 1e-9));
  std::printf("[bounds] gamma 0.5, 272 Hz: bounds [%.6e, %.6e], 5^4 grid [%.6e, %.6e]\n",
              b.min.amplitude, b.max.amplitude, grid_min, grid_max);

  BoundsOptions ipopt;
  ipopt.method = BoundsOptions::kFullSpace;
  ipopt.check_samples = 0;
  const BoundsResult unchecked = ComputeBounds(sys, f, ipopt);
  ipopt.check_samples = 16;
  const BoundsResult checked = ComputeBounds(sys, f, ipopt);
  ASSERT_TRUE(unchecked.IsUsable() && checked.IsUsable());
  EXPECT_EQ(unchecked.samples_checked, 0);
  EXPECT_EQ(checked.samples_checked, 16);
  EXPECT_GE(checked.improved_by_samples, 1) << checked.BriefReport();
  EXPECT_LT(checked.min.amplitude, unchecked.min.amplitude);
}

// Defect 8: a bound that did not converge carries NaN, never a number; R is NaN too.
TEST(Bounds, FailedBoundsAreNaN) {
  BoundsResult r;
  EXPECT_TRUE(std::isnan(r.min.amplitude));
  EXPECT_TRUE(std::isnan(r.max.loss_factor));
  EXPECT_TRUE(std::isnan(r.robustness()));
  BoundsOptions o;
  o.max_iterations = 1;
  o.method = BoundsOptions::kFullSpace;
  o.alpha_seeds = {Eigen::VectorXd::Constant(4, 0.5)};  // not a KKT point: needs iterations
  const BoundsResult f = ComputeBounds(testing::BaselineH1(), 266.0, o);
  ASSERT_FALSE(f.IsUsable()) << f.BriefReport();
  for (const BoundSolution* s : {&f.min, &f.max}) {
    if (s->IsUsable()) continue;
    EXPECT_TRUE(std::isnan(s->amplitude)) << f.BriefReport();
    EXPECT_TRUE(std::isnan(s->loss_factor)) << f.BriefReport();
  }
}

}  // namespace
}  // namespace fricrom
