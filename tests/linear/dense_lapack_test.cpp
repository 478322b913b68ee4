// The LAPACK-backed dense kernels against Eigen's own routines and against identities that hold
// whatever the route (A x = b, Aᵀ x = b, K Φ = M Φ Λ with Φᵀ M Φ = I), on both sides of the size
// where the LAPACK route starts.
#include "linear/dense_lapack.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <stdexcept>
#include <thread>
#include <vector>

#include "fricrom/condensed_system.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"
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

// A single-precision factorisation reused for many solves (a GMRES preconditioner) switches to
// its explicit inverse: the solves before and after agree to float round-off, in both
// transpositions, for vectors and blocks, from two threads at once, and in a copy; a new
// factorisation starts again on triangular solves.
TEST(DenseLu, ReusedSinglePrecisionFactorsSolveByTheirInverse) {
  const int n = 320;
  Eigen::MatrixXd a = testing::SeededRandom(n, n, 5) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  a.col(7).setZero();
  a(7, 7) = 3.0;  // one eliminated column: the inverse is of the active part
  const Eigen::MatrixXd b = testing::SeededRandom(n, 2, 6);
  const Eigen::VectorXd v = b.col(0);
  Lu lu;
  lu.Compute(a, LuPrecision::kSingle);
  ASSERT_FALSE(lu.exact());
  ASSERT_EQ(lu.num_unit_columns(), 1);
  const Eigen::VectorXd before = lu.Solve(v), before_t = lu.Solve(v, true);
  EXPECT_FALSE(lu.solves_by_inverse());
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&lu, &v] {
      for (int k = 0; k < 60; ++k) lu.Solve(v, k % 2 == 1);
    });
  }
  for (std::thread& t : threads) t.join();
  ASSERT_TRUE(lu.solves_by_inverse());
  const double tol = 1e-5 * v.norm();
  EXPECT_LT((lu.Solve(v) - before).norm(), tol);
  EXPECT_LT((lu.Solve(v, true) - before_t).norm(), tol);
  EXPECT_LT((a * lu.Solve(v) - v).norm(), 1e-5 * v.norm() * a.norm());
  EXPECT_LT((a.transpose() * lu.Solve(v, true) - v).norm(), 1e-5 * v.norm() * a.norm());
  EXPECT_LT((a * lu.Solve(b) - b).norm(), 1e-5 * b.norm() * a.norm());
  EXPECT_LT((a.transpose() * lu.Solve(b, true) - b).norm(), 1e-5 * b.norm() * a.norm());
  const Lu copy = lu;
  EXPECT_TRUE(copy.solves_by_inverse());
  EXPECT_LT((copy.Solve(v) - before).norm(), tol);
  lu.Compute(2.0 * a, LuPrecision::kSingle);
  EXPECT_FALSE(lu.solves_by_inverse());
  EXPECT_LT((2.0 * lu.Solve(v) - before).norm(), tol);
  // A double factorisation keeps its exact triangular solves however often it is used.
  Lu exact(a);
  for (int k = 0; k < 100; ++k) exact.Solve(v);
  EXPECT_FALSE(exact.solves_by_inverse());
  EXPECT_LT((a * exact.Solve(v) - v).norm(), 1e-12 * v.norm() * a.norm());
}

// The condensed balance's pattern: columns that are unit outside a few "mean" rows (fully stuck
// contacts' harmonics) among dense ones. Solves against the dense LU (both transpositions, both
// ways of factorising), rcond against the exact value, and the split seen where LAPACK is used.
Eigen::MatrixXd UnitOutsideRows(int n, int seed, std::vector<int>* split) {
  Eigen::MatrixXd a = testing::SeededRandom(n, n, seed) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  const int m = n / 5;  // rows 0..m-1 play the mean rows
  split->clear();
  for (int c = m; c < n; c += 2) {  // every other column beyond them
    const double d = a(c, c);
    a.col(c).tail(n - m).setZero();
    a(c, c) = d;
    a(c, 0) = 0.0;  // column 0 meets the split rows nowhere (stuck contacts' mean unknowns)
    split->push_back(c);
  }
  return a;
}

