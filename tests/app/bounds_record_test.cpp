#include "app/bounds_record.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "fricrom/hbm_system.h"
#include "test_models.h"

namespace fricrom::app {
namespace {

void ExpectSameSolution(const BoundSolution& a, const BoundSolution& b) {
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.alpha, b.alpha);
  EXPECT_EQ(a.amplitude, b.amplitude);  // bit for bit, not to a tolerance
  EXPECT_EQ(a.loss_factor, b.loss_factor);
  EXPECT_EQ(a.residual, b.residual);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.stationary, b.stationary);
  EXPECT_EQ(a.message, b.message);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.regimes, b.regimes);
}

// A journal record of a real bound computation reads back bit for bit, through text.
TEST(BoundsRecord, ReadsBackBitForBit) {
  HbmSystem sys(testing::LoadBaseline().model, HbmOptions{1, 128});
  BoundsOptions o;
  o.check_samples = 4;
  const BoundsResult b = ComputeBounds(sys, 266.0, o);
  ASSERT_TRUE(b.IsUsable());
  EXPECT_TRUE(b.min.stationary);
  const BoundsResult r = BoundsFromRecord(nlohmann::json::parse(BoundsRecord(b).dump()));
  EXPECT_EQ(r.freq_hz, b.freq_hz);
  ExpectSameSolution(r.min, b.min);
  ExpectSameSolution(r.max, b.max);
  EXPECT_EQ(r.spread_min, b.spread_min);
  EXPECT_EQ(r.spread_max, b.spread_max);
  EXPECT_EQ(r.seeds_tried, b.seeds_tried);
  EXPECT_EQ(r.seed_counts.base, b.seed_counts.base);
  EXPECT_EQ(r.seeds_converged, b.seeds_converged);
  EXPECT_EQ(r.optimizer_runs, b.optimizer_runs);
  EXPECT_EQ(r.runs_abandoned, b.runs_abandoned);
  EXPECT_EQ(r.samples_checked, b.samples_checked);
  EXPECT_EQ(r.search_harmonics, b.search_harmonics);
  EXPECT_EQ(r.harmonics, 1);
  EXPECT_EQ(r.wall_s, b.wall_s);
  EXPECT_EQ(r.robustness(), b.robustness());
}

// A failed bound stays a failure: NaN in, null in the record, NaN out.
TEST(BoundsRecord, FailedBoundStaysNaN) {
  BoundsResult b;
  b.freq_hz = 1000.0;
  b.spread_min = NAN;
  b.min.x = Eigen::VectorXd::Constant(2, NAN);
  const nlohmann::json j = BoundsRecord(b);
  EXPECT_TRUE(j["min"]["amplitude"].is_null());
  const BoundsResult r = BoundsFromRecord(j);
  EXPECT_FALSE(r.min.IsUsable());
  EXPECT_TRUE(std::isnan(r.min.amplitude));
  EXPECT_TRUE(std::isnan(r.spread_min));
  EXPECT_TRUE(std::isnan(r.min.x[1]));
}

// A damaged record is an error naming what is wrong, never a number.
TEST(BoundsRecord, DamagedRecordsAreErrors) {
  BoundsResult b;
  b.freq_hz = 266.0;
  const nlohmann::json good = BoundsRecord(b);
  auto expect_error = [](const nlohmann::json& j, const char* what) {
    try {
      BoundsFromRecord(j);
      ADD_FAILURE() << "no error for " << what;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  nlohmann::json j = good;
  j.erase("seeds_tried");
  expect_error(j, "seeds_tried");
  j = good;
  j["min"]["status"] = 17;
  expect_error(j, "status");
  j = good;
  j["max"]["alpha"] = {1.0, "x"};
  expect_error(j, "alpha");
  j = good;
  j["min"]["stationary"] = 1;
  expect_error(j, "stationary");
  j = good;
  j["freq_hz"] = -1.0;
  expect_error(j, "freq_hz");
  j = good;
  j["min"]["regimes"] = {9};
  expect_error(j, "regime");
  expect_error(nlohmann::json::array(), "freq_hz");
}

}  // namespace
}  // namespace fricrom::app
