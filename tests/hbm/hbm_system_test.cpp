#include "fricrom/hbm_system.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "fricrom/frf.h"
#include "fricrom/linear.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

std::vector<std::vector<ContactState>> States(const HbmSystem& sys, const Eigen::VectorXd& x,
                                              double w, const Eigen::VectorXd& alpha) {
  std::vector<std::vector<ContactState>> s;
  for (const ContactHistory& h : sys.ContactHistories(x, w, alpha)) s.push_back(h.states);
  return s;
}

// A point of a given regime: the full-stick linear solution scaled (dynamic part) and shifted.
Eigen::VectorXd RegimePoint(const HbmSystem& sys, double w, double dyn_scale, double static_scale,
                            std::mt19937* rng) {
  Eigen::VectorXd x = sys.StickLinearSolution(w);
  const int n = sys.num_dofs();
  x.head(n) *= static_scale;
  x.tail(x.size() - n) *= dyn_scale;
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  for (int i = 0; i < x.size(); ++i) x[i] *= 1.0 + noise(*rng);
  return x;
}

struct RegimeCase {
  const char* name;
  double dyn_scale, static_scale;
  ContactRegime expect_any;     // at least one contact is in this regime
  double min_slip_share = 0.0;  // ... and slips at least this share of the period
  double mu = 0.5;              // friction coefficient of every contact
};

double SlipShare(const ContactHistory& h) {
  int slip = 0;
  for (ContactState s : h.states) {
    slip += s == ContactState::kSlipPositive || s == ContactState::kSlipNegative;
  }
  return static_cast<double>(slip) / h.states.size();
}

class HbmJacobian : public ::testing::TestWithParam<RegimeCase> {};

TEST_P(HbmJacobian, MatchesCentralDifferences) {
  const RegimeCase rc = GetParam();
  Case cs = testing::LoadBaseline();
  for (Contact& c : cs.model.contacts) c.mu = rc.mu;
  for (int harmonics : {1, 3}) {
    HbmSystem sys(cs.model, HbmOptions{harmonics, 128});
    std::mt19937 rng(7 + harmonics);
    const double w = kTwoPi * 266.0;
    const Eigen::VectorXd alpha = Eigen::Vector4d(0.3, -0.6, 0.9, -0.1);
    const Eigen::VectorXd x = RegimePoint(sys, w, rc.dyn_scale, rc.static_scale, &rng);
    const auto states = States(sys, x, w, alpha);
    bool seen = false;
    for (const ContactHistory& h : sys.ContactHistories(x, w, alpha)) {
      seen |= h.regime == rc.expect_any && SlipShare(h) >= rc.min_slip_share;
    }
    ASSERT_TRUE(seen) << rc.name << ": the test point is not in the intended regime";

    HbmEvaluation e;
    sys.Evaluate(x, w, alpha, HbmRequest{true, true, true}, &e);
    EXPECT_EQ(testing::EntriesOutsidePattern(sys.StructuralPattern(), e), 0) << rc.name;
    HbmEvaluation p, m;
    int compared = 0;
    const double hx = 1e-8 * x.cwiseAbs().maxCoeff();
    for (int j = 0; j < x.size(); ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp[j] += hx;
      xm[j] -= hx;
      if (States(sys, xp, w, alpha) != states || States(sys, xm, w, alpha) != states) continue;
      sys.Evaluate(xp, w, alpha, HbmRequest{}, &p);
      sys.Evaluate(xm, w, alpha, HbmRequest{}, &m);
      const Eigen::VectorXd fd = (p.residual - m.residual) / (2 * hx);
      EXPECT_LE((fd - e.jacobian.col(j)).norm(), 1e-6 * e.jacobian.col(j).norm())
          << rc.name << " H=" << harmonics << " column " << j;
      ++compared;
    }
    EXPECT_GE(compared, x.size() / 2) << rc.name;
    // α columns.
    for (int c = 0; c < 4; ++c) {
      const double ha = 1e-6;
      Eigen::VectorXd ap = alpha, am = alpha;
      ap[c] += ha;
      am[c] -= ha;
      if (States(sys, x, w, ap) != states || States(sys, x, w, am) != states) continue;
      sys.Evaluate(x, w, ap, HbmRequest{}, &p);
      sys.Evaluate(x, w, am, HbmRequest{}, &m);
      const Eigen::VectorXd fd = (p.residual - m.residual) / (2 * ha);
      EXPECT_LE((fd - e.alpha_jacobian.col(c)).norm(),
                1e-6 * std::max(1.0, e.alpha_jacobian.col(c).norm()))
          << rc.name << " alpha " << c;
    }
    // ω derivative.
    const double hw = 1e-4;
    sys.Evaluate(x, w + hw, alpha, HbmRequest{}, &p);
    sys.Evaluate(x, w - hw, alpha, HbmRequest{}, &m);
    const Eigen::VectorXd fd = (p.residual - m.residual) / (2 * hw);
    EXPECT_LE((fd - e.omega_derivative).norm(), 1e-6 * e.omega_derivative.norm());
  }
}

