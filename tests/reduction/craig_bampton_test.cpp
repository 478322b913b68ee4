// Tests of ReduceCraigBampton (src/reduction): an exact small case against a dense T^T K T, a
// 2000-DOF sparse grid against the full model's eigenvalues, a free-free body with a negative
// shift, ARPACK against the dense path, and caller misuse.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // GCC 12 false positive inside Eigen
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/reduction.h"
#include "fricrom/units.h"

extern "C" void dsyevd_(const char* jobz, const char* uplo, const int* n, double* a, const int* lda,
                        double* w, double* work, const int* lwork, int* iwork, const int* liwork,
                        int* info, std::size_t, std::size_t);

namespace fricrom {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

struct KM {
  SpMat k, m;
};

void AddSpring(std::vector<Eigen::Triplet<double>>* t, int a, int b, double k) {
  t->emplace_back(a, a, k);
  t->emplace_back(b, b, k);
  t->emplace_back(a, b, -k);
  t->emplace_back(b, a, -k);
}

// Chain of n masses, springs between neighbours, grounded at DOF 0 (and n-1 if both_ends).
KM Chain(int n, bool both_ends) {
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int i = 0; i + 1 < n; ++i) AddSpring(&tk, i, i + 1, 1000.0 * (1.0 + 0.3 * i));
  tk.emplace_back(0, 0, 500.0);
  if (both_ends) tk.emplace_back(n - 1, n - 1, 800.0);
  for (int i = 0; i < n; ++i) tm.emplace_back(i, i, 1.0 + 0.25 * i);
  KM out;
  out.k.resize(n, n);
  out.k.setFromTriplets(tk.begin(), tk.end());
  out.m.resize(n, n);
  out.m.setFromTriplets(tm.begin(), tm.end());
  return out;
}

// nx x ny grid, one DOF per node, springs to the 4 neighbours (deterministically varying
// stiffness), lumped mass; ground springs on the column x = 0 if grounded.
KM Grid(int nx, int ny, bool grounded) {
  const int n = nx * ny;
  auto id = [&](int x, int y) { return y * nx + x; };
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      const double var = 1.0 + 0.2 * std::sin(0.7 * x + 1.3 * y);
      if (x + 1 < nx) AddSpring(&tk, id(x, y), id(x + 1, y), 1.0e4 * var);
      if (y + 1 < ny) AddSpring(&tk, id(x, y), id(x, y + 1), 0.8e4 * var);
      if (grounded && x == 0) tk.emplace_back(id(x, y), id(x, y), 2.0e4);
      tm.emplace_back(id(x, y), id(x, y), 0.01 * (1.0 + 0.1 * std::cos(0.9 * x - 0.4 * y)));
    }
  }
  KM out;
  out.k.resize(n, n);
  out.k.setFromTriplets(tk.begin(), tk.end());
  out.m.resize(n, n);
  out.m.setFromTriplets(tm.begin(), tm.end());
  return out;
}

// Eigenvalues (ascending) of a symmetric matrix (lower triangle read) by LAPACK's dsyevd: the
// dense references of the n = 2000 grid, 10x faster than Eigen's solver and not instrumented in
// the sanitizer build (Eigen's took 18 of its 20 s there). Empty if LAPACK fails.
Eigen::VectorXd SymmetricEigenvalues(Eigen::MatrixXd a) {
  const int n = static_cast<int>(a.rows());
  Eigen::VectorXd w(n);
  int info = 0, lwork = -1, liwork = -1, iwork_query = 0;
  double work_query = 0.0;
  dsyevd_("N", "L", &n, a.data(), &n, w.data(), &work_query, &lwork, &iwork_query, &liwork, &info,
          1, 1);
  if (info != 0) return {};
  lwork = static_cast<int>(work_query);
  liwork = iwork_query;
  std::vector<double> work(static_cast<std::size_t>(lwork));
  std::vector<int> iwork(static_cast<std::size_t>(liwork));
  dsyevd_("N", "L", &n, a.data(), &n, w.data(), work.data(), &lwork, iwork.data(), &liwork, &info,
          1, 1);
  if (info != 0) return {};
  return w;
}

