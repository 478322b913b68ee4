#include <gtest/gtest.h>

#include <cmath>

#include "fricrom/solve.h"

namespace fricrom {
namespace {

// R(x) = (x0² + x1² − 4, x0 − x1): roots ±(√2, √2).
struct Circle : SquareSystem {
  int size() const override { return 2; }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    *r = Eigen::Vector2d(x[0] * x[0] + x[1] * x[1] - 4.0, x[0] - x[1]);
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
    *r = Eigen::Vector2d(x[0] + x[1] - 1.0, 2 * x[0] + 2 * x[1] + 3.0);
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

TEST(Newton, ConvergesQuadraticallyToARoot) {
  Eigen::VectorXd x = Eigen::Vector2d(3.0, 1.0);
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
  Eigen::VectorXd x = Eigen::Vector2d(0.0, 0.0);
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

TEST(Newton, InvalidOptionsAndSizesThrow) {
  NewtonOptions o;
  o.residual_tolerance = -1.0;
  std::string err;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_NE(err.find("residual_tolerance"), std::string::npos);
  Eigen::VectorXd x = Eigen::Vector2d(1.0, 1.0);
  EXPECT_THROW(SolveNewton(Circle{}, o, &x), std::invalid_argument);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(SolveNewton(Circle{}, NewtonOptions{}, &bad), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