INSTANTIATE_TEST_SUITE_P(
    Regimes, HbmJacobian,
    ::testing::Values(RegimeCase{"full-stick", 0.05, 1.0, ContactRegime::kFullStick},
                      RegimeCase{"stick-slip", 0.6, 1.0, ContactRegime::kStickSlip},
                      RegimeCase{"slip", 0.6, 1.0, ContactRegime::kStickSlip, 0.85, 0.02},
                      RegimeCase{"lift-off", 2.0, 0.2, ContactRegime::kStickSlipLiftOff}),
    [](const auto& info) {
      std::string s = info.param.name;
      for (char& ch : s) {
        if (ch == '-') ch = '_';
      }
      return s;
    });

// The structure Ipopt is given: on the FE-like strip (K banded, contacts pairwise) it holds every
// nonzero the Jacobians take in stick, slip and lift-off, and is under 8 % of the dense one (5.7 %
// at 20 pairs, falling as 1/pairs).
TEST(HbmSystem, StructuralPatternHoldsEveryNonzeroAndIsSparse) {
  for (int harmonics : {1, 3}) {
    HbmSystem sys(testing::ContactStrip(20), HbmOptions{harmonics, 64});
    const JacobianPattern pattern = sys.StructuralPattern();
    const double dense = static_cast<double>(sys.num_unknowns()) *
                         static_cast<double>(sys.num_unknowns() + sys.num_alpha());
    EXPECT_LT(pattern.nnz(), 0.08 * dense) << "H=" << harmonics;
    const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(20, -0.9, 0.9);
    std::set<ContactRegime> regimes;
    for (double f : {700.0, 1000.0, 1300.0}) {
      for (double scale : {0.2, 1.0, 5.0}) {
        const double w = kTwoPi * f;
        const Eigen::VectorXd x = sys.StickLinearSolution(w) * scale;
        HbmEvaluation e;
        sys.Evaluate(x, w, alpha, HbmRequest{true, true, false}, &e);
        EXPECT_EQ(testing::EntriesOutsidePattern(pattern, e), 0) << f << " Hz x" << scale;
        for (const ContactHistory& h : sys.ContactHistories(x, w, alpha)) regimes.insert(h.regime);
      }
    }
    EXPECT_TRUE(regimes.count(ContactRegime::kFullStick) && regimes.size() >= 3)
        << "the points should cover stick, slip and lift-off";
  }
}

TEST(HbmSystem, AlphaJacobianVanishesOutsideFullStick) {
  const Case cs = testing::LoadBaseline();
  HbmSystem sys(cs.model, HbmOptions{1, 128});
  std::mt19937 rng(1);
  const double w = kTwoPi * 266.0;
  const Eigen::VectorXd alpha = Eigen::Vector4d(0.2, 0.2, 0.2, 0.2);
  const Eigen::VectorXd x = RegimePoint(sys, w, 8.0, 1.0, &rng);
  HbmEvaluation e;
  sys.Evaluate(x, w, alpha, HbmRequest{false, true, false}, &e);
  const auto hist = sys.ContactHistories(x, w, alpha);
  for (int c = 0; c < 4; ++c) {
    if (hist[c].regime != ContactRegime::kFullStick) {
      EXPECT_EQ(e.alpha_jacobian.col(c).norm(), 0.0);
    }
  }
}

