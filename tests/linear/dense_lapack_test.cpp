// The LAPACK-backed dense kernels against Eigen's own routines and against identities that hold
// whatever the route (A x = b, Aᵀ x = b, K Φ = M Φ Λ with Φᵀ M Φ = I), on both sides of the size
// where the LAPACK route starts.
#include "linear/dense_lapack.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <complex>
#include <cstdlib>
#include <stdexcept>

#include "test_models.h"

namespace fricrom::dense {
namespace {

class DenseLapackSizes : public ::testing::TestWithParam<int> {};

TEST_P(DenseLapackSizes, LuSolvesAndTransposedSolves) {
  const int n = GetParam();
  const Eigen::MatrixXd a =
      testing::SeededRandom(n, n, 3) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd b = testing::SeededRandom(n, 3, 4);
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

// Single precision: LAPACK-sized solves accurate to float round-off (not double), flagged
// inexact; below the size Eigen's double LU is kept (exact). Unit columns are eliminated exactly
// in both precisions.
TEST_P(DenseLapackSizes, SinglePrecisionLuIsAccurateToFloatRoundOff) {
  const int n = GetParam();
  Eigen::MatrixXd a = testing::SeededRandom(n, n, 3) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  a.col(2).setZero();
  a(2, 2) = 4.0;  // a unit column
  const Eigen::MatrixXd b = testing::SeededRandom(n, 2, 4);
  for (const bool transposed : {false, true}) {
    Lu lu;
    if (transposed) {
      lu.ComputeTransposed(a, LuPrecision::kSingle);
    } else {
      lu.Compute(a, LuPrecision::kSingle);
    }
    const Eigen::MatrixXd op = transposed ? Eigen::MatrixXd(a.transpose()) : a;
    const bool lapack = n >= kLapackMinSize;
    EXPECT_EQ(lu.exact(), !lapack);
    const double tol = lapack ? 1e-5 : 1e-12;
    EXPECT_LT((op * lu.Solve(b) - b).norm(), tol * b.norm() * a.norm());
    EXPECT_LT((op.transpose() * lu.Solve(b, true) - b).norm(), tol * b.norm() * a.norm());
    const Eigen::VectorXd v = b.col(1);
    const double err = (op * lu.Solve(v) - v).norm() / (v.norm() * a.norm());
    EXPECT_LT(err, tol);
    if (lapack) {
      EXPECT_GT(err, 1e-14);  // really single precision
    }
    EXPECT_GT(lu.rcond(), 1e-3);
  }
  // A double factorisation after a single one is exact again.
  Lu lu(a, LuPrecision::kSingle);
  lu.Compute(a);
  EXPECT_TRUE(lu.exact());
  EXPECT_LT((a * lu.Solve(b) - b).norm(), 1e-12 * b.norm() * a.norm());
}

TEST_P(DenseLapackSizes, WeightedGramMatchesTheGeneralProduct) {
  const int n = GetParam();
  const Eigen::MatrixXd w = testing::SeededRandom(n, n + 9, 12);
  Eigen::VectorXd d = testing::SeededRandom(n + 9, 1, 13);
  d[3] = 0.0;  // zero weights drop out
  const Eigen::MatrixXd ref = w * d.asDiagonal() * w.transpose();
  const Eigen::MatrixXd g = WeightedGram(w, d);
  EXPECT_LT((g - ref).norm(), 1e-13 * (w.norm() * w.norm() * d.cwiseAbs().maxCoeff()));
  if (n >= kLapackMinSize) {
    EXPECT_EQ((g - g.transpose()).norm(), 0.0);  // one triangle computed, mirrored
  }
  EXPECT_EQ(WeightedGram(w, Eigen::VectorXd::Zero(n + 9)).norm(), 0.0);
  EXPECT_THROW(WeightedGram(w, d.head(n)), std::invalid_argument);
}

TEST_P(DenseLapackSizes, MatVecMatchesEigen) {
  const int n = GetParam();
  const Eigen::MatrixXd a = testing::SeededRandom(n, n + 5, 8);
  const Eigen::VectorXd x = testing::SeededRandom(n + 5, 1, 9),
                        xt = testing::SeededRandom(n, 1, 10);
  Eigen::VectorXd y;
  MatVec(a, false, x, &y);
  EXPECT_LT((y - a * x).norm(), 1e-13 * (a * x).norm());
  MatVec(a, true, xt, &y);
  EXPECT_LT((y - a.transpose() * xt).norm(), 1e-13 * (a.transpose() * xt).norm());
  Eigen::MatrixXcd c(n, n + 5);
  c.real() = a;
  c.imag() = testing::SeededRandom(n, n + 5, 11);
  const Eigen::VectorXcd z = x.cast<std::complex<double>>() * std::complex<double>(0.3, -1.0);
  const Eigen::VectorXcd zt = xt.cast<std::complex<double>>() * std::complex<double>(2.0, 0.5);
  Eigen::VectorXcd w;
  MatVec(c, false, z, &w);
  EXPECT_LT((w - c * z).norm(), 1e-13 * (c * z).norm());
  MatVec(c, true, zt, &w);
  EXPECT_LT((w - c.adjoint() * zt).norm(), 1e-13 * (c.adjoint() * zt).norm());
  EXPECT_THROW(MatVec(a, false, xt, &y), std::invalid_argument);
}

TEST_P(DenseLapackSizes, SingularMatrixHasZeroOrTinyRcond) {
  const int n = GetParam();
  Eigen::MatrixXd a = testing::SeededRandom(n, n, 5);
  a.col(n - 1) = a.col(0);  // rank deficient
  EXPECT_LT(Lu(a).rcond(), 1e-14);
}

TEST_P(DenseLapackSizes, ProductMatchesEigenForEveryTransposition) {
  const int n = GetParam();
  const Eigen::MatrixXd a = testing::SeededRandom(n, n + 7, 6),
                        b = testing::SeededRandom(n + 7, n, 7);
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
  const Eigen::MatrixXd r = testing::SeededRandom(n, n, 8), q = testing::SeededRandom(n, n, 9);
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
