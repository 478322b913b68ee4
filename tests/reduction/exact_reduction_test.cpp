// Exact cases for the Craig-Bampton pieces, each against numbers worked out by hand:
//  * a 3-mass chain reduced onto its free end (constraint mode, fixed-interface modes and the
//    reduced K and M in closed form);
//  * rigid-body fields and mass properties of point masses;
//  * the structural checks of a given Craig-Bampton model (and that they detect a broken one);
//  * the full-model modal solver against the chain's closed-form eigenvalues, clamped and free.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12 false positive inside Eigen
#endif

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "fricrom/reduction.h"

namespace fricrom {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// ground --k-- m1 --k-- m2 --k-- m3 with m = 2 kg, k = 3 N/m; DOF 2 (m3) is the boundary.
// By hand: K_ii = k [[2, -1], [-1, 2]], K_ib = [0, -k]^T, so the constraint mode is
// Psi = -K_ii^-1 K_ib = [1/3, 2/3]^T (the static line), fixed-interface modes (m3 held):
// lambda = k/m {1, 3} = {1.5, 4.5}, phi = [1, 1]/sqrt(2m), [1, -1]/sqrt(2m). Reduced, in the
// order (u3, q1, q2):
//   K_r = diag(k/3, 1.5, 4.5) = diag(1, 1.5, 4.5)              (three springs in series: k/3)
//   M_r = [[m(1 + 1/9 + 4/9), sqrt(m/2), -sqrt(m/2)/3],        = [[28/9, 1, -1/3],
//          [sqrt(m/2), 1, 0], [-sqrt(m/2)/3, 0, 1]]               [1, 1, 0], [-1/3, 0, 1]]
// (signs of the modal rows/columns follow the arbitrary sign of each mode).
struct Chain3 {
  SpMat k, m;
  Chain3() {
    const double kk = 3.0, mm = 2.0;
    Eigen::MatrixXd kd(3, 3);
    kd << 2 * kk, -kk, 0, -kk, 2 * kk, -kk, 0, -kk, kk;
    k = kd.sparseView();
    m = (mm * Eigen::MatrixXd::Identity(3, 3)).sparseView();
  }
};

Eigen::MatrixXd FixSigns(Eigen::MatrixXd a, const Eigen::VectorXd& ref_row0, int nb) {
  // Flip each modal coordinate so that its coupling with the boundary has the sign of ref_row0.
  for (int j = nb; j < a.cols(); ++j) {
    if (a(0, j) * ref_row0(j) < 0) {
      a.col(j) *= -1.0;
      a.row(j) *= -1.0;
    }
  }
  return a;
}

void ExpectChain3(const ReducedModel& r, const CraigBamptonSummary& s) {
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
  Eigen::MatrixXd k_exact(3, 3), m_exact(3, 3);
  k_exact << 1, 0, 0, 0, 1.5, 0, 0, 0, 4.5;
  m_exact << 28.0 / 9.0, 1, -1.0 / 3.0, 1, 1, 0, -1.0 / 3.0, 0, 1;
  const Eigen::MatrixXd m = FixSigns(r.mass, m_exact.row(0).transpose(), 1);
  const Eigen::MatrixXd k = FixSigns(r.stiffness, m_exact.row(0).transpose(), 1);
  EXPECT_LT((k - k_exact).cwiseAbs().maxCoeff(), 1e-13) << k;
  EXPECT_LT((m - m_exact).cwiseAbs().maxCoeff(), 1e-13) << m;
  ASSERT_EQ(r.constraint_modes.rows(), 2);
  EXPECT_NEAR(r.constraint_modes(0, 0), 1.0 / 3.0, 1e-14);
  EXPECT_NEAR(r.constraint_modes(1, 0), 2.0 / 3.0, 1e-14);
  EXPECT_NEAR(r.modal_frequencies_hz(0), std::sqrt(1.5) / (2 * std::numbers::pi), 1e-14);
  EXPECT_NEAR(r.modal_frequencies_hz(1), std::sqrt(4.5) / (2 * std::numbers::pi), 1e-14);
}

TEST(ExactReduction, ThreeMassChainOntoItsEndMatchesTheHandCalculation) {
  const Chain3 c;
  CraigBamptonOptions opt;
  opt.num_modes = 2;
  CraigBamptonSummary s;
  const ReducedModel r = ReduceCraigBampton(c.k, c.m, {2}, opt, &s);
  ExpectChain3(r, s);
  // All modes kept: the reduced model is the full model in other coordinates, so its
  // eigenvalues are the chain's, 2 (k/m) (1 - cos((2j - 1) pi / 7)).
  const Eigen::VectorXd lam = ReducedEigenvalues(r.stiffness, r.mass);
  for (int j = 1; j <= 3; ++j) {
    const double exact = 2 * 1.5 * (1 - std::cos((2 * j - 1) * std::numbers::pi / 7));
    EXPECT_NEAR(lam(j - 1), exact, 1e-13 * exact);
  }
}

TEST(ExactReduction, OneModeKeepsTheFirstRowsOfTheHandCalculation) {
  const Chain3 c;
  CraigBamptonOptions opt;
  opt.num_modes = 1;
  CraigBamptonSummary s;
  const ReducedModel r = ReduceCraigBampton(c.k, c.m, {2}, opt, &s);
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess);
  ASSERT_EQ(r.stiffness.rows(), 2);
  EXPECT_NEAR(r.stiffness(0, 0), 1.0, 1e-13);
  EXPECT_NEAR(r.stiffness(1, 1), 1.5, 1e-13);
  EXPECT_NEAR(r.mass(0, 0), 28.0 / 9.0, 1e-13);
  EXPECT_NEAR(std::abs(r.mass(0, 1)), 1.0, 1e-13);
  // Truncation makes the reduced eigenvalues upper bounds (Rayleigh-Ritz).
  const Eigen::VectorXd lam = ReducedEigenvalues(r.stiffness, r.mass);
  const double exact1 = 3 * (1 - std::cos(std::numbers::pi / 7));
  EXPECT_GT(lam(0), exact1);
  EXPECT_LT(lam(0), 1.05 * exact1);
}