TEST(HbmSystem, RejectsWrongSizesAndAlphaOutOfRange) {
  const Case cs = testing::LoadBaseline();
  HbmSystem sys(cs.model, HbmOptions{1, 128});
  HbmEvaluation e;
  EXPECT_THROW(sys.Evaluate(Eigen::VectorXd::Zero(5), 1.0, Eigen::Vector4d::Zero(), {}, &e),
               std::invalid_argument);
  EXPECT_THROW(sys.Evaluate(Eigen::VectorXd::Zero(30), 1.0, Eigen::Vector3d::Zero(), {}, &e),
               std::invalid_argument);
  EXPECT_THROW(sys.Evaluate(Eigen::VectorXd::Zero(30), 1.0, Eigen::Vector4d(0, 0, 1.2, 0), {}, &e),
               std::invalid_argument);
  EXPECT_THROW(HbmSystem(cs.model, HbmOptions{3, 6}), std::invalid_argument);
}

// μ → ∞: every contact sticks, and the dynamic response is that of the full-stick linear system
// (the static part depends on α: type b1 systems of the paper).
TEST(HbmSystem, LargeFrictionGivesTheFullStickLinearResponse) {
  Case cs = testing::LoadBaseline();
  for (Contact& c : cs.model.contacts) c.mu = 1e9;
  HbmSystem sys(cs.model, HbmOptions{1, 128});
  FrfOptions opt;
  const auto pts = SolveAtFrequencies(sys, Eigen::Vector4d::Zero(), {250.0, 266.0, 280.0}, opt);
  for (const FrfPoint& p : pts) {
    ASSERT_EQ(p.status, SolverStatus::kConverged);
    const Eigen::VectorXd lin = sys.StickLinearSolution(kTwoPi * p.freq_hz);
    const int n = sys.num_dofs();
    const Eigen::VectorXd dyn = p.x.tail(2 * n), dyn_lin = lin.tail(2 * n);
    EXPECT_LE((dyn - dyn_lin).norm(), 1e-8 * dyn_lin.norm()) << p.freq_hz;
    const auto amp = LinearResponseAmplitude(cs.model, LinearSystemKind::kStick, {p.freq_hz});
    EXPECT_NEAR(p.amplitude, amp[0], 1e-8 * amp[0]);
  }
}

TEST(HbmSystem, NoContactsGivesTheFreeSystemResponse) {
  Case cs = testing::LoadBaseline();
  Model m = cs.model;
  m.contacts.clear();
  HbmSystem sys(m, HbmOptions{1, 128});
  const auto pts = SolveAtFrequencies(sys, Eigen::VectorXd(0), {240.0, 246.5, 255.0}, FrfOptions{});
  for (const FrfPoint& p : pts) {
    ASSERT_EQ(p.status, SolverStatus::kConverged);
    const auto amp = LinearResponseAmplitude(cs.model, LinearSystemKind::kFree, {p.freq_hz});
    EXPECT_NEAR(p.amplitude, amp[0], 1e-10 * amp[0]) << p.freq_hz;
  }
}