TEST_P(DenseLapackSizes, ColumnsUnitOutsideFewRowsAreEliminatedExactly) {
  const int n = GetParam();
  std::vector<int> split;
  const Eigen::MatrixXd a = UnitOutsideRows(n, 21, &split);
  const Eigen::MatrixXd b = testing::SeededRandom(n, 2, 22);
  const Eigen::PartialPivLU<Eigen::MatrixXd> ref(a);
  const double exact = 1.0 / (a.cwiseAbs().colwise().sum().maxCoeff() *
                              a.inverse().cwiseAbs().colwise().sum().maxCoeff());
  const bool lapack = n >= kLapackMinSize;
  for (const LuPrecision precision : {LuPrecision::kDouble, LuPrecision::kSingle}) {
    for (const bool transposed : {false, true}) {
      SCOPED_TRACE(::testing::Message() << "single " << (precision == LuPrecision::kSingle)
                                        << " transposed " << transposed);
      Lu lu;
      if (transposed) {
        lu.ComputeTransposed(a, precision);
      } else {
        lu.Compute(a, precision);
      }
      const Eigen::MatrixXd op = transposed ? Eigen::MatrixXd(a.transpose()) : a;
      const double tol = lapack && precision == LuPrecision::kSingle ? 1e-5 : 1e-12;
      EXPECT_LT((op * lu.Solve(b) - b).norm(), tol * b.norm() * a.norm());
      EXPECT_LT((op.transpose() * lu.Solve(b, true) - b).norm(), tol * b.norm() * a.norm());
      const Eigen::VectorXd v = b.col(1);
      EXPECT_LT((op * lu.Solve(v) - v).norm(), tol * v.norm() * a.norm());
      EXPECT_GT(lu.rcond(), 0.1 * exact);
      EXPECT_LT(lu.rcond(), 10.0 * exact);
      if (lapack) {  // every marked column split off, touching the m first rows only
        EXPECT_EQ(lu.num_unit_columns(), static_cast<Eigen::Index>(split.size()));
        EXPECT_EQ(lu.num_fill_rows(), n / 5);
      } else {
        EXPECT_EQ(lu.num_unit_columns(), 0);
      }
    }
  }
}

// A split whose Schur complement is singular: the whole matrix is, and rcond says so.
TEST_P(DenseLapackSizes, SingularSchurComplementHasTinyRcond) {
  const int n = GetParam();
  std::vector<int> split;
  Eigen::MatrixXd a = UnitOutsideRows(n, 23, &split);
  // a(:, 1) = a(:, 0) + a(:, s), s a split column: singular, and the split is unchanged.
  a.col(1) = a.col(0) + a.col(split.front());
  EXPECT_LT(Lu(a).rcond(), 1e-14);
  EXPECT_LT(Lu(a, LuPrecision::kSingle).rcond(), 1e-6);
}

// Candidate columns that touch each other cannot all be split: a(S, S) must stay diagonal.
TEST(DenseLu, CandidatesTouchingEachOtherStayInTheFactorisation) {
  const int n = 120;
  Eigen::MatrixXd a = testing::SeededRandom(n, n, 31) + 0.5 * n * Eigen::MatrixXd::Identity(n, n);
  for (int c = 60; c < n; ++c) {  // sparse columns, each touching the next one's row
    const double d = a(c, c);
    a.col(c).setZero();
    a(c, c) = d;
    a(c == n - 1 ? 60 : c + 1, c) = 0.7;
    a(c % 10, c) = 0.3;
  }
  const Lu lu(a);
  EXPECT_EQ(lu.num_unit_columns(), 0);  // every candidate is touched by another
  const Eigen::MatrixXd b = testing::SeededRandom(n, 1, 32);
  EXPECT_LT((a * lu.Solve(b) - b).norm(), 1e-12 * b.norm() * a.norm());
}

