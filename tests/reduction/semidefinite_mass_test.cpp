// Issue 9, defect 6: positive semi-definite mass (massless DOFs) in the Craig-Bampton route, and
// checks that fail on any non-finite value.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fricrom/reduction.h"

namespace fricrom {
namespace {

// Five springs k in a chain grounded at the left; node 1 massless.
void Chain(Eigen::MatrixXd* k, Eigen::MatrixXd* m) {
  *k = Eigen::MatrixXd::Zero(5, 5);
  for (int i = 0; i < 5; ++i) {
    (*k)(i, i) = i < 4 ? 2000.0 : 1000.0;
    if (i > 0) (*k)(i, i - 1) = (*k)(i - 1, i) = -1000.0;
  }
  *m = Eigen::Vector<double, 5>(0.0, 1.0, 1.0, 1.0, 1.0).asDiagonal();
}

TEST(SemidefiniteMass, ReducedEigenvaluesDropTheInfiniteOnes) {
  Eigen::MatrixXd k, m;
  Chain(&k, &m);
  const Eigen::VectorXd lambda = ReducedEigenvalues(k, m);
  ASSERT_EQ(lambda.size(), 4);  // 5 DOFs, one without mass
  // Independent route: condense the massless DOF statically, then a standard eigenproblem.
  const Eigen::MatrixXd kc = k.bottomRightCorner(4, 4) -
                             k.block(1, 0, 4, 1) * k.block(0, 1, 1, 4) / k(0, 0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(kc);
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(lambda[j], es.eigenvalues()[j], 1e-9 * es.eigenvalues()[j]);
  EXPECT_NEAR(std::sqrt(lambda[0]) / (2 * M_PI), 1.452462941099621, 1e-9);
}

TEST(SemidefiniteMass, CraigBamptonWithAMasslessBoundaryNodeIsFiniteAndExact) {
  Eigen::MatrixXd k, m;
  Chain(&k, &m);
  CraigBamptonOptions opt;
  opt.num_modes = 3;
  CraigBamptonSummary s;
  const ReducedModel red = ReduceCraigBampton(k.sparseView(), m.sparseView(), {0, 1}, opt, &s);
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
  EXPECT_TRUE(red.stiffness.allFinite() && red.mass.allFinite());
  const Eigen::VectorXd full = ReducedEigenvalues(k, m), reduced = ReducedEigenvalues(red.stiffness, red.mass);
  ASSERT_EQ(reduced.size(), full.size());  // all interior modes kept: the same finite spectrum
  for (int j = 0; j < full.size(); ++j) EXPECT_NEAR(reduced[j], full[j], 1e-9 * full[j]);
}

TEST(SemidefiniteMass, ANanCheckFailsTheRun) {
  CraigBamptonChecks c;
  c.modal_mass = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(c.Max()));  // std::max would have dropped it
  EXPECT_FALSE(c.Max() <= 1e-8);
  CraigBamptonChecks ok;
  ok.eigen_residual = 3e-12;
  EXPECT_EQ(ok.Max(), 3e-12);
}

// Issue 9, defect 6 (cutoff part): a cutoff above (nearly) the whole spectrum, on an interior
// too large for the dense path, with massless interior DOFs (fewer finite modes than DOFs):
// the ARPACK search finishes with the dense solver and keeps every finite mode, instead of
// running for minutes or stopping with dsaupd info 3.
TEST(SemidefiniteMass, CutoffAboveTheSpectrumFinishesDensely) {
  const int n = 300;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n), m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) = i + 1 < n ? 2000.0 : 1000.0;
    if (i > 0) k(i, i - 1) = k(i - 1, i) = -1000.0;
    m(i, i) = i % 10 == 5 ? 0.0 : 1.0;  // 30 massless DOFs
  }
  CraigBamptonOptions opt;
  opt.cutoff_hz = 1e6;  // above every finite mode
  opt.dense_eigen_max_size = 20;
  CraigBamptonSummary s;
  const ReducedModel red = ReduceCraigBampton(k.sparseView(), m.sparseView(), {0}, opt, &s);
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
  EXPECT_TRUE(s.dense_eigensolver);
  EXPECT_EQ(static_cast<int>(s.frequencies_hz.size()), n - 1 - 30);  // every finite interior mode
  EXPECT_TRUE(red.stiffness.allFinite() && red.mass.allFinite());
  // All finite modes kept: the reduced spectrum is the full one.
  const Eigen::VectorXd full = ReducedEigenvalues(k, m), reduced = ReducedEigenvalues(red.stiffness, red.mass);
  ASSERT_EQ(reduced.size(), full.size());
  for (int j = 0; j < full.size(); j += 25) EXPECT_NEAR(reduced[j], full[j], 1e-7 * full[j]);
}

}  // namespace
}  // namespace fricrom
