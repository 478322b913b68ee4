#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "fricrom/solve.h"
#include "linear/dense_lapack.h"
#include "solve/newton_preconditioned.h"

namespace fricrom {
namespace {

// R(x) = (x0² + x1² − 4, x0 − x1): roots ±(√2, √2).
struct Circle : SquareSystem {
  int size() const override { return 2; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    *r = Eigen::VectorXd{{x[0] * x[0] + x[1] * x[1] - 4.0, x[0] - x[1]}};
    if (j) {
      j->resize(2, 2);
      *j << 2 * x[0], 2 * x[1], 1, -1;
    }
  }
};

// arctan: plain Newton diverges from |x0| > 1.39; the line search must save it.
struct Arctan : SquareSystem {
  int size() const override { return 1; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    r->resize(1);
    (*r)[0] = std::atan(x[0]);
    if (j) {
      j->resize(1, 1);
      (*j)(0, 0) = 1.0 / (1.0 + x[0] * x[0]);
    }
  }
};

struct Singular : SquareSystem {
  int size() const override { return 2; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    *r = Eigen::VectorXd{{x[0] + x[1] - 1.0, 2 * x[0] + 2 * x[1] + 3.0}};
    if (j) {
      j->resize(2, 2);
      *j << 1, 1, 2, 2;
    }
  }
};

// x² + 1 = 0 has no real root.
struct NoRoot : SquareSystem {
  int size() const override { return 1; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    r->resize(1);
    (*r)[0] = x[0] * x[0] + 1.0;
    if (j) {
      j->resize(1, 1);
      (*j)(0, 0) = 2 * x[0];
    }
  }
};

// A x + c ∘ x³ − b with a diagonally dominant A of 240 unknowns: large enough for the GMRES
// route, and its Jacobian moves with x as a contact balance's does.
struct CubicSystem : SquareSystem {
  Eigen::MatrixXd a;
  Eigen::VectorXd b, c;
  explicit CubicSystem(int n) {
    std::srand(7);
    a = Eigen::MatrixXd::Random(n, n) + 2.0 * n * Eigen::MatrixXd::Identity(n, n);
    b = 40.0 * n * Eigen::VectorXd::Random(n);
    c = 10.0 * (Eigen::VectorXd::Random(n).array() + 1.5).matrix();
  }
  int size() const override { return static_cast<int>(b.size()); }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    *r = a * x + c.cwiseProduct(x.array().cube().matrix()) - b;
    if (j) {
      *j = a;
      j->diagonal() += 3.0 * c.cwiseProduct(x.cwiseAbs2());
    }
  }
};

// The GMRES route (LU of an earlier Jacobian as preconditioner) reaches the root of the plain
// LU route with fewer factorisations than steps.
TEST(Newton, ReusedFactorisationsReachTheSameRoot) {
  const CubicSystem sys(240);
  NewtonOptions plain;
  plain.krylov_min_size = 0;
  Eigen::VectorXd x_plain = Eigen::VectorXd::Zero(240), x_krylov = x_plain;
  const NewtonSummary sp = SolveNewton(sys, plain, &x_plain);
  const NewtonSummary sk = SolveNewton(sys, NewtonOptions{}, &x_krylov);
  ASSERT_TRUE(sp.IsSolutionUsable()) << sp.BriefReport();
  ASSERT_TRUE(sk.IsSolutionUsable()) << sk.BriefReport();
  EXPECT_EQ(sp.factorizations, sp.iterations);
  EXPECT_EQ(sp.krylov_iterations, 0);
  EXPECT_GT(sk.krylov_iterations, 0);
  EXPECT_LT(sk.factorizations, sk.iterations);
  EXPECT_LT((x_krylov - x_plain).norm(), 1e-10 * x_plain.norm());
  // GMRES with single-precision LUs ends in the same place as double LUs without GMRES: the
  // steps' accuracy is GMRES' (double), not the preconditioner's.
  NewtonOptions single_lu;
  single_lu.krylov_max_iterations = 1;  // GMRES misses on changed Jacobians: an LU per step
  Eigen::VectorXd x_single = Eigen::VectorXd::Zero(240);
  const NewtonSummary ss = SolveNewton(sys, single_lu, &x_single);
  ASSERT_TRUE(ss.IsSolutionUsable()) << ss.BriefReport();
  EXPECT_LT((x_single - x_plain).norm(), 1e-10 * x_plain.norm());
  Eigen::VectorXd r;
  sys.Evaluate(x_krylov, &r, nullptr);
  EXPECT_LE(r.norm(), NewtonOptions{}.residual_tolerance);
}

// CubicSystem with tolerances relative to |b|: far above its round-off floor.
struct RelativeCubicSystem : CubicSystem {
  RelativeCubicSystem() : CubicSystem(240) {}
  double ResidualScale() const override { return b.norm(); }
};

// GMRES steps are solved no further than the residual tolerance needs (krylov_oversolve): a
// warm start near the root (as the bound optimiser's line-search solves are) takes fewer products
// for the same root, its residual still within the tolerance.
TEST(Newton, StepsAreNotSolvedPastTheResidualTolerance) {
  const RelativeCubicSystem sys;
  Eigen::VectorXd root = Eigen::VectorXd::Zero(240), r;
  ASSERT_TRUE(SolveNewton(sys, NewtonOptions{}, &root).IsSolutionUsable());
  Eigen::MatrixXd j;
  sys.Evaluate(root, &r, &j);
  const dense::Lu lu(j, dense::LuPrecision::kSingle);
  const Eigen::VectorXd start = root + 1e-6 * root.norm() * Eigen::VectorXd::Random(240);
  NewtonOptions strict;
  strict.krylov_oversolve = 0.0;  // the bare Eisenstat-Walker forcing, down to 1e-9
  Eigen::VectorXd x_strict = start, x_enough = start;
  const NewtonPreconditioner m{&lu, false};
  const NewtonSummary ss = SolveNewtonPreconditioned(sys, strict, m, &x_strict);
  const NewtonSummary se = SolveNewtonPreconditioned(sys, NewtonOptions{}, m, &x_enough);
  ASSERT_TRUE(ss.IsSolutionUsable()) << ss.BriefReport();
  ASSERT_TRUE(se.IsSolutionUsable()) << se.BriefReport();
  EXPECT_GT(se.krylov_iterations, 0);
  EXPECT_LT(se.krylov_iterations, ss.krylov_iterations) << ss.BriefReport() << "\n"
                                                        << se.BriefReport();
  EXPECT_EQ(se.iterations, ss.iterations);
  EXPECT_LE(se.final_residual, NewtonOptions{}.residual_tolerance) << se.BriefReport();
  EXPECT_LT((x_enough - root).norm(), 1e-10 * root.norm());
}

// A caller's factorisation of a nearby Jacobian (here: at the root, transposed as the bound
// optimiser keeps it) lets a warm-started solve finish without an LU of its own.
TEST(Newton, CallerPreconditionerSavesTheFactorisation) {
  const CubicSystem sys(240);
  Eigen::VectorXd root = Eigen::VectorXd::Zero(240), r;
  ASSERT_TRUE(SolveNewton(sys, NewtonOptions{}, &root).IsSolutionUsable());
  Eigen::MatrixXd j;
  sys.Evaluate(root, &r, &j);
  dense::Lu lu;
  lu.ComputeTransposed(j);
  Eigen::VectorXd x = root + 1e-3 * root.cwiseAbs().maxCoeff() * Eigen::VectorXd::Ones(240);
  const NewtonSummary s =
      SolveNewtonPreconditioned(sys, NewtonOptions{}, NewtonPreconditioner{&lu, true}, &x);
  ASSERT_TRUE(s.IsSolutionUsable()) << s.BriefReport();
  EXPECT_EQ(s.factorizations, 0);
  EXPECT_GT(s.krylov_iterations, 0);
  EXPECT_LT((x - root).norm(), 1e-10 * root.norm());
  // A preconditioner of the wrong size is not used (a new LU instead), never an error.
  dense::Lu small(Eigen::MatrixXd::Identity(100, 100));
  x = root + 1e-3 * Eigen::VectorXd::Ones(240);
  const NewtonSummary s2 =
      SolveNewtonPreconditioned(sys, NewtonOptions{}, NewtonPreconditioner{&small, false}, &x);
  ASSERT_TRUE(s2.IsSolutionUsable());
  EXPECT_GE(s2.factorizations, 1);
}

// A residual the caller already evaluated at the start (the bound optimiser's chord attempt)
// spares one evaluation and changes nothing else, bit for bit; one of the wrong size is an error.
TEST(Newton, ResidualGivenAtTheStartIsNotEvaluatedAgain) {
  const CubicSystem sys(240);
  const Eigen::VectorXd start = Eigen::VectorXd::Zero(240);
  Eigen::VectorXd r0;
  sys.Evaluate(start, &r0, nullptr);
  Eigen::VectorXd x_plain = start, x_given = start;
  const NewtonSummary a = SolveNewtonPreconditioned(sys, NewtonOptions{}, {}, &x_plain);
  const NewtonSummary b =
      SolveNewtonPreconditioned(sys, NewtonOptions{}, {}, &x_given, nullptr, &r0);
  ASSERT_TRUE(a.IsSolutionUsable()) << a.BriefReport();
  EXPECT_EQ(b.status, a.status);
  EXPECT_EQ(b.iterations, a.iterations);
  EXPECT_EQ(b.evaluations, a.evaluations - 1);
  EXPECT_EQ(b.initial_residual, a.initial_residual);
  EXPECT_EQ(x_given, x_plain);
  Eigen::VectorXd x = start;
  const Eigen::VectorXd wrong = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(SolveNewtonPreconditioned(sys, NewtonOptions{}, {}, &x, nullptr, &wrong),
               std::invalid_argument);
}

TEST(Newton, ConvergesQuadraticallyToARoot) {
  Eigen::VectorXd x{{3.0, 1.0}};
  const NewtonSummary s = SolveNewton(Circle{}, NewtonOptions{}, &x);
  EXPECT_EQ(s.status, SolverStatus::kConverged) << s.BriefReport();
  EXPECT_NEAR(x[0], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(x[1], std::sqrt(2.0), 1e-12);
  EXPECT_LE(s.iterations, 8);
  EXPECT_TRUE(s.IsSolutionUsable());
}

TEST(Newton, LineSearchGlobalises) {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 3.0);
  const NewtonSummary s = SolveNewton(Arctan{}, NewtonOptions{}, &x);
  EXPECT_EQ(s.status, SolverStatus::kConverged) << s.BriefReport();
  EXPECT_NEAR(x[0], 0.0, 1e-10);
}

TEST(Newton, ReportsSingularJacobian) {
  Eigen::VectorXd x{{0.0, 0.0}};
  const NewtonSummary s = SolveNewton(Singular{}, NewtonOptions{}, &x);
  EXPECT_EQ(s.status, SolverStatus::kSingular);
  EXPECT_FALSE(s.IsSolutionUsable());
}

TEST(Newton, NeverReportsConvergenceWithoutARoot) {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.5);
  NewtonOptions o;
  o.max_iterations = 40;
  const NewtonSummary s = SolveNewton(NoRoot{}, o, &x);
  EXPECT_NE(s.status, SolverStatus::kConverged);
  EXPECT_GE(s.final_residual, 1.0 - 1e-12);
}

