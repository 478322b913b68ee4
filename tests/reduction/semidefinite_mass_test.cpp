// Issue 9, defect 6: positive semi-definite mass (massless DOFs) in the Craig-Bampton route, and
// checks that fail on any non-finite value.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
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
  const Eigen::MatrixXd kc =
      k.bottomRightCorner(4, 4) - k.block(1, 0, 4, 1) * k.block(0, 1, 1, 4) / k(0, 0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(kc);
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(lambda[j], es.eigenvalues()[j], 1e-9 * es.eigenvalues()[j]);
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
  const Eigen::VectorXd full = ReducedEigenvalues(k, m),
                        reduced = ReducedEigenvalues(red.stiffness, red.mass);
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
  const Eigen::VectorXd full = ReducedEigenvalues(k, m),
                        reduced = ReducedEigenvalues(red.stiffness, red.mass);
  ASSERT_EQ(reduced.size(), full.size());
  for (int j = 0; j < full.size(); j += 25) EXPECT_NEAR(reduced[j], full[j], 1e-7 * full[j]);
}

// ---- The C3D20R beam of tests/data/c3d20r_beam (ccx MATRIXSTORAGE, M only semi-definite).

struct Beam {
  FeModel model;
  const FeMatrix* k = nullptr;
  const FeMatrix* m = nullptr;
};

Beam ReadBeam() {
  Beam b;
  b.model = ReadFe(std::string(FRICROM_SOURCE_DIR) + "/tests/data/c3d20r_beam/beam.inp");
  b.k = b.model.Find("STIFFNESS");
  b.m = b.model.Find("MASS");
  return b;
}

// Independent reference for K x = lambda M x with a singular M: in the eigenbasis of M, the
// massless directions carry no inertia and are condensed statically; the rest is a standard
// eigenproblem. Returns the finite eigenvalues, ascending.
Eigen::VectorXd CondensedEigenvalues(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                                     int* null_dim) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> em(m);
  const Eigen::VectorXd mu = em.eigenvalues();
  const double tol = 1e-12 * mu.cwiseAbs().maxCoeff();
  int n0 = 0;
  while (n0 < mu.size() && mu(n0) < tol) ++n0;
  *null_dim = n0;
  const Eigen::Index nr = mu.size() - n0;
  const Eigen::MatrixXd v = em.eigenvectors();
  const Eigen::MatrixXd kt = v.transpose() * k * v;
  const Eigen::MatrixXd k00 = kt.topLeftCorner(n0, n0), k0r = kt.topRightCorner(n0, nr);
  const Eigen::MatrixXd kc = kt.bottomRightCorner(nr, nr) - k0r.transpose() * k00.ldlt().solve(k0r);
  const Eigen::VectorXd s = mu.tail(nr).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd a = s.asDiagonal() * kc * s.asDiagonal();
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (a + a.transpose())).eigenvalues();
}

TEST(SemidefiniteMass, C3D20RBeamFullModelModesThroughArpackAndDense) {
  const Beam b = ReadBeam();
  ASSERT_TRUE(b.k && b.m);
  ASSERT_EQ(b.k->rows, 114);
  int null_dim = 0;
  const Eigen::VectorXd ref =
      CondensedEigenvalues(Eigen::MatrixXd(b.k->real), Eigen::MatrixXd(b.m->real), &null_dim);
  EXPECT_EQ(null_dim, 30);  // the reduced-integration mass has 30 null directions here
  EXPECT_EQ(ref.size(), 114 - 30);
  for (const int dense_max : {0, 1000}) {  // ARPACK shift-invert (mode 3), then dense
    ModalSolveOptions mo;
    mo.num_modes = 10;
    mo.dense_max_size = dense_max;
    const ModalSolveResult r = SolveLowestModes(b.k->real, b.m->real, mo);
    ASSERT_EQ(r.status, ModalSolveStatus::kSuccess) << r.message;
    ASSERT_EQ(r.lambda.size(), 10);
    for (int j = 0; j < 10; ++j)
      EXPECT_NEAR(r.lambda(j) / ref(j), 1.0, 1e-9) << dense_max << " " << j;
    EXPECT_TRUE(r.modes.allFinite());
  }
  // Cantilever 10 x 10 x 100 mm steel, Euler-Bernoulli: 1.875^2/(2 pi) sqrt(EI/(rho A L^4)) = 834
  // Hz; two quadratic elements along the beam are a little stiffer (and shear makes it softer).
  EXPECT_NEAR(std::sqrt(ref(0)) / (2 * M_PI), 834.0, 0.03 * 834.0);
}

