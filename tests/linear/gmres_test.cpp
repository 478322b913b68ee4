// GMRES preconditioned by an LU of a nearby matrix: exact preconditioner, low-rank changes
// (the case of consecutive Newton Jacobians), the transposed routes and honest failure.
#include "linear/gmres.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>

#include "test_models.h"

namespace fricrom::dense {
namespace {

// A well-conditioned matrix on the LAPACK route (n ≥ kLapackMinSize).
Eigen::MatrixXd Base(int n) {
  return testing::SeededRandom(n, n, 11) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
}

TEST(Gmres, ExactPreconditionerNeedsOneProduct) {
  const int n = 150;
  const Eigen::MatrixXd a = Base(n);
  const Eigen::VectorXd b = testing::SeededRandom(n, 1, 12);
  Eigen::VectorXd x;
  const GmresResult g = PreconditionedGmres(a, false, Lu(a), false, b, 1e-12, 10, &x);
  EXPECT_TRUE(g.converged);
  EXPECT_EQ(g.iterations, 1);
  EXPECT_LT((a * x - b).norm(), 1e-12 * b.norm());
}

// A = M + U Vᵀ with rank k: A M⁻¹ is the identity plus rank k, so GMRES ends within k + 1 products.
TEST(Gmres, LowRankChangeConvergesWithinRankPlusOneProducts) {
  const int n = 200, k = 6;
  const Eigen::MatrixXd m = Base(n);
  const Eigen::MatrixXd a =
      m + 3.0 * testing::SeededRandom(n, k, 13) * testing::SeededRandom(k, n, 14);
  const Eigen::VectorXd b = testing::SeededRandom(n, 1, 15);
  Eigen::VectorXd x;
  const GmresResult g = PreconditionedGmres(a, false, Lu(m), false, b, 1e-10, 50, &x);
  EXPECT_TRUE(g.converged);
  EXPECT_LE(g.iterations, k + 1);
  EXPECT_LT((a * x - b).norm(), 1e-9 * b.norm());
  EXPECT_NEAR(g.relative_residual, (a * x - b).norm() / b.norm(), 1e-9);
}

TEST(Gmres, TransposedOperatorAndPreconditioner) {
  const int n = 120, k = 3;
  const Eigen::MatrixXd m = Base(n);
  const Eigen::MatrixXd a = m + testing::SeededRandom(n, k, 16) * testing::SeededRandom(k, n, 17);
  const Eigen::VectorXd b = testing::SeededRandom(n, 1, 18);
  Lu mt;
  mt.ComputeTransposed(m);  // factorises mᵀ: Solve(·, false) applies m⁻ᵀ, Solve(·, true) m⁻¹
  Eigen::VectorXd x;
  // aᵀ x = b preconditioned by mᵀ.
  GmresResult g = PreconditionedGmres(a, true, mt, false, b, 1e-11, 20, &x);
  EXPECT_TRUE(g.converged);
  EXPECT_LE(g.iterations, k + 1);
  EXPECT_LT((a.transpose() * x - b).norm(), 1e-10 * b.norm());
  // a x = b preconditioned by the same factorisation used the other way round.
  g = PreconditionedGmres(a, false, mt, true, b, 1e-11, 20, &x);
  EXPECT_TRUE(g.converged);
  EXPECT_LE(g.iterations, k + 1);
  EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm());
}

TEST(Gmres, ReportsFailureWhenTheProductsRunOut) {
  const int n = 150;
  const Eigen::MatrixXd m = Base(n);
  const Eigen::MatrixXd a = m + 5.0 * testing::SeededRandom(n, n, 19);  // a full-rank change
  const Eigen::VectorXd b = testing::SeededRandom(n, 1, 20);
  Eigen::VectorXd x;
  const GmresResult g = PreconditionedGmres(a, false, Lu(m), false, b, 1e-12, 3, &x);
  EXPECT_FALSE(g.converged);
  EXPECT_EQ(g.iterations, 3);
  EXPECT_GT(g.relative_residual, 1e-12);
}

TEST(Gmres, ZeroRightHandSideAndBadArguments) {
  const Eigen::MatrixXd a = Base(100);
  Eigen::VectorXd x;
  const GmresResult g =
      PreconditionedGmres(a, false, Lu(a), false, Eigen::VectorXd::Zero(100), 1e-12, 5, &x);
  EXPECT_TRUE(g.converged);
  EXPECT_EQ(g.iterations, 0);
  EXPECT_EQ(x, Eigen::VectorXd::Zero(100));
  EXPECT_THROW(PreconditionedGmres(a, false, Lu(a), false, Eigen::VectorXd::Ones(99), 1e-12, 5, &x),
               std::invalid_argument);
  EXPECT_THROW(
      PreconditionedGmres(a, false, Lu(a), false, Eigen::VectorXd::Ones(100), 1e-12, 0, &x),
      std::invalid_argument);
}

}  // namespace
}  // namespace fricrom::dense