// The real pattern: at a solution of the condensed balance with stuck and sliding contacts, the
// dense Jacobian's columns of the stuck contacts' harmonics are split off (the exact zeros
// EffectiveBlocks leaves are what makes them so), and the solves still match the dense LU.
TEST(DenseLu, StuckContactsOfTheCondensedBalanceAreSplitOff) {
  const CondensedSystem cond(testing::ContactStrip(40), HbmOptions{1, 64});
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(cond.num_contacts(), -0.8, 0.8);
  const double f = 1000.0;
  const FrfPoint sol = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(sol.status, SolverStatus::kConverged);
  int stuck = 0;
  for (const ContactRegime r : cond.ContactRegimes(sol.x, kTwoPi * f, alpha)) {
    stuck += r == ContactRegime::kFullStick;
  }
  ASSERT_GT(stuck, 0);
  ASSERT_LT(stuck, cond.num_contacts());
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = true;
  cond.Evaluate(sol.x, kTwoPi * f, alpha, req, &e);
  ASSERT_GE(e.jacobian.rows(), kLapackMinSize);
  const Eigen::MatrixXd b = testing::SeededRandom(e.jacobian.rows(), 2, 51);
  const double scale = b.norm() * e.jacobian.norm();
  for (const LuPrecision precision : {LuPrecision::kDouble, LuPrecision::kSingle}) {
    const Lu lu(e.jacobian, precision);
    // Two harmonic coefficients of each stuck tangential row at least, minus shared rows.
    EXPECT_GE(lu.num_unit_columns(), stuck);
    EXPECT_GT(lu.num_fill_rows(), 0) << lu.num_unit_columns() << " " << stuck << " " << lu.rows();
    const double tol = precision == LuPrecision::kSingle ? 1e-5 : 1e-12;
    EXPECT_LT((e.jacobian * lu.Solve(b) - b).norm(), tol * scale);
    EXPECT_LT((e.jacobian.transpose() * lu.Solve(b, true) - b).norm(), tol * scale);
    EXPECT_GT(lu.rcond(), 0.0);
  }
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

TEST_P(DenseLapackSizes, SymmetricMatVecReadsTheUpperTriangleOnly) {
  const int n = GetParam();
  const Eigen::MatrixXd r = testing::SeededRandom(n, n, 14);
  const Eigen::MatrixXd a = r + r.transpose();
  const Eigen::VectorXd x = testing::SeededRandom(n, 1, 15);
  Eigen::MatrixXd upper = a;
  upper.triangularView<Eigen::StrictlyLower>().setConstant(std::nan(""));
  Eigen::VectorXd y;
  SymmetricMatVec(upper, x, &y);
  ASSERT_TRUE(y.allFinite());
  EXPECT_LT((y - a * x).norm(), 1e-13 * (a * x).norm());
  EXPECT_THROW(SymmetricMatVec(a, testing::SeededRandom(n + 1, 1, 16), &y), std::invalid_argument);
  EXPECT_THROW(SymmetricMatVec(testing::SeededRandom(n, n + 1, 17), x, &y), std::invalid_argument);
}

TEST_P(DenseLapackSizes, ProductWithOneOrTwoColumnsMatchesEigen) {
  const int n = GetParam();
  const Eigen::MatrixXd a = testing::SeededRandom(n, n + 7, 18);
  for (int cols : {1, 2}) {
    const Eigen::MatrixXd x = testing::SeededRandom(n + 7, cols, 19),
                          xt = testing::SeededRandom(n, cols, 20);
    EXPECT_LT((Product(a, false, x, false) - a * x).norm(), 1e-13 * (a * x).norm());
    EXPECT_LT((Product(a, true, xt, false) - a.transpose() * xt).norm(),
              1e-13 * (a.transpose() * xt).norm());
    EXPECT_THROW(Product(a, false, xt, false), std::invalid_argument);
  }
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