TEST(SemidefiniteMass, C3D20RBeamCraigBamptonOntoTheTipIsFiniteAndExact) {
  const Beam b = ReadBeam();
  const BoundarySelection tip = SelectBoundaryDofs(b.model, *b.k, {"TIP"});
  ASSERT_EQ(tip.indices.size(), 39u);
  CraigBamptonOptions opt;
  opt.num_modes = 100;  // more than the 75 - 15 = 60 finite interior modes
  CraigBamptonSummary s;
  const ReducedModel red = ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &s);
  ASSERT_EQ(s.status, CraigBamptonStatus::kSuccess) << s.BriefReport();
  EXPECT_EQ(s.modes, 60);
  EXPECT_NE(s.message.find("clamped to 60"), std::string::npos) << s.message;
  EXPECT_TRUE(red.stiffness.allFinite() && red.mass.allFinite());
  EXPECT_LE(s.checks.Max(), 1e-8);
  // Every finite interior mode kept: the reduced model has the full model's finite spectrum.
  int null_dim = 0;
  const Eigen::VectorXd ref =
      CondensedEigenvalues(Eigen::MatrixXd(b.k->real), Eigen::MatrixXd(b.m->real), &null_dim);
  const Eigen::VectorXd lr = ReducedEigenvalues(red.stiffness, red.mass);
  ASSERT_EQ(lr.size(), ref.size());
  for (int j = 0; j < ref.size(); ++j) EXPECT_NEAR(lr(j) / ref(j), 1.0, 1e-7) << j;
}

TEST(SemidefiniteMass, C3D20RBeamArpackInteriorModesAndSylvesterCutoff) {
  const Beam b = ReadBeam();
  const BoundarySelection tip = SelectBoundaryDofs(b.model, *b.k, {"TIP"});
  CraigBamptonOptions opt;
  opt.num_modes = 8;
  opt.dense_eigen_max_size = 0;  // ARPACK shift-invert with the singular M_ii
  CraigBamptonSummary sa, sd;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &sa);
  ASSERT_EQ(sa.status, CraigBamptonStatus::kSuccess) << sa.BriefReport();
  EXPECT_FALSE(sa.dense_eigensolver);
  opt.dense_eigen_max_size = 1000;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &sd);
  ASSERT_EQ(sd.status, CraigBamptonStatus::kSuccess) << sd.BriefReport();
  for (int j = 0; j < 8; ++j) EXPECT_NEAR(sa.frequencies_hz[j] / sd.frequencies_hz[j], 1.0, 1e-9);
  EXPECT_LE(sa.checks.eigen_residual, 1e-10);

  // Cutoff between interior modes 14 and 15: a first batch of 4, then the Sylvester count at the
  // cutoff says how many modes to ask for (one ARPACK run more, not a doubling search).
  CraigBamptonSummary all;
  opt.num_modes = 60;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &all);
  ASSERT_EQ(all.modes, 60);
  opt.cutoff_hz = 0.5 * (all.frequencies_hz[13] + all.frequencies_hz[14]);
  opt.num_modes = 4;
  opt.dense_eigen_max_size = 0;
  CraigBamptonSummary sc;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &sc);
  ASSERT_EQ(sc.status, CraigBamptonStatus::kSuccess) << sc.BriefReport();
  EXPECT_FALSE(sc.dense_eigensolver);
  EXPECT_EQ(sc.eigen_batches, 2);
  ASSERT_EQ(sc.modes, 14);
  for (int j = 0; j < 14; ++j) EXPECT_NEAR(sc.frequencies_hz[j] / all.frequencies_hz[j], 1.0, 1e-9);
}