// Eigenvalues (ascending) of K x = lambda M x, M diagonal positive: M^-1/2 K M^-1/2.
Eigen::VectorXd LumpedEigenvalues(const SpMat& k, const SpMat& m) {
  const Eigen::VectorXd s = Eigen::VectorXd(m.diagonal()).cwiseSqrt().cwiseInverse();
  return SymmetricEigenvalues(s.asDiagonal() * Eigen::MatrixXd(k) * s.asDiagonal());
}

Eigen::VectorXd DenseGeneralisedEigenvalues(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(k, m, Eigen::EigenvaluesOnly);
  return es.eigenvalues();
}

double ToHz(double lambda) { return std::sqrt(std::max(lambda, 0.0)) / kTwoPi; }

// (1) Exact small case: 6-DOF chain, boundary {4, 1}, all 4 interior modes kept.
TEST(CraigBampton, SmallChainMatchesDenseTransformationAndFullEigenvalues) {
  const KM km = Chain(6, true);
  const std::vector<int> boundary = {4, 1};
  CraigBamptonOptions opt;
  opt.num_modes = 4;
  CraigBamptonSummary sum;
  const ReducedModel red = ReduceCraigBampton(km.k, km.m, boundary, opt, &sum);
  ASSERT_EQ(sum.status, CraigBamptonStatus::kSuccess) << sum.BriefReport();
  ASSERT_EQ(red.stiffness.rows(), 6);
  EXPECT_EQ(sum.modes, 4);
  EXPECT_TRUE(sum.dense_eigensolver);
  EXPECT_EQ(red.boundary_dofs, boundary);
  EXPECT_EQ(red.interior_dofs, (std::vector<int>{0, 2, 3, 5}));

  // Full and reduced eigenvalues agree exactly (T is square and invertible).
  const Eigen::VectorXd full =
      DenseGeneralisedEigenvalues(Eigen::MatrixXd(km.k), Eigen::MatrixXd(km.m));
  const Eigen::VectorXd redl = DenseGeneralisedEigenvalues(red.stiffness, red.mass);
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(redl(j) / full(j), 1.0, 1e-10) << j;

  // Independent dense T: permute [b | i], Psi = -Kii^-1 Kib, Phi mass-normalised.
  const std::vector<int> order = {4, 1, 0, 2, 3, 5};
  Eigen::MatrixXd kp(6, 6), mp(6, 6);
  const Eigen::MatrixXd kd(km.k), md(km.m);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) {
      kp(r, c) = kd(order[r], order[c]);
      mp(r, c) = md(order[r], order[c]);
    }
  const Eigen::MatrixXd kii = kp.bottomRightCorner(4, 4), mii = mp.bottomRightCorner(4, 4);
  const Eigen::MatrixXd psi = -kii.llt().solve(kp.bottomLeftCorner(4, 2));
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(kii, mii);
  Eigen::MatrixXd phi = es.eigenvectors();  // mass-normalised, ascending
  for (int j = 0; j < 4; ++j) {             // align signs with the library's modes
    const double d = phi.col(j).dot(mii * red.normal_modes.col(j));
    EXPECT_NEAR(std::abs(d), 1.0, 1e-10);
    if (d < 0) phi.col(j) *= -1.0;
    EXPECT_NEAR(red.modal_frequencies_hz(j), ToHz(es.eigenvalues()(j)),
                1e-10 * ToHz(es.eigenvalues()(j)));
  }
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(6, 6);
  t.topLeftCorner(2, 2).setIdentity();
  t.bottomLeftCorner(4, 2) = psi;
  t.bottomRightCorner(4, 4) = phi;
  const Eigen::MatrixXd kr = t.transpose() * kp * t, mr = t.transpose() * mp * t;
  EXPECT_LE((kr - red.stiffness).cwiseAbs().maxCoeff(), 1e-10 * kr.cwiseAbs().maxCoeff());
  EXPECT_LE((mr - red.mass).cwiseAbs().maxCoeff(), 1e-10 * mr.cwiseAbs().maxCoeff());
  EXPECT_LE(sum.checks.Max(), 1e-10);
  EXPECT_LE((red.constraint_modes - psi).cwiseAbs().maxCoeff(), 1e-12);
}

