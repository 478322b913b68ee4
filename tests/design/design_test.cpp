#include "fricrom/design.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fricrom/balance.h"
#include "fricrom/hbm_system.h"
#include "test_models.h"

namespace fricrom {
namespace {

BalanceFactory Factory(const std::string& param) {
  return [param](double p) {
    return MakeBalance(testing::LoadBaseline({{param, p}}).model, HbmOptions{1, 128},
                       BalanceKind::kFull);
  };
}

SweepOptions Inner() {
  SweepOptions so;
  so.reference_freq_hz = 266.0;  // near the full-stick resonance, as the paper's ω_ref
  return so;
}

// Paper §4.2.1: R(γ) grows monotonically to R = 1 at γ = 0.43.
TEST(Design, RobustnessGrowsWithThePreloadAsymmetry) {
  const std::vector<double> gammas = {0.0, 0.15, 0.3, 0.43};
  const auto pts = SweepRobustness(Factory("gamma"), gammas, Inner());
  ASSERT_EQ(pts.size(), gammas.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    ASSERT_TRUE(pts[i].bounds.IsUsable()) << gammas[i];
    if (i > 0) {
      EXPECT_GT(pts[i].robustness, pts[i - 1].robustness) << gammas[i];
    }
  }
  EXPECT_LT(pts[0].robustness, 0.9);   // scatter at the baseline
  EXPECT_GT(pts[3].robustness, 0.99);  // nearly unique at γ = 0.43
  // Baseline: mixed configuration on both dampers (inner contacts stuck, outer stick-slip).
  const auto& r = pts[0].bounds.min.regimes;
  EXPECT_EQ(r[0], ContactRegime::kStickSlip);
  EXPECT_EQ(r[1], ContactRegime::kFullStick);
  EXPECT_EQ(r[2], ContactRegime::kFullStick);
  EXPECT_EQ(r[3], ContactRegime::kStickSlip);
}

// A sweep's value runs the bound search over the sweep's α levels: each point is that value's
// ComputeLevelBounds, with the levels' records; a level that does not fit the α count is refused.
TEST(Design, SweepSearchesOverItsAlphaLevels) {
  SweepOptions so = Inner();
  const int n = Factory("gamma")(0.15)->num_alpha();
  so.levels.levels = {
      AlphaLevel{"all", Eigen::MatrixXd::Ones(n, 1), {"all"}},
      AlphaLevel{"contact", Eigen::MatrixXd::Identity(n, n), std::vector<std::string>(n, "c")}};
  so.levels.max_corners = 2;
  const RobustnessPoint pt = SweepRobustness(Factory("gamma"), {0.15}, so).front();
  const BoundsResult direct =
      ComputeLevelBounds(*Factory("gamma")(0.15), 266.0, so.bounds, so.levels);
  ASSERT_TRUE(pt.bounds.IsUsable());
  ASSERT_EQ(pt.bounds.levels.size(), 2u);
  EXPECT_EQ(pt.bounds.min.amplitude, direct.min.amplitude);
  EXPECT_EQ(pt.bounds.max.amplitude, direct.max.amplitude);
  // The finest level contains the coarse one (one α for every contact).
  EXPECT_LE(pt.bounds.min.amplitude, pt.bounds.levels[0].min.amplitude * (1 + 1e-12));
  EXPECT_GE(pt.bounds.max.amplitude, pt.bounds.levels[0].max.amplitude * (1 - 1e-12));
  so.levels.levels[0].map = Eigen::MatrixXd::Ones(n + 1, 1);
  EXPECT_THROW(SweepRobustness(Factory("gamma"), {0.15}, so), std::invalid_argument);
}

// Paper §4.2.2: R(β) = 1 on a middle interval, lower on both sides; the NOA lands inside it.
TEST(Design, NoaFindsTheRobustIntervalOfTheAngleAsymmetry) {
  NoaOptions no;
  no.lower = 0.0;
  no.upper = 0.2;
  no.inner = Inner();
  const NoaResult res = RunNoa(Factory("beta"), no);
  ASSERT_TRUE(res.converged) << res.BriefReport();
  EXPECT_NEAR(res.robustness, 1.0, 1e-6) << res.BriefReport();
  EXPECT_GT(res.p_opt, 0.075);
  EXPECT_LT(res.p_opt, 0.15);
  EXPECT_NEAR(res.eta1, res.eta2, 1e-9);
  EXPECT_EQ(res.inner_solves, 2 * res.outer_iterations);
  // Outside the interval the response is not unique.
  double r_lo = 1, r_hi = 1;
  for (const RobustnessPoint& h : res.history) {
    if (h.parameter == 0.0) r_lo = h.robustness;
    if (h.parameter == 0.2) r_hi = h.robustness;
  }
  EXPECT_LT(r_lo, 0.9);
  EXPECT_LT(r_hi, 0.9);
}

// The paper's gradient NOA stopped at γ = 0.354 (R = 0.974); the scan + golden refinement goes to
// the end of the interval where R → 1.
TEST(Design, NoaBeatsThePaperOnThePreloadAsymmetry) {
  NoaOptions no;
  no.lower = 0.0;
  no.upper = 0.43;
  no.scan_points = 5;
  no.parameter_tolerance = 0.01;
  no.objective = NoaOptions::kOneMinusR;
  no.inner = Inner();
  const NoaResult res = RunNoa(Factory("gamma"), no);
  ASSERT_TRUE(res.converged) << res.BriefReport();
  EXPECT_GE(res.robustness, 0.974) << res.BriefReport();
  EXPECT_GT(res.p_opt, 0.354);
}

// The scan is independent units: on two threads, or through a caller's evaluator that computes
// the values in reverse order, the NOA takes the same path to the same optimum.
TEST(Design, NoaScanIsTheSameOnThreadsAndThroughAnEvaluator) {
  NoaOptions no;
  no.lower = 0.0;
  no.upper = 0.2;
  no.scan_points = 5;
  no.parameter_tolerance = 0.01;
  no.inner = Inner();
  const NoaResult one = RunNoa(Factory("beta"), no);
  no.inner.threads = 2;
  const NoaResult two = RunNoa(Factory("beta"), no);
  no.inner.threads = 1;
  int calls = 0;
  no.scan_evaluator = [&](const std::vector<double>& values) {
    ++calls;
    std::vector<RobustnessPoint> pts(values.size());
    for (int i = static_cast<int>(values.size()) - 1; i >= 0; --i) {
      pts[i] = SweepRobustness(Factory("beta"), {values[i]}, Inner()).front();
    }
    return pts;
  };
  const NoaResult custom = RunNoa(Factory("beta"), no);
  EXPECT_EQ(calls, 1);
  for (const NoaResult* r : {&two, &custom}) {
    EXPECT_EQ(r->p_opt, one.p_opt);
    EXPECT_EQ(r->robustness, one.robustness);
    EXPECT_EQ(r->outer_iterations, one.outer_iterations);
    ASSERT_EQ(r->history.size(), one.history.size());
    for (size_t i = 0; i < one.history.size(); ++i) {
      EXPECT_EQ(r->history[i].parameter, one.history[i].parameter);
      EXPECT_EQ(r->history[i].robustness, one.history[i].robustness);
    }
  }
  no.scan_evaluator = [](const std::vector<double>&) { return std::vector<RobustnessPoint>(2); };
  EXPECT_THROW(RunNoa(Factory("beta"), no), std::logic_error);
}

TEST(Design, InvalidOptionsThrow) {
  NoaOptions no;
  no.lower = 1.0;
  no.upper = 0.0;
  EXPECT_THROW(RunNoa(Factory("beta"), no), std::invalid_argument);
  SweepOptions so;  // no reference frequency
  EXPECT_THROW(SweepRobustness(Factory("beta"), {0.0}, so), std::invalid_argument);
  ResonanceSearchOptions rs;
  std::string err;
  EXPECT_FALSE(rs.IsValid(&err));
}

TEST(Design, ResonanceIsThePeakOfTheMaximumResponse) {
  HbmSystem sys(testing::LoadBaseline().model, HbmOptions{1, 128});
  ResonanceSearchOptions rs;
  rs.lo_hz = 260.0;
  rs.hi_hz = 272.0;
  rs.scan_points = 7;
  const ResonanceResult r = FindResonance(sys, rs, BoundsOptions{});
  ASSERT_TRUE(r.bounds.max.IsUsable());
  for (double f : {r.freq_hz - 0.5, r.freq_hz + 0.5}) {
    const BoundsResult b = ComputeBounds(sys, f, BoundsOptions{});
    ASSERT_TRUE(b.max.IsUsable());
    EXPECT_LE(b.max.amplitude, r.bounds.max.amplitude * (1 + 1e-9)) << f;
  }
}

// Issue 9, defect 8: when no maximum converges anywhere there is no resonance: NaN, not the
// first scan frequency reported as a peak.
TEST(Design, NoConvergedMaximumMeansNoResonance) {
  HbmSystem sys(testing::LoadBaseline().model, HbmOptions{1, 128});
  ResonanceSearchOptions rs;
  rs.lo_hz = 265.9;
  rs.hi_hz = 266.1;
  rs.scan_points = 3;
  BoundsOptions bo;
  bo.method = BoundsOptions::kFullSpace;
  bo.max_iterations = 1;  // nothing that needs the optimiser converges
  bo.alpha_seeds = {Eigen::VectorXd::Constant(4, 0.5)};
  bo.check_samples = 0;
  const ResonanceResult r = FindResonance(sys, rs, bo);
  ASSERT_FALSE(r.bounds.max.IsUsable()) << r.bounds.BriefReport();
  EXPECT_TRUE(std::isnan(r.freq_hz));
  EXPECT_TRUE(std::isnan(r.bounds.max.amplitude));
  EXPECT_EQ(r.bound_solves, 3);  // the scan only: no refinement around a non-existent peak
}

// A bound curve is its points' bounds: without the warm start each point equals a single bound
// computation; with it every point is at least as wide (pass 2 only adds starts), the peak is the
// largest converged y_max, and progress counts both passes.
TEST(Design, BoundCurveIsItsPointsWithNeighbourStartsAndItsPeak) {
  HbmSystem sys(testing::LoadBaseline().model, HbmOptions{1, 128});
  const std::vector<double> freqs = EvenFrequencies(262.0, 270.0, 3);
  ASSERT_EQ(freqs.size(), 3u);
  EXPECT_DOUBLE_EQ(freqs[1], 266.0);
  BoundCurveOptions o;
  o.neighbour_pass = BoundCurveOptions::kNeighbours;
  o.bounds.check_samples = 0;
  std::vector<int> done, refined;
  o.progress = [&](const std::string& stage, int d, int total) {
    if (stage == "frequencies" || stage == "neighbour starts") {
      EXPECT_EQ(total, 3);
      (stage == "frequencies" ? done : refined).push_back(d);
    } else {
      EXPECT_NE(stage.find(" Hz: seeds"), std::string::npos) << stage;
    }
  };
  const BoundCurve curve = ComputeBoundCurve(sys, freqs, o);
  EXPECT_EQ(done, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(refined, (std::vector<int>{1, 2, 3}));
  ASSERT_EQ(curve.points.size(), 3u);
  BoundCurveOptions cold_options = o;
  cold_options.warm_start = false;
  cold_options.progress = nullptr;
  const BoundCurve cold_curve = ComputeBoundCurve(sys, freqs, cold_options);
  for (int i = 0; i < 3; ++i) {
    const BoundsResult cold = ComputeBounds(sys, freqs[i], o.bounds);
    EXPECT_EQ(cold_curve.points[i].min.amplitude, cold.min.amplitude);
    EXPECT_EQ(cold_curve.points[i].max.amplitude, cold.max.amplitude);
    ASSERT_TRUE(curve.points[i].IsUsable());
    EXPECT_LE(curve.points[i].min.amplitude, cold.min.amplitude);
    EXPECT_GE(curve.points[i].max.amplitude, cold.max.amplitude);
    EXPECT_GE(curve.points[i].seeds_tried, cold.seeds_tried);
    EXPECT_GT(curve.points[i].wall_s, 0.0);  // every point carries its cost
    EXPECT_LE(curve.points[i].wall_s, curve.wall_s);
  }
  ASSERT_TRUE(curve.HasPeak());
  for (const BoundsResult& b : curve.points) {
    EXPECT_LE(b.max.amplitude, curve.points[curve.peak].max.amplitude);
  }
  EXPECT_NE(curve.BriefReport().find("peak of y_max"), std::string::npos);
  EXPECT_THROW(ComputeBoundCurve(sys, {266.0, -1.0}, o), std::invalid_argument);
  BoundCurveOptions bad = o;
  bad.threads = -1;
  EXPECT_THROW(ComputeBoundCurve(sys, freqs, bad), std::invalid_argument);
  EXPECT_THROW(EvenFrequencies(270.0, 262.0, 3), std::invalid_argument);
  EXPECT_THROW(EvenFrequencies(262.0, 270.0, 1), std::invalid_argument);
}

// The curve has no order: on two threads (each with its own balance) it is bit for bit the curve
// of one thread, and a point's second pass depends only on its neighbours' first-pass results.
TEST(Design, BoundCurveIsTheSameOnTwoThreadsAndPointByPoint) {
  const Model model = testing::LoadBaseline().model;
  HbmSystem sys(model, HbmOptions{1, 128});
  const std::vector<double> freqs = EvenFrequencies(255.0, 275.0, 6);
  BoundCurveOptions o;
  o.neighbour_pass = BoundCurveOptions::kNeighbours;
  o.bounds.check_samples = 4;
  const BoundCurve one = ComputeBoundCurve(sys, freqs, o);
  o.threads = 2;
  int made = 0;
  const BoundCurve two = ComputeBoundCurve(sys, freqs, o, [&] {
    ++made;
    return std::make_unique<HbmSystem>(model, HbmOptions{1, 128});
  });
  EXPECT_LE(made, 1);  // one balance per extra thread at most
  BoundsOptions bo = o.bounds;
  std::vector<BoundsResult> pass1;
  for (double f : freqs) pass1.push_back(ComputeBounds(sys, f, bo));
  int refined = 0;
  for (int i = 0; i < 6; ++i) {
    const BoundsResult by_hand = RefineFromNeighbours(sys, pass1, i, bo);
    refined += by_hand.seeds_tried > pass1[i].seeds_tried;
    for (const BoundCurve* c : {&one, &two}) {
      EXPECT_EQ(c->points[i].min.amplitude, by_hand.min.amplitude) << i;
      EXPECT_EQ(c->points[i].max.amplitude, by_hand.max.amplitude) << i;
      EXPECT_EQ(c->points[i].min.alpha, by_hand.min.alpha) << i;
      EXPECT_EQ(c->points[i].seeds_tried, by_hand.seeds_tried) << i;
    }
  }
  EXPECT_GT(refined, 0);  // some neighbour optimum was a new start, so pass 2 ran
  EXPECT_EQ(one.peak, two.peak);
  EXPECT_THROW(RefineFromNeighbours(sys, pass1, 6, bo), std::invalid_argument);
}

// Pass 2 as sweeps (the default): the curve is pass 1 carried up and down the points
// (SweepBounds) and merged (MergeSweeps), on two threads as on one; each sweep starts at pass
// 1's point and never narrows a bound; progress counts the two sweeps.
TEST(Design, BoundCurveSweepsCarryPassOneUpAndDownTheCurve) {
  const Model model = testing::LoadBaseline().model;
  HbmSystem sys(model, HbmOptions{1, 128});
  const std::vector<double> freqs = EvenFrequencies(255.0, 275.0, 6);
  BoundCurveOptions o;
  ASSERT_EQ(o.neighbour_pass, BoundCurveOptions::kSweeps);
  o.bounds.check_samples = 4;
  std::vector<int> sweeps_done;
  o.progress = [&](const std::string& stage, int d, int total) {
    if (stage == "sweeps") {
      EXPECT_EQ(total, 2);
      sweeps_done.push_back(d);
    }
    EXPECT_NE(stage, "neighbour starts");
  };
  const BoundCurve one = ComputeBoundCurve(sys, freqs, o);
  EXPECT_EQ(sweeps_done, (std::vector<int>{1, 2}));
  o.progress = nullptr;
  o.threads = 2;
  const BoundCurve two = ComputeBoundCurve(sys, freqs, o, [&] {
    return std::make_unique<HbmSystem>(model, HbmOptions{1, 128});
  });
  std::vector<BoundsResult> pass1;
  for (double f : freqs) pass1.push_back(ComputeBounds(sys, f, o.bounds));
  const std::vector<BoundsResult> up = SweepBounds(sys, pass1, true, o.bounds);
  const std::vector<BoundsResult> down = SweepBounds(sys, pass1, false, o.bounds);
  ASSERT_EQ(up.size(), 6u);
  ASSERT_EQ(down.size(), 6u);
  EXPECT_EQ(up[0].max.alpha, pass1[0].max.alpha);  // each sweep starts at pass 1's point
  EXPECT_EQ(down[5].min.alpha, pass1[5].min.alpha);
  const std::vector<BoundsResult> merged = MergeSweeps(up, down, pass1, o.bounds.objective);
  int moved = 0;
  for (int i = 0; i < 6; ++i) {
    ASSERT_TRUE(merged[i].IsUsable()) << i;
    EXPECT_LE(merged[i].min.amplitude, std::min(up[i].min.amplitude, down[i].min.amplitude)) << i;
    EXPECT_GE(merged[i].max.amplitude, std::max(up[i].max.amplitude, down[i].max.amplitude)) << i;
    EXPECT_LE(merged[i].min.amplitude, pass1[i].min.amplitude) << i;
    EXPECT_GE(merged[i].max.amplitude, pass1[i].max.amplitude) << i;
    EXPECT_GE(merged[i].wall_s, pass1[i].wall_s) << i;
    moved += merged[i].seeds_tried > pass1[i].seeds_tried;
    for (const BoundCurve* c : {&one, &two}) {
      EXPECT_EQ(c->points[i].min.amplitude, merged[i].min.amplitude) << i;
      EXPECT_EQ(c->points[i].max.amplitude, merged[i].max.amplitude) << i;
      EXPECT_EQ(c->points[i].max.alpha, merged[i].max.alpha) << i;
    }
  }
  EXPECT_GT(moved, 0) << "no sweep ran a single start: the test checks nothing";
  EXPECT_THROW(MergeSweeps(up, {down[0]}, pass1, o.bounds.objective), std::invalid_argument);
  BoundCurveOptions::NeighbourPass pass = BoundCurveOptions::kSweeps;
  EXPECT_TRUE(FromString("neighbours", &pass));
  EXPECT_EQ(pass, BoundCurveOptions::kNeighbours);
  EXPECT_EQ(ToString(pass), "neighbours");
  EXPECT_FALSE(FromString("sideways", &pass));
  EXPECT_EQ(pass, BoundCurveOptions::kNeighbours);  // left alone on an unknown name
  EXPECT_EQ(ToString(BoundCurveOptions::kSweeps), "sweeps");
}

// Pass 2's minima start nothing else: with BoundsOptions::negligible_minimum it makes no minimum
// runs where pass 1's minimum is below that fraction of the maximum already, and stops them there
// elsewhere. The maxima are those of the full pass 2; a minimum never falls below the full pass
// 2's nor rises above pass 1's. (0.99 on the lumped benchmark, whose bounds lie within 20 % of each
// other.)
TEST(Design, PassTwoStopsItsMinimumRunsAtANegligibleResponse) {
  HbmSystem sys(testing::LoadBaseline().model, HbmOptions{1, 128});
  const std::vector<double> freqs = EvenFrequencies(262.0, 272.0, 6);
  BoundsOptions full;
  full.check_samples = 4;
  full.negligible_minimum = 0.0;
  std::vector<BoundsResult> pass1;
  for (double f : freqs) pass1.push_back(ComputeBounds(sys, f, full));
  BoundsOptions cut = full;
  cut.negligible_minimum = 0.99;
  int fewer_runs = 0;
  for (int i = 0; i < static_cast<int>(freqs.size()); ++i) {
    const BoundsResult a = RefineFromNeighbours(sys, pass1, i, full);
    const BoundsResult b = RefineFromNeighbours(sys, pass1, i, cut);
    ASSERT_TRUE(a.IsUsable() && b.IsUsable()) << i;
    EXPECT_EQ(b.max.amplitude, a.max.amplitude) << i;
    EXPECT_GE(b.min.amplitude, a.min.amplitude * (1 - 1e-12)) << i;
    EXPECT_LE(b.min.amplitude, pass1[i].min.amplitude) << i;
    EXPECT_LE(b.optimizer_runs, a.optimizer_runs) << i;
    fewer_runs += b.optimizer_runs < a.optimizer_runs;
  }
  EXPECT_GT(fewer_runs, 0) << "no minimum run was saved: the test checks nothing";
}

// The harmonic ladder on a curve: the H = 1 curve (both passes) refined point by point at H = 3,
// on two threads as on one, and within 1 % in R of the direct H = 3 curve (the independent
// route) where the bounds differ from H = 1's.
TEST(Design, LadderCurveIsTheFirstHarmonicCurveRefinedAtH3) {
  const Model model = testing::LoadBaseline().model;
  HbmSystem h1(model, HbmOptions{1, 128});
  HbmSystem h3(model, HbmOptions{3, 128});
  const std::vector<double> freqs = EvenFrequencies(262.0, 270.0, 5);
  BoundCurveOptions o;
  o.bounds.check_samples = 4;
  const BoundCurve low = ComputeBoundCurve(h1, freqs, o);
  const BoundCurve direct = ComputeBoundCurve(h3, freqs, o);
  o.bounds.search_harmonics = 1;
  const BoundCurve one = ComputeBoundCurve(h3, freqs, o);
  o.threads = 2;
  const BoundCurve two = ComputeBoundCurve(h3, freqs, o, [&] {
    return std::make_unique<HbmSystem>(model, HbmOptions{3, 128});
  });
  for (int i = 0; i < 5; ++i) {
    const BoundsResult by_hand = RefineBoundsAtHarmonics(h3, low.points[i], o.bounds);
    for (const BoundCurve* c : {&one, &two}) {
      const BoundsResult& p = c->points[i];
      ASSERT_TRUE(p.IsUsable()) << p.BriefReport();
      EXPECT_EQ(p.search_harmonics, 1);
      EXPECT_EQ(p.min.amplitude, by_hand.min.amplitude) << i;
      EXPECT_EQ(p.max.amplitude, by_hand.max.amplitude) << i;
      EXPECT_EQ(p.min.x.size(), h3.num_unknowns());
    }
    EXPECT_NEAR(one.points[i].robustness(), direct.points[i].robustness(),
                1e-2 * direct.points[i].robustness())
        << freqs[i];
  }
  EXPECT_EQ(one.peak, direct.peak);
}

TEST(Design, CurveAnchorsAndChainsCoverEveryPointOnce) {
  EXPECT_EQ(CurveAnchors(10, 3), (std::vector<int>{0, 3, 6, 9}));
  EXPECT_EQ(CurveAnchors(10, 4), (std::vector<int>{0, 4, 8, 9}));
  EXPECT_EQ(CurveAnchors(4, 1), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(CurveAnchors(1, 5), (std::vector<int>{0}));
  EXPECT_TRUE(CurveChains(CurveAnchors(4, 1)).empty());
  EXPECT_THROW(CurveAnchors(4, 0), std::invalid_argument);
  const std::vector<CurveChain> c = CurveChains({0, 3, 4, 7});
  ASSERT_EQ(c.size(), 4u);  // two per stretch with interior points, none for 3-4
  EXPECT_EQ(c[0].from, 0);
  EXPECT_EQ(c[0].points, (std::vector<int>{1, 2}));
  EXPECT_EQ(c[1].from, 3);
  EXPECT_EQ(c[1].points, (std::vector<int>{2, 1}));
  EXPECT_EQ(c[2].from, 4);
  EXPECT_EQ(c[3].from, 7);
  EXPECT_EQ(c[3].points, (std::vector<int>{6, 5}));
}

// Continuation between anchors on the paper's system reaches the bounds that every point's own
// multi-start and sample check find (41 points through the resonance, anchors every 5 and 10),
// and its points are harmonic-balance solutions.
TEST(Design, AnchoredCurveEqualsTheFullCurveOnTheLumpedSystem) {
  const Model model = testing::LoadBaseline().model;
  HbmSystem sys(model, HbmOptions{1, 128});
  const std::vector<double> freqs = EvenFrequencies(250.0, 280.0, 41);
  BoundCurveOptions o;
  const BoundCurve full = ComputeBoundCurve(sys, freqs, o);
  for (int every : {5, 10}) {
    o.anchor_every = every;
    const BoundCurve anchored = ComputeBoundCurve(sys, freqs, o);
    ASSERT_EQ(anchored.points.size(), freqs.size());
    for (size_t i = 0; i < freqs.size(); ++i) {
      const BoundsResult& a = anchored.points[i];
      ASSERT_TRUE(a.IsUsable()) << every << " " << freqs[i];
      EXPECT_NEAR(a.min.amplitude, full.points[i].min.amplitude,
                  1e-9 * full.points[i].min.amplitude)
          << every << " " << freqs[i];
      EXPECT_NEAR(a.max.amplitude, full.points[i].max.amplitude,
                  1e-9 * full.points[i].max.amplitude)
          << every << " " << freqs[i];
      HbmEvaluation e;
      sys.Evaluate(a.max.x, 2 * M_PI * freqs[i], a.max.alpha, HbmRequest{}, &e);
      EXPECT_LE(e.residual.norm(), 1e-6 * sys.ResidualScale());
    }
    EXPECT_EQ(anchored.peak, full.peak);
  }
  o.anchor_every = 0;
  EXPECT_THROW(ComputeBoundCurve(sys, freqs, o), std::invalid_argument);
}

// Merging keeps the better converged bound per side and never lets a failure replace one.
TEST(Design, MergeBoundsKeepsTheBetterConvergedSide) {
  BoundsResult a, b;
  a.freq_hz = b.freq_hz = 266.0;
  a.min.status = a.max.status = BoundStatus::kConverged;
  a.min.amplitude = 2.0;
  a.max.amplitude = 5.0;
  a.seeds_tried = 3;
  b.min.status = BoundStatus::kConverged;
  b.min.amplitude = 1.5;
  b.max.status = BoundStatus::kFailed;  // NaN amplitude
  b.seeds_tried = 2;
  MergeBounds(b, BoundsOptions::kAmplitude, &a);
  EXPECT_EQ(a.min.amplitude, 1.5);
  EXPECT_EQ(a.max.amplitude, 5.0);
  EXPECT_TRUE(a.max.IsUsable());
  EXPECT_EQ(a.seeds_tried, 5);
  EXPECT_DOUBLE_EQ(a.spread_min, 0.5);
  b.freq_hz = 267.0;
  EXPECT_THROW(MergeBounds(b, BoundsOptions::kAmplitude, &a), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
