// The harmonic ladder (BoundsOptions::search_harmonics = 1): the search at H = 1, the optima
// refined at H. Compared with the direct search at H (the independent route) on the paper's
// lumped system, where contacts stick-slip at 264-268 Hz and H = 3 moves the bounds (y_min at
// 266 Hz: 2.0376e-4 m at H = 1, 2.0485e-4 m at H = 3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

HbmSystem& BaselineAt(int harmonics) {
  static HbmSystem h1(testing::LoadBaseline().model, HbmOptions{1, 128});
  static HbmSystem h3(testing::LoadBaseline().model, HbmOptions{3, 128});
  return harmonics == 1 ? h1 : h3;
}

// R(x, α) = 0 at H = 3; where contacts slip (`slips`) with non-zero higher harmonics: a solution
// of the finer balance, not the H = 1 one padded with zeros.
void ExpectSolutionAtH3(double freq_hz, const BoundSolution& s, bool slips) {
  const HbmSystem& sys = BaselineAt(3);
  ASSERT_TRUE(s.IsUsable()) << s.message;
  ASSERT_EQ(s.x.size(), sys.num_unknowns());
  HbmEvaluation e;
  sys.Evaluate(s.x, kTwoPi * freq_hz, s.alpha, HbmRequest{}, &e);
  EXPECT_LE(e.residual.norm(), 1e-6 * sys.ResidualScale());
  const int block = sys.num_unknowns() / 7;
  if (slips) {
    EXPECT_GT(s.x.tail(4 * block).norm(), 0.0);
  }
}

class Ladder : public ::testing::TestWithParam<double> {};

TEST_P(Ladder, RefinedBoundsMatchTheDirectSearchAtH3) {
  const double f = GetParam();
  BoundsOptions direct;
  BoundsOptions ladder;
  ladder.search_harmonics = 1;
  const BoundsResult d = ComputeBounds(BaselineAt(3), f, direct);
  const BoundsResult l = ComputeBounds(BaselineAt(3), f, ladder);
  const BoundsResult h1 = ComputeBounds(BaselineAt(1), f, direct);
  ASSERT_TRUE(d.IsUsable()) << d.BriefReport();
  ASSERT_TRUE(l.IsUsable()) << l.BriefReport();
  EXPECT_EQ(d.search_harmonics, 3);
  EXPECT_EQ(l.search_harmonics, 1);
  EXPECT_EQ(l.harmonics, 3);
  EXPECT_EQ(d.harmonics, 3);
  EXPECT_NE(l.BriefReport().find("searched at H = 1, refined at H = 3"), std::string::npos);
  EXPECT_EQ(d.BriefReport().find("refined"), std::string::npos) << d.BriefReport();
  EXPECT_EQ(l.refinement_fallbacks, 0) << l.BriefReport();
  // Each refined bound is a point where a run at H = 3 stopped by its test (a KKT start counts),
  // not merely the embedded H = 1 optimum taken as a known solution.
  EXPECT_TRUE(l.min.stationary) << l.min.message;
  EXPECT_TRUE(l.max.stationary) << l.max.message;
  // The minimum slips at all three frequencies (H = 3 moves it), the maximum only from 266 Hz.
  ExpectSolutionAtH3(f, l.min, true);
  ExpectSolutionAtH3(f, l.max, f > 265.0);
  // The same bounds as the direct search at H = 3 (0.5 %), and R within 1 % ...
  EXPECT_NEAR(l.min.amplitude, d.min.amplitude, 5e-3 * d.min.amplitude) << l.BriefReport();
  EXPECT_NEAR(l.max.amplitude, d.max.amplitude, 5e-3 * d.max.amplitude) << l.BriefReport();
  EXPECT_NEAR(l.robustness(), d.robustness(), 1e-2 * d.robustness());
  // ... and the seeds were searched at H = 1: the counts are the H = 1 search's plus the
  // refinement's runs, the samples the H = 1 check's plus the check at H.
  EXPECT_GT(l.seeds_tried, h1.seeds_tried);  // the H = 1 seeds and the refinement's starts
  EXPECT_EQ(l.samples_checked, h1.samples_checked + ladder.check_samples);
}

INSTANTIATE_TEST_SUITE_P(StickSlipFrequencies, Ladder, ::testing::Values(264.0, 266.0, 268.0));

TEST(Ladder, ProgressShowsTheSearchAndThenTheRefinement) {
  BoundsOptions o;
  o.search_harmonics = 1;
  std::vector<std::string> stages;
  std::vector<std::pair<int, int>> counts;
  o.progress = [&](const std::string& stage, int done, int total) {
    stages.push_back(stage);
    counts.emplace_back(done, total);
  };
  ASSERT_TRUE(ComputeBounds(BaselineAt(3), 266.0, o).IsUsable());
  ASSERT_GE(stages.size(), 3u);
  EXPECT_EQ(stages.front(), "seeds");
  // The refinement's stage opens (0 of 1), its sample check at H runs, and it closes (1 of 1).
  const auto open = std::find(stages.begin(), stages.end(), "harmonic refinement");
  ASSERT_NE(open, stages.end());
  EXPECT_EQ(counts[open - stages.begin()], std::make_pair(0, 1));
  EXPECT_EQ(stages[stages.size() - 2], "samples at H");
  EXPECT_EQ(stages.back(), "harmonic refinement");
  EXPECT_EQ(counts.back(), std::make_pair(1, 1));
  EXPECT_EQ(std::count(stages.begin(), open, "samples"), o.check_samples);
  EXPECT_EQ(std::count(open, stages.end(), "samples at H"), o.check_samples);
}

