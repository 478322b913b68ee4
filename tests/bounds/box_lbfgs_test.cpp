// The limited-memory BFGS direction of the maximum runs (src/bounds/box_lbfgs.h).
#include "bounds/box_lbfgs.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>

namespace fricrom::bounds_detail {
namespace {

// A symmetric positive definite Hessian and the exact secant pairs (s, A s) of a quadratic.
Eigen::MatrixXd Spd(int n) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Random(n, n);
  return m * m.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

// Away from the bounds the direction solves the secant equation of the newest pair: at g = y
// it is −s (H y = s is what every BFGS update enforces for its pair).
TEST(BoxLbfgs, InTheInteriorTheNewestPairsSecantEquationHolds) {
  const int n = 6;
  const Eigen::MatrixXd a = Spd(n);
  BoxLbfgs q(3);
  Eigen::VectorXd s;
  for (int k = 0; k < 5; ++k) {
    s = 0.1 * Eigen::VectorXd::Random(n);
    q.Push(s, a * s);
  }
  EXPECT_EQ(q.pairs(), 3);  // the memory keeps the newest three
  const Eigen::VectorXd alpha = Eigen::VectorXd::Constant(n, 0.2);
  const Eigen::VectorXd d = q.Direction(alpha, a * s, 1.0);
  EXPECT_LT((d + s).norm(), 1e-10 * s.norm()) << d.transpose();
}

// On a quadratic with memory n and n exact pairs along A-conjugate steps (its eigenvectors)
// every secant equation is inherited, so the estimate is A⁻¹ and the direction the Newton step.
TEST(BoxLbfgs, ConjugatePairsOnAQuadraticGiveTheNewtonStep) {
  const int n = 4;
  const Eigen::MatrixXd a = Spd(n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a);
  BoxLbfgs q(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::VectorXd s = 0.05 * eig.eigenvectors().col(k);
    q.Push(s, a * s);
  }
  const Eigen::VectorXd g = Eigen::VectorXd::Random(n);
  const Eigen::VectorXd newton = -a.ldlt().solve(g);
  const Eigen::VectorXd d = q.Direction(Eigen::VectorXd::Zero(n), g, 1.0);
  EXPECT_LT((d - newton).norm(), 1e-10 * newton.norm())
      << d.transpose() << " / " << newton.transpose();
}

// A variable at a bound that the gradient pushes out of the box does not move; one the
// gradient pulls inside does.
TEST(BoxLbfgs, VariablesHeldAtABoundDoNotMove) {
  const int n = 3;
  const Eigen::MatrixXd a = Spd(n);
  BoxLbfgs q(5);
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd s = 0.1 * Eigen::VectorXd::Random(n);
    q.Push(s, a * s);
  }
  const Eigen::Vector3d alpha(1.0, -1.0, 0.0);
  const Eigen::Vector3d g(-2.0, 1.5, 0.7);  // −g points out at both bounds
  const Eigen::VectorXd d = q.Direction(alpha, g, 1.0);
  EXPECT_EQ(d[0], 0.0);
  EXPECT_EQ(d[1], 0.0);
  EXPECT_LT(d[2], 0.0);
  const Eigen::Vector3d inward(2.0, -1.5, 0.7);  // −g points into the box at both bounds
  const Eigen::VectorXd e = q.Direction(alpha, inward, 1.0);
  EXPECT_LT(e[0], 0.0);
  EXPECT_GT(e[1], 0.0);
}

// Without a usable pair the direction is the caller's gradient step on the free variables;
// pairs without positive curvature or with non-finite entries are not kept.
TEST(BoxLbfgs, WithoutCurvatureTheDirectionIsTheGradientStep) {
  BoxLbfgs q(5);
  q.Push(Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(-1.0, 0.0));  // s·y < 0: a kink
  q.Push(Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0.0, 1.0));   // s·y = 0
  q.Push(Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(std::numeric_limits<double>::quiet_NaN(), 0.0));
  EXPECT_EQ(q.pairs(), 0);
  const Eigen::VectorXd d =
      q.Direction(Eigen::Vector2d(1.0, 0.3), Eigen::Vector2d(-1.0, 2.0), 0.25);
  EXPECT_EQ(d[0], 0.0);  // held at +1
  EXPECT_DOUBLE_EQ(d[1], -0.5);
  BoxLbfgs off(0);  // memory 0 keeps nothing
  off.Push(Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 0.0));
  EXPECT_EQ(off.pairs(), 0);
}

// Whatever pairs it holds, the direction descends where the gradient is not zero on the free
// variables.
TEST(BoxLbfgs, TheDirectionAlwaysDescends) {
  const int n = 8;
  BoxLbfgs q(4);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd s = Eigen::VectorXd::Random(n), y = Eigen::VectorXd::Random(n);
    q.Push(s, y);  // only those with s·y > 0 are kept
    const Eigen::VectorXd alpha = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd g = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd d = q.Direction(alpha, g, 0.5);
    ASSERT_TRUE(d.allFinite());
    ASSERT_LT(g.dot(d), 0.0) << "trial " << trial;
  }
}

}  // namespace
}  // namespace fricrom::bounds_detail
