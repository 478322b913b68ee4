#include <gtest/gtest.h>

#include <cmath>

#include "fricrom/solve.h"

namespace fricrom {
namespace {

// λ = x³ − 3x: an S-curve with turning points at x = ±1 (λ = ∓2... ±2).
struct SCurve : ParametricSystem {
  int size() const override { return 1; }
  void Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* r, Eigen::MatrixXd* j,
                Eigen::VectorXd* dl) const override {
    r->resize(1);
    (*r)[0] = x[0] * x[0] * x[0] - 3 * x[0] - lambda;
    if (j) {
      j->resize(1, 1);
      (*j)(0, 0) = 3 * x[0] * x[0] - 3;
    }
    if (dl) {
      dl->resize(1);
      (*dl)[0] = -1.0;
    }
  }
};

// The S-curve's continuation from x = −3.1 over λ ∈ [−18, 18].
ContinuationOptions SCurveOptions() {
  ContinuationOptions o;
  o.lambda_start = -18.0;
  o.lambda_end = 18.0;
  o.lambda_scale = 36.0;
  o.x_scale = 3.0;
  o.max_step = 0.05;
  return o;
}

// Both folds passed, every point on the curve, the middle (unstable) branch between the folds
// traversed, the end landed exactly.
void ExpectTheWholeSCurve(const ContinuationOptions& o) {
  std::vector<ContinuationPoint> pts;
  const ContinuationSummary s =
      Continue(SCurve{}, o, Eigen::VectorXd::Constant(1, -3.1), [&](const ContinuationPoint& p) {
        pts.push_back(p);
        return true;
      });
  EXPECT_EQ(s.status, ContinuationStatus::kReachedEnd) << s.BriefReport();
  EXPECT_EQ(s.turning_points, 2);
  ASSERT_GT(pts.size(), 10u);
  bool middle = false;
  for (const ContinuationPoint& p : pts) {
    EXPECT_NEAR(p.x[0] * p.x[0] * p.x[0] - 3 * p.x[0], p.lambda, 1e-8);
    middle |= std::abs(p.x[0]) < 0.2;
  }
  EXPECT_TRUE(middle);
  EXPECT_NEAR(pts.back().lambda, 18.0, 1e-12);
  EXPECT_NEAR(pts.back().x[0], 3.0, 1e-8);
}

TEST(Continuation, PassesTwoTurningPointsOfAnSCurve) { ExpectTheWholeSCurve(SCurveOptions()); }

// The secant predictor with a short corrector budget (TraceFrf's) follows the same S-curve.
TEST(Continuation, TheSecantPredictorWithAShortCorrectorPassesBothFolds) {
  ContinuationOptions o = SCurveOptions();
  o.secant_predictor = true;
  o.max_corrector_iterations = 6;
  o.max_corrector_backtracks = 2;
  ExpectTheWholeSCurve(o);
  o.max_corrector_backtracks = -2;
  EXPECT_THROW(Continue(SCurve{}, o, Eigen::VectorXd::Zero(1), {}), std::invalid_argument);
}

TEST(Continuation, CallbackCanStop) {
  int n = 0;
  const ContinuationSummary s =
      Continue(SCurve{}, SCurveOptions(), Eigen::VectorXd::Constant(1, -3.0),
               [&](const ContinuationPoint&) { return ++n < 5; });
  EXPECT_EQ(s.status, ContinuationStatus::kStopped);
  EXPECT_EQ(n, 5);
}

TEST(Continuation, InvalidOptionsThrow) {
  ContinuationOptions o;
  o.lambda_start = o.lambda_end = 1.0;
  EXPECT_THROW(Continue(SCurve{}, o, Eigen::VectorXd::Zero(1), {}), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