// The refinement of the minimum at H stops once the response falls to negligible_minimum times
// the H = 1 maximum (0: it refines to its stopping tests). At 268 Hz the refinement runs from a
// non-stationary H = 1 minimum (the first iterate of a run from this seed) to a KKT point; with a
// ratio below that point's y_min / y_max nothing changes, with one above it the refinement ends
// at the stop: a non-stationary point at or below it, never below the full refinement's minimum.
TEST(Ladder, RefinementOfTheMinimumStopsAtANegligibleResponse) {
  const double f = 268.0;
  BoundsOptions o;
  o.check_samples = 0;
  o.alpha_seeds = {Eigen::Vector4d(-0.7, 0.2, 0.6, -0.1)};
  BoundsResult low = ComputeBounds(BaselineAt(1), f, o);
  BoundsOptions first = o;
  first.minimum_stop_m = 1.0;  // every minimising run ends on its first iterate
  low.min = ComputeBounds(BaselineAt(1), f, first).min;
  ASSERT_TRUE(low.IsUsable() && !low.min.stationary) << low.BriefReport();

  o.search_harmonics = 1;
  o.negligible_minimum = 0.0;
  const BoundsResult full = RefineBoundsAtHarmonics(BaselineAt(3), low, o);
  ASSERT_TRUE(full.IsUsable()) << full.BriefReport();
  ASSERT_TRUE(full.min.stationary) << full.min.message;
  ASSERT_GE(full.min.iterations, 1) << "the refinement must run for this test";
  const double ratio = full.min.amplitude / low.max.amplitude;
  ASSERT_LT(ratio, 0.99);

  o.negligible_minimum = 0.5 * ratio;
  const BoundsResult below = RefineBoundsAtHarmonics(BaselineAt(3), low, o);
  EXPECT_EQ(below.min.amplitude, full.min.amplitude);
  EXPECT_TRUE(below.min.stationary);

  o.negligible_minimum = 0.99;
  const BoundsResult stopped = RefineBoundsAtHarmonics(BaselineAt(3), low, o);
  ASSERT_TRUE(stopped.IsUsable()) << stopped.BriefReport();
  ExpectSolutionAtH3(f, stopped.min, true);
  EXPECT_FALSE(stopped.min.stationary);
  EXPECT_NE(stopped.min.message.find("negligible"), std::string::npos) << stopped.min.message;
  EXPECT_LE(stopped.min.amplitude, 0.99 * low.max.amplitude);
  EXPECT_GE(stopped.min.amplitude, full.min.amplitude * (1 - 1e-12));
  EXPECT_EQ(stopped.max.amplitude, full.max.amplitude);
}

// The stationarity tests are fractions in (0, 1); the search's runs and the ladder's refinement
// have one each (Cascade.LooserStationarityTestStopsEarlierOnTheSamePath: what a looser one does).
TEST(Ladder, StationarityTestsOutsideZeroToOneAreRejected) {
  std::string error;
  EXPECT_TRUE(BoundsOptions{}.IsValid(&error)) << error;
  EXPECT_GT(BoundsOptions{}.refinement_stationary_change, BoundsOptions{}.stationary_change);
  for (double bad : {0.0, 1.0, -1e-5, std::nan("")}) {
    BoundsOptions b;
    b.refinement_stationary_change = bad;
    EXPECT_FALSE(b.IsValid(&error)) << bad;
    EXPECT_NE(error.find("refinement_stationary_change"), std::string::npos) << error;
    b = BoundsOptions{};
    b.stationary_change = bad;
    EXPECT_FALSE(b.IsValid(&error)) << bad;
    EXPECT_NE(error.find("stationary_change"), std::string::npos) << error;
  }
}

TEST(Ladder, ChangesNothingAtH1) {
  BoundsOptions ladder;
  ladder.search_harmonics = 1;
  const BoundsResult a = ComputeBounds(BaselineAt(1), 266.0, BoundsOptions{});
  const BoundsResult b = ComputeBounds(BaselineAt(1), 266.0, ladder);
  EXPECT_EQ(a.min.amplitude, b.min.amplitude);
  EXPECT_EQ(a.max.amplitude, b.max.amplitude);
  EXPECT_EQ(b.search_harmonics, 1);
  EXPECT_EQ(b.harmonics, 1);
  // Nothing was refined: the report must not say so.
  EXPECT_EQ(b.BriefReport().find("refined"), std::string::npos) << b.BriefReport();
}

TEST(Ladder, OptionsAndBalancesThatCannotDropHarmonicsAreRejected) {
  BoundsOptions o;
  std::string error;
  o.search_harmonics = 2;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("search_harmonics"), std::string::npos);
  o.search_harmonics = -1;
  EXPECT_FALSE(o.IsValid(&error));
  // A load at the third harmonic: the H = 1 sibling would drop it.
  Model m = testing::LoadBaseline().model;
  ASSERT_FALSE(m.loads.empty());
  HarmonicLoad third = m.loads.back();
  third.harmonic = 3;
  m.loads.push_back(third);
  const HbmSystem sys(m, HbmOptions{3, 128});
  BoundsOptions ladder;
  ladder.search_harmonics = 1;
  EXPECT_THROW(ComputeBounds(sys, 266.0, ladder), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