TEST(ExactReduction, RigidBodyModesAndMassPropertiesOfPointMasses) {
  // Four point masses (3 translational DOFs each, lumped mass) at known places.
  FeModel model;
  const std::vector<std::pair<Eigen::Vector3d, double>> pts = {
      {{0, 0, 0}, 1.0}, {{2, 0, 0}, 1.0}, {{0, 1, 0}, 2.0}, {{0, 0, 3}, 4.0}};
  std::vector<DofId> dofs;
  std::vector<Eigen::Triplet<double>> tm;
  for (size_t i = 0; i < pts.size(); ++i) {
    model.nodes.push_back(FeNode{static_cast<int64_t>(i + 1), pts[i].first, 0, 0});
    for (int c = 1; c <= 3; ++c) {
      tm.emplace_back(static_cast<int>(dofs.size()), static_cast<int>(dofs.size()), pts[i].second);
      dofs.push_back(DofId{static_cast<int64_t>(i + 1), c});
    }
  }
  SpMat m(12, 12);
  m.setFromTriplets(tm.begin(), tm.end());
  const Eigen::MatrixXd r = RigidBodyModes(model, dofs, Eigen::Vector3d(1, 1, 1));
  // Rotation about z through (1,1,1) moves the node at (2,0,0) by e_z x (1,-1,-1) = (1, 1, 0).
  EXPECT_DOUBLE_EQ(r(3, 5), 1.0);
  EXPECT_DOUBLE_EQ(r(4, 5), 1.0);
  EXPECT_DOUBLE_EQ(r(5, 5), 0.0);
  const Eigen::Matrix<double, 6, 6> mrr = r.transpose() * (m * r);
  MassProperties p = MassPropertiesFromRigidMass(mrr);
  p.center += Eigen::Vector3d(1, 1, 1);
  // By hand: mass 8, center (2/8, 2/8, 12/8); inertia about the center sum m (|d|^2 I - d d^T).
  EXPECT_NEAR(p.mass, 8.0, 1e-14);
  EXPECT_LT((p.center - Eigen::Vector3d(0.25, 0.25, 1.5)).norm(), 1e-14);
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  for (const auto& [x, mass] : pts) {
    const Eigen::Vector3d d = x - p.center;
    j += mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  EXPECT_LT((p.inertia_at_center - j).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_NEAR(p.inertia_at_center(2, 2), 1 * (0.0625 + 0.0625) + 1 * (3.0625 + 0.0625) +
                                             2 * (0.0625 + 0.5625) + 4 * (0.0625 + 0.0625),
              1e-13);
}

TEST(ExactReduction, RigidBodyModesInARotatedDisplacementSystem) {
  // System 10: z along basic x, x-z plane through basic y (as the Nastran EXTSEOUT sample):
  // local x = basic y, local y = basic z, local z = basic x.
  FeModel model;
  model.systems.push_back(CoordinateSystem{10, 0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  model.nodes.push_back(FeNode{7, {0, 0, 0}, 0, 10});
  std::vector<DofId> dofs;
  for (int c = 1; c <= 6; ++c) dofs.push_back({7, c});
  const Eigen::MatrixXd r = RigidBodyModes(model, dofs);
  EXPECT_DOUBLE_EQ(r(0, 1), 1.0);  // local x displacement = basic y translation
  EXPECT_DOUBLE_EQ(r(1, 2), 1.0);  // local y = basic z
  EXPECT_DOUBLE_EQ(r(2, 0), 1.0);  // local z = basic x
  EXPECT_DOUBLE_EQ(r(5, 3), 1.0);  // local rz = basic rx
  EXPECT_THROW(RigidBodyModes(model, {{8, 1}}), std::invalid_argument);  // no such node
}

TEST(ExactReduction, StructuralChecksPassForAReductionAndCatchABrokenModel) {
  const Chain3 c;
  CraigBamptonOptions opt;
  opt.num_modes = 2;
  CraigBamptonSummary s;
  const ReducedModel r = ReduceCraigBampton(c.k, c.m, {2}, opt, &s);
  CraigBamptonChecks ch = CheckCraigBamptonMatrices(r.stiffness, r.mass, 1);
  EXPECT_LT(ch.Max(), 1e-14);
  Eigen::MatrixXd k_bad = r.stiffness;
  k_bad(0, 2) = k_bad(2, 0) = 0.01;  // boundary-modal stiffness coupling
  EXPECT_NEAR(CheckCraigBamptonMatrices(k_bad, r.mass, 1).stiffness_coupling, 0.01 / 4.5, 1e-15);
  Eigen::MatrixXd m_bad = r.mass;
  m_bad(1, 1) = 1.001;
  EXPECT_NEAR(CheckCraigBamptonMatrices(r.stiffness, m_bad, 1).modal_mass, 1e-3, 1e-15);
  EXPECT_THROW(CheckCraigBamptonMatrices(r.stiffness, r.mass, 4), std::invalid_argument);
}

TEST(ExactReduction, FullModelModesOfClampedAndFreeChains) {
  // Clamped-free chain of n unit masses/springs: lambda_j = 2 (1 - cos((2j - 1) pi / (2n + 1))).
  const int n = 400;
  std::vector<Eigen::Triplet<double>> tk;
  for (int i = 0; i < n; ++i) {
    tk.emplace_back(i, i, i + 1 < n ? 2.0 : 1.0);
    if (i + 1 < n) {
      tk.emplace_back(i, i + 1, -1.0);
      tk.emplace_back(i + 1, i, -1.0);
    }
  }
  SpMat k(n, n), m(n, n);
  k.setFromTriplets(tk.begin(), tk.end());
  m.setIdentity();
  ModalSolveOptions o;
  o.num_modes = 5;
  const ModalSolveResult clamped = SolveLowestModes(k, m, o);
  ASSERT_EQ(clamped.status, ModalSolveStatus::kSuccess) << clamped.message;
  EXPECT_EQ(clamped.shift_used, 0.0);
  for (int j = 1; j <= 5; ++j) {
    const double exact = 2 * (1 - std::cos((2 * j - 1) * std::numbers::pi / (2 * n + 1)));
    EXPECT_NEAR(clamped.lambda(j - 1), exact, 1e-9 * exact);
  }
  // Free-free: remove the ground spring. lambda_j = 2 (1 - cos(j pi / n)), j = 0.. (one rigid
  // mode). K is singular, so the solver must pick a negative shift by itself.
  k.coeffRef(0, 0) = 1.0;
  const ModalSolveResult free = SolveLowestModes(k, m, o);
  ASSERT_EQ(free.status, ModalSolveStatus::kSuccess) << free.message;
  EXPECT_LT(free.shift_used, 0.0);
  EXPECT_NEAR(free.lambda(0), 0.0, 1e-12);
  for (int j = 1; j < 5; ++j) {
    const double exact = 2 * (1 - std::cos(j * std::numbers::pi / n));
    EXPECT_NEAR(free.lambda(j), exact, 1e-9 * exact);
  }
  // Without auto_shift the singular K is reported, not hidden.
  o.auto_shift = false;
  EXPECT_EQ(SolveLowestModes(k, m, o).status, ModalSolveStatus::kFactorizationFailed);
  o.num_modes = 0;
  EXPECT_THROW(SolveLowestModes(k, m, o), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