// Truncated small case: still equals the dense T^T K T built from the kept modes.
TEST(CraigBampton, TruncatedChainMatchesDenseTransformation) {
  const KM km = Chain(12, false);
  CraigBamptonOptions opt;
  opt.num_modes = 3;
  CraigBamptonSummary sum;
  const std::vector<int> boundary = {11, 5};
  const ReducedModel red = ReduceCraigBampton(km.k, km.m, boundary, opt, &sum);
  ASSERT_TRUE(sum.IsSolutionUsable()) << sum.BriefReport();
  ASSERT_EQ(red.stiffness.rows(), 5);
  // T in full-model order: u = T [u_b; q].
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(12, 5);
  for (int j = 0; j < 2; ++j) t(boundary[j], j) = 1.0;
  for (size_t r = 0; r < red.interior_dofs.size(); ++r) {
    t.row(red.interior_dofs[r]).head(2) = red.constraint_modes.row(static_cast<Eigen::Index>(r));
    t.row(red.interior_dofs[r]).tail(3) = red.normal_modes.row(static_cast<Eigen::Index>(r));
  }
  const Eigen::MatrixXd kr = t.transpose() * Eigen::MatrixXd(km.k) * t;
  const Eigen::MatrixXd mr = t.transpose() * Eigen::MatrixXd(km.m) * t;
  EXPECT_LE((kr - red.stiffness).cwiseAbs().maxCoeff(), 1e-10 * kr.cwiseAbs().maxCoeff());
  EXPECT_LE((mr - red.mass).cwiseAbs().maxCoeff(), 1e-10 * mr.cwiseAbs().maxCoeff());
  // Reduced eigenvalues are upper bounds of the full ones (Rayleigh-Ritz).
  const Eigen::VectorXd full =
      DenseGeneralisedEigenvalues(Eigen::MatrixXd(km.k), Eigen::MatrixXd(km.m));
  const Eigen::VectorXd redl = DenseGeneralisedEigenvalues(red.stiffness, red.mass);
  for (int j = 0; j < 5; ++j) EXPECT_GE(redl(j), full(j) * (1.0 - 1e-12)) << j;
}

