// One sector in cyclic symmetry against the explicit ring of its N sectors: the same harmonic
// balance solutions (H = 1 and 3, stick and slip), the same linear frequencies per nodal
// diameter, exact derivatives of the cyclic contacts, and clear errors.
#include "fricrom/cyclic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/condensed_system.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/linear.h"
#include "fricrom/units.h"

namespace fricrom {
namespace {

// A blade (x, y) on its root spring and a damper (x, y) between it and the next sector's blade,
// in the sector's own frame; the next sector is this one rotated by 2π/N about z.
Model CyclicSector(int sectors, int engine_order) {
  const double pi = std::numbers::pi, beta = 2.0 * pi / sectors;
  Model m;
  m.dof_names = {"blade.x", "blade.y", "damper.x", "damper.y"};
  const double kb = std::pow(2.0 * pi * 100.0, 2), mb = 1.0, md = 0.05, kg = 1e2;
  m.mass = Eigen::Vector4d(mb, mb, md, md).asDiagonal();
  m.stiffness = Eigen::Vector4d(kb, 1.5 * kb, kg, kg).asDiagonal();
  m.damping = Eigen::Vector4d(2 * 0.005 * std::sqrt(kb * mb), 2 * 0.005 * std::sqrt(1.5 * kb * mb),
                              0.0, 0.0)
                  .asDiagonal();
  Contact left;
  left.name = "left";
  left.dofs_a = {2, 3};
  left.dofs_b = {0, 1};
  left.normal = Eigen::VectorXd{{0.6, 0.8}};
  left.tangent = Eigen::VectorXd{{0.8, -0.6}};
  left.kn = left.kt = 2e5;
  left.mu = 0.5;
  Contact right = left;
  right.name = "right";
  right.normal = Eigen::VectorXd{{-0.6, 0.8}};
  right.tangent = Eigen::VectorXd{{0.8, 0.6}};
  // Side B seen from this sector: Rᵀ d, R the rotation by β to the next sector's frame.
  const auto rotated_back = [beta](double x, double y) {
    return Eigen::VectorXd{
        {std::cos(beta) * x + std::sin(beta) * y, -std::sin(beta) * x + std::cos(beta) * y}};
  };
  right.normal_b = rotated_back(-0.6, 0.8);
  right.tangent_b = rotated_back(0.8, 0.6);
  m.cyclic.sectors = sectors;
  m.cyclic.engine_order = engine_order;
  right.phase_b = m.cyclic.phase();
  m.contacts = {left, right};
  // The damper's centrifugal load presses it into both platforms (along n_left + n_right).
  m.loads = {HarmonicLoad{0, Eigen::Vector4d(0.0, 0.0, 0.0, 40.0), Eigen::Vector4d::Zero()},
             HarmonicLoad{1, Eigen::Vector4d(12.0, 3.0, 0.0, 0.0), Eigen::Vector4d::Zero()}};
  m.response_dof = 0;
  m.free_dofs = {0, 1};
  return m;
}

TEST(Cyclic, SectorSolutionsAreTheRingSolutionsAtHarmonicsOneAndThree) {
  for (const int eo : {1, 2}) {
    const Model sector = CyclicSector(6, eo);
    const Model ring = ExpandCyclicRing(sector);
    for (const int harmonics : {1, 3}) {
      const HbmOptions options{harmonics, 96};  // a multiple of N: the delay is whole samples
      HbmSystem cyc(sector, options), full(ring, options);
      const Eigen::Vector2d alpha(0.3, -0.5);
      int slipping = 0;
      for (const double f : {80.0, 95.0, 100.0, 105.0, 120.0}) {
        const FrfPoint s = SolveAtFrequency(cyc, alpha, f, Eigen::VectorXd(), FrfOptions{});
        ASSERT_EQ(s.status, SolverStatus::kConverged)
            << "EO " << eo << " H " << harmonics << " " << f;
        // The sector's solution, spread over the ring, solves the ring's balance at the α that
        // start each sector's period at its instant of the wave ...
        const Eigen::VectorXd xr = SpreadOverRing(sector, s.x, harmonics);
        const Eigen::VectorXd ring_alpha =
            RingContactAlpha(sector, cyc.ContactHistories(s.x, kTwoPi * f, alpha), alpha);
        HbmEvaluation e;
        full.Evaluate(xr, kTwoPi * f, ring_alpha, HbmRequest{}, &e);
        EXPECT_LE(e.residual.norm(), 1e-9 * full.ResidualScale())
            << "EO " << eo << " H " << harmonics << " " << f;
        // ... and the ring solved on its own lands on it.
        const FrfPoint r = SolveAtFrequency(full, ring_alpha, f, Eigen::VectorXd(), FrfOptions{});
        ASSERT_EQ(r.status, SolverStatus::kConverged);
        EXPECT_LE((r.x - xr).norm(), 1e-8 * xr.norm())
            << "EO " << eo << " H " << harmonics << " " << f;
        EXPECT_NEAR(r.amplitude, s.amplitude, 1e-8 * s.amplitude);
        for (const ContactRegime regime : cyc.ContactRegimes(s.x, kTwoPi * f, alpha)) {
          slipping += regime != ContactRegime::kFullStick;
        }
      }
      EXPECT_GT(slipping, 0) << "the check needs contacts that slip, EO " << eo;
    }
  }
}

// The condensed balance of the sector (dense receptance per harmonic with the delayed rows)
// solves to the full sector balance's solution, and condenses it to a zero residual.
TEST(Cyclic, CondensedSectorReproducesTheFullSectorBalance) {
  for (const int eo : {1, 3}) {
    const Model sector = CyclicSector(6, eo);
    for (const int harmonics : {1, 3}) {
      const HbmOptions options{harmonics, 96};
      HbmSystem full(sector, options);
      CondensedSystem cond(sector, options);
      const Eigen::Vector2d alpha(-0.6, 0.8);
      for (const double f : {90.0, 100.0, 104.0, 110.0}) {
        const FrfPoint a = SolveAtFrequency(full, alpha, f, Eigen::VectorXd(), FrfOptions{});
        const FrfPoint b = SolveAtFrequency(cond, alpha, f, Eigen::VectorXd(), FrfOptions{});
        ASSERT_EQ(a.status, SolverStatus::kConverged) << eo << " " << harmonics << " " << f;
        ASSERT_EQ(b.status, SolverStatus::kConverged) << eo << " " << harmonics << " " << f;
        HbmEvaluation e;
        cond.Evaluate(cond.Condense(a.x), kTwoPi * f, alpha, HbmRequest{}, &e);
        EXPECT_LE(e.residual.norm(), 1e-9 * cond.ResidualScale())
            << eo << " " << harmonics << " " << f;
        const Eigen::VectorXd xb = cond.Recover(b.x, kTwoPi * f, alpha);
        EXPECT_LE((xb - a.x).norm(), 1e-9 * a.x.norm()) << eo << " " << harmonics << " " << f;
        EXPECT_NEAR(b.amplitude, a.amplitude, 1e-9 * a.amplitude);
      }
    }
  }
  HbmOptions modal{1, 96};
  modal.receptance = ReceptanceMethod::kModal;
  EXPECT_THROW(CondensedSystem(CyclicSector(6, 1), modal), std::invalid_argument);
}

// The sector's bounds are bounds over the travelling-wave states, a subset of the ring's states
// over α per sector: the ring's bounds contain them (the ring's search also starts from the
// sector's optima carried to the ring, so that the check does not hang on its multi-start).
TEST(Cyclic, SectorBoundsLieInsideTheRingBoundsOverAlphaPerSector) {
  const Model sector = CyclicSector(6, 1);
  const Model ring = ExpandCyclicRing(sector);
  const HbmOptions options{1, 96};
  HbmSystem cyc(sector, options), full(ring, options);
  const double f = 108.0, w = kTwoPi * f;  // past the peak: α moves the response there
  const BoundsResult s = ComputeBounds(cyc, f, BoundsOptions{});
  ASSERT_TRUE(s.IsUsable()) << s.BriefReport();
  EXPECT_LT(s.min.amplitude, 0.99 * s.max.amplitude) << "the check needs bounds that differ";
  BoundsOptions ring_options;
  ring_options.alpha_seeds = DefaultAlphaSeeds(static_cast<int>(ring.contacts.size()));
  for (const BoundSolution* b : {&s.min, &s.max}) {
    ring_options.alpha_seeds.push_back(
        RingContactAlpha(sector, cyc.ContactHistories(b->x, w, b->alpha), b->alpha));
  }
  const BoundsResult r = ComputeBounds(full, f, ring_options);
  ASSERT_TRUE(r.IsUsable()) << r.BriefReport();
  EXPECT_LE(r.min.amplitude, s.min.amplitude * (1 + 1e-8));
  EXPECT_GE(r.max.amplitude, s.max.amplitude * (1 - 1e-8));
  RecordProperty("sector_bounds_m",
                 std::to_string(s.min.amplitude) + " " + std::to_string(s.max.amplitude));
  RecordProperty("ring_bounds_m",
                 std::to_string(r.min.amplitude) + " " + std::to_string(r.max.amplitude));
  std::cout << "sector [" << s.min.amplitude << ", " << s.max.amplitude << "] m, ring over α per "
            << "sector [" << r.min.amplitude << ", " << r.max.amplitude << "] m at " << f
            << " Hz\n";
}

// Each nodal diameter's frequencies, counted twice for 0 < nd < N/2 (the two travelling
// directions), make up the ring's spectrum, with the cyclic contacts stuck and without contacts.
TEST(Cyclic, NaturalFrequenciesPerNodalDiameterMakeUpTheRingsSpectrum) {
  for (const int sectors : {5, 6}) {
    const Model sector = CyclicSector(sectors, 1);
    const Model ring = ExpandCyclicRing(sector);
    for (const bool stick : {true, false}) {
      Eigen::MatrixXd k = ring.stiffness;
      if (stick) k += ContactStickStiffness(ring);
      Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, ring.mass);
      std::vector<double> expected;
      for (int i = 0; i < eig.eigenvalues().size(); ++i) {
        expected.push_back(std::sqrt(std::max(eig.eigenvalues()[i], 0.0)) / kTwoPi);
      }
      std::vector<double> got;
      for (int nd = 0; nd <= sectors / 2; ++nd) {
        const Eigen::VectorXd f = CyclicNaturalFrequencies(sector, nd, stick);
        const int copies = (nd == 0 || 2 * nd == sectors) ? 1 : 2;
        for (int c = 0; c < copies; ++c) got.insert(got.end(), f.data(), f.data() + f.size());
      }
      std::sort(expected.begin(), expected.end());
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got.size(), expected.size());
      for (size_t i = 0; i < got.size(); ++i) {
        EXPECT_NEAR(got[i], expected[i], 1e-9 * std::max(1.0, expected[i])) << sectors << " " << i;
      }
    }
  }
}