// Work of the excitation = viscous + contact dissipation per cycle at converged solutions; the
// contact side is computed from the contact's own forces and kinematics, not from the residual.
TEST(HbmSystem, EnergyBalanceAtConvergedSolutions) {
  const Case cs = testing::LoadBaseline();
  for (int harmonics : {1, 3}) {
    HbmSystem sys(cs.model, HbmOptions{harmonics, 128});
    for (const Eigen::Vector4d& alpha :
         {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, -1, 0.5, -0.3)}) {
      const auto pts = SolveAtFrequencies(sys, alpha, {260.0, 265.0, 266.5, 268.0}, FrfOptions{});
      int with_friction = 0;
      for (const FrfPoint& p : pts) {
        ASSERT_EQ(p.status, SolverStatus::kConverged) << p.freq_hz;
        const CycleEnergy e = sys.Energies(p.x, kTwoPi * p.freq_hz, alpha);
        const double balance = e.excitation_work - e.viscous_dissipation - e.friction_dissipation();
        EXPECT_LE(std::abs(balance), 1e-8 * e.excitation_work) << p.freq_hz;
        EXPECT_GT(e.viscous_dissipation, 0.0);
        if (e.friction_dissipation() > 1e-3 * e.excitation_work) ++with_friction;
      }
      EXPECT_GT(with_friction, 0) << "no point dissipates by friction: the test would be vacuous";
    }
  }
}

// η of a linear oscillator is cω/k (loss factor definition of docs/theory.md).
TEST(HbmSystem, LossFactorOfALinearOscillatorIsCOmegaOverK) {
  Model m = testing::JenkinsOscillator(1.0, 1e4, 3.0, 1e4, 1.0, 5.0, 8.0);
  m.contacts.clear();
  HbmSystem sys(m, HbmOptions{1, 64});
  for (double f : {10.0, 16.0, 30.0}) {
    const auto pts = SolveAtFrequencies(sys, Eigen::VectorXd(0), {f}, FrfOptions{});
    ASSERT_EQ(pts[0].status, SolverStatus::kConverged);
    const CycleEnergy e = sys.Energies(pts[0].x, kTwoPi * f, Eigen::VectorXd(0));
    EXPECT_NEAR(e.loss_factor(), 3.0 * kTwoPi * f / 1e4, 1e-12) << f;
  }
}

// Away from resonance every contact sticks and dissipates nothing; near it friction dissipates.
TEST(HbmSystem, FullStickDissipatesNothingAndStickSlipDoes) {
  const Case cs = testing::LoadBaseline();
  HbmSystem sys(cs.model, HbmOptions{1, 128});
  const Eigen::VectorXd alpha = Eigen::Vector4d::Zero();
  const auto pts = SolveAtFrequencies(sys, alpha, {250.0, 266.0}, FrfOptions{});
  const CycleEnergy far = sys.Energies(pts[0].x, kTwoPi * 250.0, alpha);
  const CycleEnergy near = sys.Energies(pts[1].x, kTwoPi * 266.0, alpha);
  EXPECT_NEAR(far.friction_dissipation(), 0.0, 1e-9 * far.excitation_work);  // full stick
  EXPECT_GT(near.friction_dissipation(), 0.0);
  EXPECT_GT(near.loss_factor(), 0.0);
  EXPECT_GT(far.potential_energy, 0.0);
}

// Issue 9, defect 1: H = 0 cannot carry a harmonic load or the harmonic-1 response, and a load
// above H cannot be represented: both are errors, never silently dropped.
TEST(HbmSystem, RejectsWhatTheHarmonicsCannotRepresent) {
  std::string err;
  EXPECT_FALSE((HbmOptions{0, 16}).IsValid(&err));
  EXPECT_NE(err.find("harmonics"), std::string::npos);
  const Model m = testing::LoadBaseline().model;
  EXPECT_THROW({ HbmSystem sys(m, HbmOptions{0, 16}); }, std::invalid_argument);
  Model high = m;
  high.loads.push_back(
      HarmonicLoad{3, Eigen::VectorXd::Ones(m.num_dofs()), Eigen::VectorXd::Zero(m.num_dofs())});
  EXPECT_FALSE(LoadsRepresentable(high, 2, &err));
  EXPECT_NE(err.find("harmonic 3"), std::string::npos) << err;
  EXPECT_TRUE(LoadsRepresentable(high, 3, &err));
  try {
    HbmSystem sys(high, HbmOptions{1, 16});
    ADD_FAILURE() << "a harmonic-3 load with H = 1 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("harmonic 3"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW({ HbmSystem sys(high, HbmOptions{3, 16}); });
}

}  // namespace
}  // namespace fricrom