// (2) 2000-DOF strip (200 x 10 grid), grounded at x = 0, boundary = the free edge x = 199;
// fixed-interface modes up to a cutoff through ARPACK in growing batches.
TEST(CraigBampton, SparseGridLowModesMatchFullModel) {
  const int nx = 200, ny = 10;
  const KM km = Grid(nx, ny, true);
  std::vector<int> boundary;
  for (int y = 0; y < ny; ++y) boundary.push_back(y * nx + nx - 1);  // edge x = nx-1
  CraigBamptonOptions opt;
  opt.num_modes = 8;     // first batch
  opt.cutoff_hz = 50.0;  // 29 modes
  CraigBamptonSummary sum;
  const ReducedModel red = ReduceCraigBampton(km.k, km.m, boundary, opt, &sum);
  std::cout << sum.BriefReport() << "\n";
  ASSERT_EQ(sum.status, CraigBamptonStatus::kSuccess) << sum.BriefReport();
  EXPECT_FALSE(sum.dense_eigensolver);
  EXPECT_GE(sum.eigen_batches, 2);  // had to grow past the first batch
  EXPECT_GE(sum.modes, 10);
  EXPECT_LE(sum.modes, 30);
  EXPECT_LE(sum.frequencies_hz.back(), opt.cutoff_hz);
  EXPECT_LE(sum.checks.stiffness_coupling, 1e-10);
  EXPECT_LE(sum.checks.modal_mass, 1e-10);
  EXPECT_LE(sum.checks.modal_stiffness, 1e-10);
  EXPECT_LE(sum.checks.stiffness_symmetry, 1e-12);
  EXPECT_LE(sum.checks.eigen_residual, 1e-10);

  // Completeness of the cutoff search: the fixed-interface spectrum (dense) below the cutoff.
  {
    SpMat kii(km.k), mii(km.m);
    std::vector<int> interior;
    for (int i = 0; i < nx * ny; ++i)
      if (i % nx != nx - 1) interior.push_back(i);
    Eigen::MatrixXd kd(km.k), md(km.m);
    const Eigen::Index ni = static_cast<Eigen::Index>(interior.size());
    Eigen::MatrixXd kid(ni, ni);
    Eigen::VectorXd mid(ni);
    for (Eigen::Index r = 0; r < ni; ++r) {
      mid(r) = md(interior[r], interior[r]);
      for (Eigen::Index c = 0; c < ni; ++c) kid(r, c) = kd(interior[r], interior[c]);
    }
    const Eigen::VectorXd s = mid.cwiseSqrt().cwiseInverse();
    const Eigen::VectorXd dense = SymmetricEigenvalues(s.asDiagonal() * kid * s.asDiagonal());
    ASSERT_EQ(dense.size(), ni);
    int below = 0;
    for (Eigen::Index j = 0; j < ni; ++j) below += ToHz(dense(j)) <= opt.cutoff_hz;
    EXPECT_EQ(below, sum.modes);
    double worst = 0;
    for (int j = 0; j < sum.modes; ++j)
      worst = std::max(worst, std::abs(sum.frequencies_hz[j] / ToHz(dense(j)) - 1.0));
    std::cout << "fixed-interface frequencies vs dense: max rel err " << worst << "\n";
    EXPECT_LE(worst, 1e-10);
  }

  // Lowest system modes: reduced vs full. Craig-Bampton is a Rayleigh-Ritz method: reduced
  // eigenvalues are upper bounds, and the relative error grows like (f / f_cut)^2 (measured
  // coefficient 6.5e-3 for this model), so only the lowest mode reaches ~4e-6 with 29 modes.
  const Eigen::VectorXd full = LumpedEigenvalues(km.k, km.m);
  const Eigen::VectorXd redl = DenseGeneralisedEigenvalues(red.stiffness, red.mass);
  const double fq = sum.frequencies_hz.back();
  int compared = 0;
  for (int j = 0; j < redl.size(); ++j) {
    const double f = ToHz(full(j));
    if (f > 0.5 * fq) break;
    const double rel = redl(j) / full(j) - 1.0;
    std::cout << "system mode " << j << ": " << f << " Hz, f/f_q " << f / fq
              << ", rel eigenvalue error " << rel << "\n";
    EXPECT_GE(rel, -1e-12) << j;                      // upper bound
    EXPECT_LE(rel, 1e-2 * (f / fq) * (f / fq)) << j;  // quadratic convergence
    ++compared;
  }
  EXPECT_GE(compared, 5);
  EXPECT_LE(redl(0) / full(0) - 1.0, 1e-5);

  // Doubling the modal basis (cutoff 100 Hz) cuts the low-mode errors about fourfold.
  opt.cutoff_hz = 100.0;
  CraigBamptonSummary sum2;
  const ReducedModel red2 = ReduceCraigBampton(km.k, km.m, boundary, opt, &sum2);
  std::cout << sum2.BriefReport() << "\n";
  ASSERT_TRUE(sum2.IsSolutionUsable());
  const Eigen::VectorXd redl2 = DenseGeneralisedEigenvalues(red2.stiffness, red2.mass);
  for (int j = 0; j < 3; ++j) {
    const double e1 = redl(j) / full(j) - 1.0, e2 = redl2(j) / full(j) - 1.0;
    std::cout << "mode " << j << " error 29 modes " << e1 << ", " << sum2.modes << " modes " << e2
              << "\n";
    EXPECT_LT(e2, 0.4 * e1) << j;
  }
}

// ARPACK and the dense path give the same reduction (up to mode signs).
TEST(CraigBampton, ArpackMatchesDensePath) {
  const KM km = Grid(20, 15, true);
  const std::vector<int> boundary = {19, 139, 299, 150};
  CraigBamptonOptions opt;
  opt.num_modes = 12;
  opt.dense_eigen_max_size = 0;
  CraigBamptonSummary sa, sd;
  const ReducedModel ra = ReduceCraigBampton(km.k, km.m, boundary, opt, &sa);
  opt.dense_eigen_max_size = 10000;
  const ReducedModel rd = ReduceCraigBampton(km.k, km.m, boundary, opt, &sd);
  ASSERT_TRUE(sa.IsSolutionUsable()) << sa.BriefReport();
  ASSERT_TRUE(sd.IsSolutionUsable()) << sd.BriefReport();
  EXPECT_FALSE(sa.dense_eigensolver);
  EXPECT_TRUE(sd.dense_eigensolver);
  for (int j = 0; j < 12; ++j)
    EXPECT_NEAR(sa.frequencies_hz[j], sd.frequencies_hz[j], 1e-10 * sd.frequencies_hz[j]);
  const Eigen::VectorXd la = DenseGeneralisedEigenvalues(ra.stiffness, ra.mass);
  const Eigen::VectorXd ld = DenseGeneralisedEigenvalues(rd.stiffness, rd.mass);
  for (int j = 0; j < la.size(); ++j) EXPECT_NEAR(la(j) / ld(j), 1.0, 1e-10) << j;
  EXPECT_LE(
      (ra.stiffness.topLeftCorner(4, 4) - rd.stiffness.topLeftCorner(4, 4)).cwiseAbs().maxCoeff(),
      1e-10 * rd.stiffness.cwiseAbs().maxCoeff());
}