// The cyclic contacts' Jacobians (∂R/∂x, ∂R/∂α) against central differences at a slipping state.
TEST(Cyclic, CyclicContactDerivativesMatchCentralDifferences) {
  const Model sector = CyclicSector(6, 2);
  const HbmOptions options{3, 64};
  HbmSystem cyc(sector, options);
  const Eigen::Vector2d alpha(0.2, -0.4);
  const double f = 100.0, w = kTwoPi * f;
  // The full-stick response, large enough for slip and lift-off, perturbed off its symmetry.
  const Eigen::VectorXd stick = cyc.StickLinearSolution(w);
  Eigen::VectorXd x = stick;
  for (int i = sector.num_dofs(); i < x.size(); ++i) x[i] *= 20.0;
  for (int i = 0; i < x.size(); ++i) x[i] += 0.05 * std::sin(1.3 * i + 0.2) * stick.norm();
  for (const ContactRegime r : cyc.ContactRegimes(x, w, alpha)) {
    EXPECT_TRUE(r == ContactRegime::kStickSlip || r == ContactRegime::kStickSlipLiftOff)
        << ToString(r);
  }
  HbmEvaluation e;
  cyc.Evaluate(x, w, alpha, HbmRequest{true, true, false}, &e);
  const double hx = 1e-7 * x.norm();
  double worst = 0.0;
  for (int j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += hx;
    xm[j] -= hx;
    HbmEvaluation ep, em;
    cyc.Evaluate(xp, w, alpha, HbmRequest{}, &ep);
    cyc.Evaluate(xm, w, alpha, HbmRequest{}, &em);
    const Eigen::VectorXd fd = (ep.residual - em.residual) / (2 * hx);
    worst =
        std::max(worst, (fd - e.jacobian.col(j)).norm() / std::max(1.0, e.jacobian.col(j).norm()));
  }
  EXPECT_LE(worst, 1e-4);
  for (int c = 0; c < 2; ++c) {
    Eigen::Vector2d ap = alpha, am = alpha;
    ap[c] += 1e-6;
    am[c] -= 1e-6;
    HbmEvaluation ep, em;
    cyc.Evaluate(x, w, ap, HbmRequest{}, &ep);
    cyc.Evaluate(x, w, am, HbmRequest{}, &em);
    const Eigen::VectorXd fd = (ep.residual - em.residual) / 2e-6;
    EXPECT_LE((fd - e.alpha_jacobian.col(c)).norm(), 1e-4 * std::max(1.0, fd.norm())) << c;
  }
}

