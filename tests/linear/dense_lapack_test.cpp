// The LAPACK-backed dense kernels against Eigen's own routines and against identities that hold
// whatever the route (A x = b, Aᵀ x = b, K Φ = M Φ Λ with Φᵀ M Φ = I), on both sides of the size
// where the LAPACK route starts.
#include "linear/dense_lapack.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdlib>
#include <stdexcept>

namespace fricrom::dense {
namespace {

Eigen::MatrixXd Random(Eigen::Index r, Eigen::Index c, unsigned seed) {
  std::srand(seed);
  return Eigen::MatrixXd::Random(r, c);
}

class DenseLapackSizes : public ::testing::TestWithParam<int> {};

TEST_P(DenseLapackSizes, LuSolvesAndTransposedSolves) {
  const int n = GetParam();
  const Eigen::MatrixXd a = Random(n, n, 3) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd b = Random(n, 3, 4);
  const Lu lu(a);
  EXPECT_LT((a * lu.Solve(b) - b).norm(), 1e-12 * b.norm() * a.norm());
  EXPECT_LT((a.transpose() * lu.Solve(b, true) - b).norm(), 1e-12 * b.norm() * a.norm());
  const Eigen::VectorXd v = b.col(0);
  EXPECT_LT((a * lu.Solve(v) - v).norm(), 1e-12 * v.norm() * a.norm());
  // rcond: the 1-norm estimate of both routes is within a factor 10 of the exact value.
  const double exact = 1.0 / (a.cwiseAbs().colwise().sum().maxCoeff() *
                              a.inverse().cwiseAbs().colwise().sum().maxCoeff());
  EXPECT_GT(lu.rcond(), 0.1 * exact);
  EXPECT_LT(lu.rcond(), 10.0 * exact);
}

TEST_P(DenseLapackSizes, SingularMatrixHasZeroOrTinyRcond) {
  const int n = GetParam();
  Eigen::MatrixXd a = Random(n, n, 5);
  a.col(n - 1) = a.col(0);  // rank deficient
  EXPECT_LT(Lu(a).rcond(), 1e-14);
}

TEST_P(DenseLapackSizes, ProductMatchesEigenForEveryTransposition) {
  const int n = GetParam();
  const Eigen::MatrixXd a = Random(n, n + 7, 6), b = Random(n + 7, n, 7);
  const Eigen::MatrixXd at = a.transpose(), bt = b.transpose();
  const Eigen::MatrixXd ref = a * b;
  EXPECT_LT((Product(a, false, b, false) - ref).norm(), 1e-13 * ref.norm());
  EXPECT_LT((Product(at, true, b, false) - ref).norm(), 1e-13 * ref.norm());
  EXPECT_LT((Product(a, false, bt, true) - ref).norm(), 1e-13 * ref.norm());
  EXPECT_LT((Product(at, true, bt, true) - ref).norm(), 1e-13 * ref.norm());
  EXPECT_THROW(Product(a, false, a, false), std::invalid_argument);
}

TEST_P(DenseLapackSizes, GeneralizedEigenIsMOrthonormalAndMatchesEigen) {
  const int n = GetParam();
  const Eigen::MatrixXd r = Random(n, n, 8), q = Random(n, n, 9);
  const Eigen::MatrixXd k = r * r.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd m = 1e-3 * (q * q.transpose() + n * Eigen::MatrixXd::Identity(n, n));
  Eigen::VectorXd lambda;
  Eigen::MatrixXd phi;
  ASSERT_TRUE(SymmetricGeneralizedEigen(k, m, &lambda, &phi));
  EXPECT_LT((k * phi - m * phi * lambda.asDiagonal()).norm(), 1e-10 * k.norm());
  EXPECT_LT((phi.transpose() * m * phi - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-10);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(k, m);
  EXPECT_LT((lambda - es.eigenvalues()).norm(), 1e-11 * es.eigenvalues().norm());
  for (int i = 1; i < n; ++i) EXPECT_LE(lambda[i - 1], lambda[i]);
}

TEST_P(DenseLapackSizes, GeneralizedEigenRefusesAnIndefiniteMass) {
  const int n = GetParam();
  const Eigen::MatrixXd k = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n);
  m(n / 2, n / 2) = -1.0;
  Eigen::VectorXd lambda;
  Eigen::MatrixXd phi;
  EXPECT_FALSE(SymmetricGeneralizedEigen(k, m, &lambda, &phi));
}

// 12: Eigen's routines; 150: LAPACK (kLapackMinSize = 96).
INSTANTIATE_TEST_SUITE_P(BothRoutes, DenseLapackSizes, ::testing::Values(12, 150));

TEST(DenseLapack, BothRoutesAreExercised) {
  EXPECT_LT(12, kLapackMinSize);
  EXPECT_GE(150, kLapackMinSize);
}

}  // namespace
}  // namespace fricrom::dense