// (3) Free-free body: a negative shift makes the interior factorable; rigid modes appear.
TEST(CraigBampton, FreeFreeBodyWithNegativeShift) {
  const KM km = Grid(30, 20, false);  // 600 DOFs, no grounding: one rigid-body mode
  const Eigen::VectorXd full = LumpedEigenvalues(km.k, km.m);
  ASSERT_LT(std::abs(full(0)), 1e-6 * full(1));

  CraigBamptonOptions opt;
  opt.num_modes = 10;
  opt.dense_eigen_max_size = 0;  // force ARPACK
  CraigBamptonSummary sum;
  // Empty boundary, shift 0: K itself is singular.
  ReducedModel red = ReduceCraigBampton(km.k, km.m, {}, opt, &sum);
  EXPECT_EQ(sum.status, CraigBamptonStatus::kFactorizationFailed);
  EXPECT_FALSE(sum.IsSolutionUsable());
  EXPECT_EQ(red.stiffness.size(), 0);
  EXPECT_NE(sum.message.find("positive definite"), std::string::npos) << sum.message;

  // Empty boundary (pure modal truncation of the free-free body), negative shift.
  opt.shift = -std::pow(kTwoPi * 1.0, 2);
  red = ReduceCraigBampton(km.k, km.m, {}, opt, &sum);
  ASSERT_EQ(sum.status, CraigBamptonStatus::kSuccess) << sum.BriefReport();
  ASSERT_EQ(sum.modes, 10);
  EXPECT_LT(sum.frequencies_hz[0], 1e-5 * sum.frequencies_hz[1]);  // rigid-body mode
  for (int j = 1; j < 10; ++j)
    EXPECT_NEAR(sum.frequencies_hz[j], ToHz(full(j)), 1e-9 * ToHz(full(j))) << j;

  // Boundary = 4 corners, the interior is grounded by them; the reduced model keeps the rigid
  // mode exactly (constraint modes reproduce it).
  const std::vector<int> corners = {0, 29, 570, 599};
  red = ReduceCraigBampton(km.k, km.m, corners, opt, &sum);
  ASSERT_EQ(sum.status, CraigBamptonStatus::kSuccess) << sum.BriefReport();
  const Eigen::VectorXd redl = DenseGeneralisedEigenvalues(red.stiffness, red.mass);
  EXPECT_LT(std::abs(redl(0)), 1e-8 * redl(1));
  EXPECT_NEAR(redl(1) / full(1), 1.0, 1e-3);  // truncated: Rayleigh-Ritz upper bound, close
  EXPECT_GE(redl(1), full(1) * (1 - 1e-12));
  // Rigid translation of the boundary gives zero reduced force.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(red.stiffness.rows());
  u.head(4).setOnes();
  EXPECT_LE((red.stiffness * u).cwiseAbs().maxCoeff(), 1e-8 * red.stiffness.cwiseAbs().maxCoeff());
}