TEST(Cyclic, InvalidCyclicModelsAreClearErrors) {
  Model one = CyclicSector(6, 1);
  one.cyclic.sectors = 1;
  EXPECT_THROW(one.cyclic.Validate(), std::invalid_argument);
  Model beyond = CyclicSector(6, 1);
  beyond.cyclic.engine_order = 4;
  EXPECT_THROW(ExpandCyclicRing(beyond), std::invalid_argument);
  Model plain = CyclicSector(6, 1);
  plain.cyclic = CyclicSymmetry{};
  EXPECT_THROW(ExpandCyclicRing(plain), std::invalid_argument);
  EXPECT_THROW(CyclicNaturalFrequencies(CyclicSector(6, 1), 4, true), std::invalid_argument);
  // Routes that cannot represent the delay between sectors refuse the sector.
  EXPECT_THROW(StickSystemModes(CyclicSector(6, 1)), std::invalid_argument);
  Model bad = CyclicSector(6, 1);
  bad.contacts[1].normal_b = Eigen::VectorXd{{1.0, 0.0, 0.0}};
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
  EXPECT_EQ(NodalDiameterOfHarmonic(CyclicSymmetry{6, 2}, 1), 2);
  EXPECT_EQ(NodalDiameterOfHarmonic(CyclicSymmetry{6, 2}, 2), 2);  // 4 folds to 6 − 4
  EXPECT_EQ(NodalDiameterOfHarmonic(CyclicSymmetry{6, 2}, 3), 0);
}

}  // namespace
}  // namespace fricrom
