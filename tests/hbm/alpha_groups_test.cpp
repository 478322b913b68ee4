// α groups (AlphaGroupedBalance, Model::alpha_group): contacts sharing one α. Checked against the
// ungrouped balance: equal residuals at expanded α, the α Jacobian and the loss-factor gradient
// against central differences, and bounds over a subset of the α box inside the ungrouped bounds.
#include "fricrom/alpha_groups.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

Model GroupedByDamper() {
  Model m = testing::LoadBaseline().model;
  m.alpha_group = {0, 0, 1, 1};  // c1, c2 on damper 1; c3, c4 on damper 2
  return m;
}

TEST(AlphaGroups, ResidualEqualsTheUngroupedBalanceAtExpandedAlpha) {
  const Model grouped = GroupedByDamper();
  Model plain = grouped;
  plain.alpha_group.clear();
  for (BalanceKind kind : {BalanceKind::kFull, BalanceKind::kCondensed}) {
    const auto g = MakeBalance(grouped, HbmOptions{1, 64}, kind);
    const auto p = MakeBalance(plain, HbmOptions{1, 64}, kind);
    ASSERT_EQ(g->num_alpha(), 2);
    ASSERT_EQ(g->num_contacts(), 4);
    const double w = RadPerS(266.0);
    const Eigen::VectorXd x = g->StickLinearSolution(w) * 1.7;
    const Eigen::Vector2d a(0.3, -0.6);
    HbmEvaluation eg, ep;
    g->Evaluate(x, w, a, HbmRequest{true, true, false}, &eg);
    p->Evaluate(x, w, Eigen::Vector4d(0.3, 0.3, -0.6, -0.6), HbmRequest{true, true, false}, &ep);
    EXPECT_EQ((eg.residual - ep.residual).norm(), 0.0);
    ASSERT_EQ(eg.alpha_jacobian.cols(), 2);
    EXPECT_LT(
        (eg.alpha_jacobian.col(0) - ep.alpha_jacobian.col(0) - ep.alpha_jacobian.col(1)).norm(),
        1e-12 * (1.0 + ep.alpha_jacobian.norm()));
    EXPECT_EQ(testing::EntriesOutsidePattern(g->StructuralPattern(), eg), 0) << ToString(kind);
    EXPECT_EQ(testing::EntriesOutsidePattern(p->StructuralPattern(), ep), 0) << ToString(kind);
    EXPECT_THROW(g->Evaluate(x, w, Eigen::Vector4d::Zero(), HbmRequest{}, &eg),
                 std::invalid_argument);
  }
}

TEST(AlphaGroups, AlphaJacobianAndLossFactorGradientMatchCentralDifferences) {
  const auto g = MakeBalance(GroupedByDamper(), HbmOptions{1, 128}, BalanceKind::kFull);
  const double w = RadPerS(266.0);
  const Eigen::Vector2d a(0.2, -0.1);
  const FrfPoint s = SolveAtFrequency(*g, a, 266.0, g->StickLinearSolution(w), FrfOptions{});
  ASSERT_EQ(s.status, SolverStatus::kConverged);
  HbmEvaluation e;
  g->Evaluate(s.x, w, a, HbmRequest{true, true, false}, &e);
  Eigen::VectorXd gx, ga;
  g->LossFactor(s.x, w, a, e, &gx, &ga);
  ASSERT_EQ(ga.size(), 2);
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-6;
    Eigen::Vector2d ap = a, am = a;
    ap[k] += h;
    am[k] -= h;
    HbmEvaluation rp, rm;
    g->Evaluate(s.x, w, ap, HbmRequest{}, &rp);
    g->Evaluate(s.x, w, am, HbmRequest{}, &rm);
    const Eigen::VectorXd fd = (rp.residual - rm.residual) / (2 * h);
    EXPECT_LT((fd - e.alpha_jacobian.col(k)).norm(), 1e-5 * (1.0 + fd.norm())) << k;
    HbmEvaluation ep, em;
    g->Evaluate(s.x, w, ap, HbmRequest{true, true, false}, &ep);
    g->Evaluate(s.x, w, am, HbmRequest{true, true, false}, &em);
    const double etad = (g->LossFactor(s.x, w, ap, ep, nullptr, nullptr) -
                         g->LossFactor(s.x, w, am, em, nullptr, nullptr)) /
                        (2 * h);
    EXPECT_NEAR(ga[k], etad, 1e-5 * (1.0 + std::abs(etad))) << k;
  }
}

// One α per damper is a subset of the α box: its range lies inside the per-contact range.
TEST(AlphaGroups, GroupedBoundsLieInsideThePerContactBounds) {
  const Model grouped = GroupedByDamper();
  Model plain = grouped;
  plain.alpha_group.clear();
  const auto g = MakeBalance(grouped, HbmOptions{1, 128}, BalanceKind::kFull);
  const auto p = MakeBalance(plain, HbmOptions{1, 128}, BalanceKind::kFull);
  const BoundsResult bg = ComputeBounds(*g, 266.0, BoundsOptions{});
  const BoundsResult bp = ComputeBounds(*p, 266.0, BoundsOptions{});
  ASSERT_TRUE(bg.IsUsable());
  ASSERT_TRUE(bp.IsUsable());
  EXPECT_EQ(bg.min.alpha.size(), 2);
  EXPECT_GE(bg.min.amplitude, bp.min.amplitude * (1 - 1e-9));
  EXPECT_LE(bg.max.amplitude, bp.max.amplitude * (1 + 1e-9));
  // At γ = 0 both ends of the per-contact range have α equal within each damper, so the
  // grouped range is the same (to round-off: which of the two ends lower is not defined).
  EXPECT_NEAR(bg.min.amplitude, bp.min.amplitude, 1e-9 * bp.min.amplitude);
  EXPECT_NEAR(bg.max.amplitude, bp.max.amplitude, 1e-9 * bp.max.amplitude);
}

TEST(AlphaGroups, InvalidGroupsAreRejected) {
  Model m = testing::LoadBaseline().model;
  m.alpha_group = {0, 0, 2, 2};  // group 1 empty
  EXPECT_THROW(m.Validate(), std::invalid_argument);
  m.alpha_group = {0, 0, 1};
  EXPECT_THROW(m.Validate(), std::invalid_argument);
  EXPECT_THROW(AlphaGroupedBalance(
                   MakeBalance(testing::LoadBaseline().model, HbmOptions{}, BalanceKind::kFull),
                   {0, 0, 2, 2}),
               std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