// A boundary that does not ground the interior: K_ii singular, reported, not thrown.
TEST(CraigBampton, UngroundedInteriorReportsFactorizationFailure) {
  // Two disconnected chains; the boundary touches only the first.
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int i = 0; i < 3; ++i) AddSpring(&tk, i, i + 1, 100.0);
  for (int i = 4; i < 7; ++i) AddSpring(&tk, i, i + 1, 100.0);
  for (int i = 0; i < 8; ++i) tm.emplace_back(i, i, 1.0);
  SpMat k(8, 8), m(8, 8);
  k.setFromTriplets(tk.begin(), tk.end());
  m.setFromTriplets(tm.begin(), tm.end());
  CraigBamptonSummary sum;
  ReduceCraigBampton(k, m, {0}, CraigBamptonOptions{}, &sum);
  EXPECT_EQ(sum.status, CraigBamptonStatus::kFactorizationFailed);
  EXPECT_NE(sum.message.find("rigid-body"), std::string::npos) << sum.message;
}

// Cutoff above every interior mode and num_modes above the interior size are handled.
TEST(CraigBampton, ClampsModeCount) {
  const KM km = Chain(6, true);
  CraigBamptonOptions opt;
  opt.num_modes = 50;
  CraigBamptonSummary sum;
  ReducedModel red = ReduceCraigBampton(km.k, km.m, {0}, opt, &sum);
  ASSERT_TRUE(sum.IsSolutionUsable()) << sum.BriefReport();
  EXPECT_EQ(sum.modes, 5);
  EXPECT_NE(sum.message.find("clamped"), std::string::npos);
  opt.cutoff_hz = 1e6;
  red = ReduceCraigBampton(km.k, km.m, {0}, opt, &sum);
  ASSERT_TRUE(sum.IsSolutionUsable()) << sum.BriefReport();
  EXPECT_EQ(sum.modes, 5);
  opt.cutoff_hz = 1e-3;  // below every mode: static (Guyan) reduction
  red = ReduceCraigBampton(km.k, km.m, {0, 5}, opt, &sum);
  ASSERT_TRUE(sum.IsSolutionUsable()) << sum.BriefReport();
  EXPECT_EQ(sum.modes, 0);
  EXPECT_EQ(red.stiffness.rows(), 2);
}

// (4) Caller misuse throws std::invalid_argument.
TEST(CraigBampton, InvalidInputThrows) {
  const KM km = Chain(6, true);
  CraigBamptonOptions opt;
  CraigBamptonSummary sum;
  EXPECT_THROW(ReduceCraigBampton(km.k, km.m, {1, 1}, opt, &sum), std::invalid_argument);
  EXPECT_THROW(ReduceCraigBampton(km.k, km.m, {6}, opt, &sum), std::invalid_argument);
  EXPECT_THROW(ReduceCraigBampton(km.k, km.m, {-1}, opt, &sum), std::invalid_argument);
  EXPECT_THROW(ReduceCraigBampton(km.k, km.m, {1}, opt, nullptr), std::invalid_argument);
  SpMat m5(5, 5);
  EXPECT_THROW(ReduceCraigBampton(km.k, m5, {1}, opt, &sum), std::invalid_argument);
  SpMat rect(6, 5);
  EXPECT_THROW(ReduceCraigBampton(rect, rect, {1}, opt, &sum), std::invalid_argument);
  SpMat upper = km.k.triangularView<Eigen::Upper>();
  EXPECT_THROW(ReduceCraigBampton(upper, km.m, {1}, opt, &sum), std::invalid_argument);

  std::string err;
  opt.num_modes = 0;
  EXPECT_FALSE(opt.IsValid(&err));
  EXPECT_NE(err.find("num_modes"), std::string::npos);
  EXPECT_THROW(ReduceCraigBampton(km.k, km.m, {1}, opt, &sum), std::invalid_argument);
  opt = CraigBamptonOptions{};
  opt.shift = 1.0;
  EXPECT_FALSE(opt.IsValid(&err));
  EXPECT_NE(err.find("shift"), std::string::npos);
  opt = CraigBamptonOptions{};
  opt.cutoff_hz = -1.0;
  EXPECT_FALSE(opt.IsValid(&err));
  EXPECT_NE(err.find("cutoff_hz"), std::string::npos);
  EXPECT_TRUE(CraigBamptonOptions{}.IsValid(&err));
}

TEST(CraigBampton, StatusStrings) {
  EXPECT_STREQ(ToString(CraigBamptonStatus::kSuccess), "SUCCESS");
  EXPECT_STREQ(ToString(CraigBamptonStatus::kEigenNotConverged), "EIGEN_NOT_CONVERGED");
}

}  // namespace
}  // namespace fricrom