// A 2 x 2 x 6 C3D20R beam (540 DOFs, 477 interior, 90 of them massless directions), made by
// gen_beam.py and ccx at test time (an 800 KB model is too large to keep). 60 interior modes by
// Lanczos: ARPACK mode 3 in the M-inner product (the code before issue 9) "converged" to 60 wrong
// eigenvalues, the lowest -1.06e10 (ghosts from null-space components the semi-definite M cannot
// see); Lanczos on the Cholesky-transformed operator agrees with the dense solver.
TEST(SemidefiniteMass, C3D20RBeamLanczosHasNoGhostModes) {
  if (std::system("command -v ccx > /dev/null 2>&1") != 0) GTEST_SKIP() << "ccx not installed";
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("fricrom_c3d20r_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string src = std::string(FRICROM_SOURCE_DIR) + "/tests/data/c3d20r_beam/gen_beam.py";
  const std::string cmd = "cd '" + dir.string() + "' && /usr/bin/python3 '" + src +
                          "' 2 2 6 0.01 0.01 0.1 > b.inp && ccx b > ccx.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  Beam b;
  b.model = ReadFe((dir / "b.inp").string());
  std::filesystem::remove_all(dir);
  b.k = b.model.Find("STIFFNESS");
  b.m = b.model.Find("MASS");
  ASSERT_EQ(b.k->rows, 540);
  const BoundarySelection tip = SelectBoundaryDofs(b.model, *b.k, {"TIP"});
  CraigBamptonOptions opt;
  opt.num_modes = 60;
  opt.dense_eigen_max_size = 0;
  CraigBamptonSummary sa, sd;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &sa);
  ASSERT_EQ(sa.status, CraigBamptonStatus::kSuccess) << sa.BriefReport();
  EXPECT_FALSE(sa.dense_eigensolver);
  opt.dense_eigen_max_size = 1000;
  ReduceCraigBampton(b.k->real, b.m->real, tip.indices, opt, &sd);
  ASSERT_EQ(sd.status, CraigBamptonStatus::kSuccess) << sd.BriefReport();
  ASSERT_EQ(sa.modes, 60);
  for (int j = 0; j < 60; ++j) {
    EXPECT_NEAR(sa.frequencies_hz[j] / sd.frequencies_hz[j], 1.0, 1e-9) << j;
  }
  EXPECT_LE(sa.checks.eigen_residual, 1e-10);
}

// A cutoff that needs most of a large interior's spectrum (7000 DOFs, beyond the dense limit):
// the Sylvester count says so at once, and the run stops saying why and what to do instead of
// running ARPACK for minutes (issue 9: dsaupd info = 3 after 49 s).
TEST(SemidefiniteMass, CutoffBeyondWhatCanBeSolvedStopsAtOnceSayingWhy) {
  const int n = 7001;
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int i = 0; i < n; ++i) {
    tk.emplace_back(i, i, i + 1 < n ? 2000.0 : 1000.0);
    if (i > 0) {
      tk.emplace_back(i, i - 1, -1000.0);
      tk.emplace_back(i - 1, i, -1000.0);
    }
    tm.emplace_back(i, i, i % 10 == 5 ? 0.0 : 1.0);
  }
  Eigen::SparseMatrix<double> k(n, n), m(n, n);
  k.setFromTriplets(tk.begin(), tk.end());
  m.setFromTriplets(tm.begin(), tm.end());
  CraigBamptonOptions opt;
  opt.cutoff_hz = 8.0;  // lambda_cut = 2527: most of the chain's spectrum (max ~4000)
  CraigBamptonSummary s;
  const ReducedModel red = ReduceCraigBampton(k, m, {0}, opt, &s);
  EXPECT_EQ(s.status, CraigBamptonStatus::kEigenNotConverged) << s.BriefReport();
  EXPECT_EQ(red.stiffness.size(), 0);
  EXPECT_NE(s.message.find("interior modes lie below the cutoff 8 Hz (Sylvester count)"),
            std::string::npos)
      << s.message;
  EXPECT_NE(s.message.find("lower the cutoff"), std::string::npos) << s.message;
  EXPECT_EQ(s.eigen_batches, 1);  // one batch, then the count: no doubling search
  EXPECT_LT(s.wall_s, 10.0);
}

TEST(SemidefiniteMass, NonFiniteInputIsRejectedNotReduced) {
  Eigen::MatrixXd k, m;
  Chain(&k, &m);
  m(3, 3) = std::numeric_limits<double>::quiet_NaN();
  CraigBamptonSummary s;
  try {
    ReduceCraigBampton(k.sparseView(), m.sparseView(), {0}, CraigBamptonOptions{}, &s);
    FAIL() << "a NaN in M was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("M holds a non-finite value at row 4"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(SolveLowestModes(k.sparseView(), m.sparseView(), ModalSolveOptions{}),
               std::invalid_argument);
  EXPECT_THROW(ReducedEigenvalues(k, m), std::invalid_argument);
  EXPECT_TRUE(std::isnan(NanMax(1.0, std::nan(""))) && std::isnan(NanMax(std::nan(""), 1.0)));
  EXPECT_EQ(NanMax(1.0, 2.0), 2.0);
}

}  // namespace
}  // namespace fricrom
