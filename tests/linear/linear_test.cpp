#include "fricrom/linear.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_models.h"

namespace fricrom {
namespace {

// Paper, Table 3.
const double kFreeHz[] = {87.17, 87.17, 159.15, 159.15, 246.56, 246.56};
const double kStickHz[] = {84.58,  84.58,  168.19, 168.19, 266.89,
                           266.89, 396.71, 396.71, 406.88, 406.88};

TEST(Linear, Table3FreeAndFullStickFrequencies) {
  const Case cs = testing::LoadBaseline();
  const ModalResult free = FreeSystemModes(cs.model);
  const ModalResult stick = StickSystemModes(cs.model);
  ASSERT_EQ(free.frequencies_hz.size(), 6);
  ASSERT_EQ(stick.frequencies_hz.size(), 10);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(free.frequencies_hz[i], kFreeHz[i], 0.01) << i;
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(stick.frequencies_hz[i], kStickHz[i], 0.01) << i;
}

// The free chain has closed-form eigenvalues k + kC·{0, 1, 3} per direction (path Laplacian).
TEST(Linear, FreeSystemMatchesClosedForm) {
  const Case cs = testing::LoadBaseline();
  const ModalResult free = FreeSystemModes(cs.model);
  const double k = 3e5, kc = 7e5;
  const double expected[] = {k, k, k + kc, k + kc, k + 3 * kc, k + 3 * kc};
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(free.frequencies_hz[i], std::sqrt(expected[i]) / (2 * std::numbers::pi), 1e-9);
  }
}

TEST(Linear, ModesAreMassNormalisedEigenpairs) {
  const Case cs = testing::LoadBaseline();
  const Eigen::MatrixXd k = cs.model.stiffness + ContactStickStiffness(cs.model);
  const ModalResult r = StickSystemModes(cs.model);
  const Eigen::MatrixXd& phi = r.shapes;
  const Eigen::VectorXd w2 = (2 * std::numbers::pi * r.frequencies_hz).array().square();
  const Eigen::MatrixXd resid = k * phi - cs.model.mass * phi * w2.asDiagonal();
  EXPECT_LE(resid.norm(), 1e-8 * k.norm());
  EXPECT_LE((phi.transpose() * cs.model.mass * phi - Eigen::MatrixXd::Identity(10, 10)).norm(),
            1e-10);
}

TEST(Linear, ResponsePeaksAtTheTargetModes) {
  const Case cs = testing::LoadBaseline();
  std::vector<double> f;
  for (double x = 240.0; x <= 290.0; x += 0.01) f.push_back(x);
  auto peak = [&](LinearSystemKind kind) {
    const auto a = LinearResponseAmplitude(cs.model, kind, f);
    return f[std::max_element(a.begin(), a.end()) - a.begin()];
  };
  EXPECT_NEAR(peak(LinearSystemKind::kFree), 246.56, 0.05);
  EXPECT_NEAR(peak(LinearSystemKind::kStick), 266.89, 0.05);
}

TEST(Linear, RejectsMismatchedMatrices) {
  EXPECT_THROW(ComputeModes(Eigen::MatrixXd::Identity(3, 3), Eigen::MatrixXd::Identity(2, 2)),
               std::invalid_argument);
  EXPECT_THROW(ComputeModes(Eigen::MatrixXd::Identity(2, 2), -Eigen::MatrixXd::Identity(2, 2)),
               std::invalid_argument);
}

// A chain of three springs with a massless middle node: the finite modes are those of the
// statically condensed 2-DOF system (Guyan is exact for a massless DOF); the free-free chain
// (rigid mode at 0 Hz) takes the shifted route. Mass-normalised shapes.
TEST(Linear, ASemiDefiniteMassGivesTheCondensedModes) {
  for (double ground : {1.0, 0.0}) {
    Eigen::Matrix3d k;
    k << 2 + ground, -2, 0, -2, 5, -3, 0, -3, 3 + ground;
    const Eigen::Matrix3d m = Eigen::Vector3d(1.5, 0.0, 0.5).asDiagonal();
    const ModalResult r = ComputeModes(k, m);
    EXPECT_EQ(r.massless, 1);
    ASSERT_EQ(r.frequencies_hz.size(), 2);
    // Condensed: K_c = K_aa - K_ab K_bb^-1 K_ba over DOFs 0 and 2.
    Eigen::Matrix2d kc, mc;
    kc << k(0, 0) - k(0, 1) * k(1, 0) / k(1, 1), k(0, 2) - k(0, 1) * k(1, 2) / k(1, 1),
        k(2, 0) - k(2, 1) * k(1, 0) / k(1, 1), k(2, 2) - k(2, 1) * k(1, 2) / k(1, 1);
    mc << 1.5, 0, 0, 0.5;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> want(kc, mc);
    for (int i = 0; i < 2; ++i) {
      const double f = std::sqrt(std::max(want.eigenvalues()[i], 0.0)) / (2 * M_PI);
      EXPECT_NEAR(r.frequencies_hz[i], f, 1e-9 * (1 + f)) << "ground " << ground << " mode " << i;
      EXPECT_NEAR(r.shapes.col(i).dot(m * r.shapes.col(i)), 1.0, 1e-9);
    }
  }
  // Indefinite is not a mass.
  EXPECT_THROW(ComputeModes(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1, -1).asDiagonal()),
               std::invalid_argument);
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

// Without a receptance key the modal route is taken only where it is exact: damping that the
// full-stick modes diagonalise (mass-proportional here), a definite mass, enough DOFs.
TEST(Linear, TheModalReceptanceIsChosenWhereItIsExact) {
  const int n = 6;
  Model m;
  m.stiffness = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    m.stiffness(i, i) += 2e4 + 1e3 * i;
    if (i + 1 < n) {
      m.stiffness(i, i) += 1e4;
      m.stiffness(i + 1, i + 1) += 1e4;
      m.stiffness(i, i + 1) = m.stiffness(i + 1, i) = -1e4;
    }
  }
  m.mass = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0).asDiagonal();
  m.damping = 3.0 * m.mass;  // mass-proportional
  m.dof_names.assign(n, "dof");
  EXPECT_EQ(ChooseReceptance(m, 1), ReceptanceMethod::kModal);
  EXPECT_EQ(ChooseReceptance(m, n + 1), ReceptanceMethod::kDense);  // too small to pay
  m.damping(0, 0) += 5.0;  // one dashpot: not diagonal in the modes
  EXPECT_EQ(ChooseReceptance(m, 1), ReceptanceMethod::kDense);
  m.damping = 3.0 * m.mass;
  m.mass(n - 1, n - 1) = 0.0;  // a massless DOF: the modal route cannot take it
  EXPECT_EQ(ChooseReceptance(m, 1), ReceptanceMethod::kDense);
}

}  // namespace
}  // namespace fricrom