// R(x) = x − 1 with a Jacobian 1000× too large: every Newton step removes 0.1 % of ‖R‖, a crawl
// like that of a contact residual whose Jacobian is wrong across a kink.
struct Crawling : SquareSystem {
  int size() const override { return 1; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    r->resize(1);
    (*r)[0] = x[0] - 1.0;
    if (j) j->setConstant(1, 1, 1000.0);
  }
};

// The stall test ends a solve that crawls without a root, and leaves converging solves untouched
// to the last bit (the bound optimiser relies on that: only failures get cheaper).
TEST(Newton, StallTestEndsCrawlingSolvesOnly) {
  NewtonOptions plain;
  plain.max_iterations = 40;
  NewtonOptions stall = plain;
  stall.stall_window = 5;
  Eigen::VectorXd x_plain = Eigen::VectorXd::Constant(1, 3.0), x_stall = x_plain;
  const NewtonSummary a = SolveNewton(Crawling{}, plain, &x_plain);
  const NewtonSummary b = SolveNewton(Crawling{}, stall, &x_stall);
  EXPECT_FALSE(b.IsSolutionUsable());
  EXPECT_NE(b.message.find("stalled"), std::string::npos) << b.BriefReport();
  EXPECT_EQ(a.iterations, plain.max_iterations) << a.BriefReport();
  EXPECT_EQ(b.iterations, stall.stall_window) << b.BriefReport();  // 0.5 % in 5 steps
  for (const Eigen::VectorXd& start : {Eigen::VectorXd{{3.0, 1.0}}, Eigen::VectorXd{{-0.3, 2.0}}}) {
    Eigen::VectorXd p = start, q = start;
    const NewtonSummary sp = SolveNewton(Circle{}, plain, &p);
    const NewtonSummary sq = SolveNewton(Circle{}, stall, &q);
    EXPECT_EQ(sq.status, SolverStatus::kConverged);
    EXPECT_EQ(sp.iterations, sq.iterations);
    EXPECT_EQ(p, q);  // bit for bit
  }
  Eigen::VectorXd p = Eigen::VectorXd::Constant(1, 3.0), q = p;
  SolveNewton(Arctan{}, plain, &p);
  EXPECT_TRUE(SolveNewton(Arctan{}, stall, &q).IsSolutionUsable());
  EXPECT_EQ(p, q);
  std::string err;
  stall.stall_window = -1;
  EXPECT_FALSE(stall.IsValid(&err));
  EXPECT_NE(err.find("stall_window"), std::string::npos);
  stall.stall_window = 5;
  for (double d : {0.0, 1.0, std::nan("")}) {
    stall.stall_decrease = d;
    EXPECT_FALSE(stall.IsValid(&err)) << d;
    EXPECT_NE(err.find("stall_decrease"), std::string::npos);
  }
}

TEST(Newton, InvalidOptionsAndSizesThrow) {
  NewtonOptions o;
  o.residual_tolerance = -1.0;
  std::string err;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("residual_tolerance"), std::string::npos);
  Eigen::VectorXd x{{1.0, 1.0}};
  EXPECT_THROW(SolveNewton(Circle{}, o, &x), std::invalid_argument);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(SolveNewton(Circle{}, NewtonOptions{}, &bad), std::invalid_argument);
  NewtonOptions k;
  k.krylov_tolerance = 1.0;
  EXPECT_FALSE(k.IsValid(&err));
  EXPECT_NE(err.find("krylov_tolerance"), std::string::npos);
  k = NewtonOptions{};
  k.krylov_max_iterations = 0;
  EXPECT_FALSE(k.IsValid(&err));
  k = NewtonOptions{};
  k.krylov_oversolve = -0.5;
  EXPECT_FALSE(k.IsValid(&err));
  EXPECT_NE(err.find("krylov_oversolve"), std::string::npos);
}

}  // namespace
}  // namespace fricrom
