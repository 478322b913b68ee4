#include "fricrom/contact_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

namespace fricrom {
namespace {

constexpr int kSamples = 64;
const ContactLawParams kParams{3e5, 2e5, 0.5, 0.0};

void Harmonic(double u0, double u1, double phase, double v0, double v1, Eigen::VectorXd* u,
              Eigen::VectorXd* v) {
  u->resize(kSamples);
  v->resize(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double th = 2 * std::numbers::pi * k / kSamples;
    (*u)[k] = u0 + u1 * std::cos(th);
    (*v)[k] = v0 + v1 * std::cos(th + phase);
  }
}

TEST(ContactLaw, FullStickMeanIsSetByAlpha) {
  Eigen::VectorXd u, v;
  Harmonic(0.0, 1e-5, 0.3, 3e-4, 1e-5, &u, &v);  // small motion, large preload: sticks
  for (double alpha : {-0.5, 0.0, 0.7}) {
    ContactLawResult r;
    EvaluateContactLaw(kParams, u, v, alpha, false, &r);
    ASSERT_EQ(ClassifyRegime(r.states), ContactRegime::kFullStick) << alpha;
    const double t0 = alpha * kParams.mu * kParams.kn * v[0];
    for (int k = 0; k < kSamples; ++k) {
      EXPECT_NEAR(r.tangential[k], t0 + kParams.kt * (u[k] - u[0]), 1e-9);
      EXPECT_NEAR(r.normal[k], kParams.kn * v[k], 1e-9);
    }
  }
}

TEST(ContactLaw, StickSlipLoopIsIndependentOfAlphaAndBoundedByCoulomb) {
  Eigen::VectorXd u, v;
  Harmonic(0.0, 2e-4, 0.0, 2e-4, 0.0, &u, &v);  // kt·A = 40 N > μN = 30 N: slips
  ContactLawResult a, b;
  EvaluateContactLaw(kParams, u, v, -1.0, false, &a);
  EvaluateContactLaw(kParams, u, v, 0.6, false, &b);
  EXPECT_EQ(ClassifyRegime(a.states), ContactRegime::kStickSlip);
  for (int k = 0; k < kSamples; ++k) {
    EXPECT_NEAR(a.tangential[k], b.tangential[k], 1e-9);
    EXPECT_LE(std::abs(a.tangential[k]), kParams.mu * a.normal[k] + 1e-9);
  }
}

TEST(ContactLaw, LiftOffGivesZeroForces) {
  Eigen::VectorXd u, v;
  Harmonic(0.0, 1e-4, 0.0, 0.0, 2e-4, &u, &v);  // v < 0 half of the period
  ContactLawResult r;
  EvaluateContactLaw(kParams, u, v, 0.0, false, &r);
  EXPECT_EQ(ClassifyRegime(r.states), ContactRegime::kStickSlipLiftOff);
  for (int k = 0; k < kSamples; ++k) {
    if (v[k] < 0) {
      EXPECT_EQ(r.states[k], ContactState::kLiftOff);
      EXPECT_EQ(r.tangential[k], 0.0);
      EXPECT_EQ(r.normal[k], 0.0);
    }
  }
}

// The one-sample step both the AFT and the time integrator use, by hand: N = 50 + 1000·0.01 =
// 60 N, limit μN = 30 N.
TEST(ContactLaw, OneStepSticksSlipsAndLiftsOff) {
  const ContactLawParams p{1000.0, 2000.0, 0.5, 50.0};
  ContactStep s = AdvanceContact(p, 10.0, 0.005, 0.01);  // 10 + 2000·0.005 = 20 N ≤ 30 N
  EXPECT_EQ(s.state, ContactState::kStick);
  EXPECT_DOUBLE_EQ(s.normal, 60.0);
  EXPECT_DOUBLE_EQ(s.tangential, 20.0);
  s = AdvanceContact(p, 10.0, 0.02, 0.01);  // predictor 50 N > 30 N
  EXPECT_EQ(s.state, ContactState::kSlipPositive);
  EXPECT_DOUBLE_EQ(s.tangential, 30.0);
  s = AdvanceContact(p, -10.0, -0.02, 0.01);
  EXPECT_EQ(s.state, ContactState::kSlipNegative);
  EXPECT_DOUBLE_EQ(s.tangential, -30.0);
  s = AdvanceContact(p, 10.0, 0.01, -0.06);  // 50 − 60 < 0: separated, no force at all
  EXPECT_EQ(s.state, ContactState::kLiftOff);
  EXPECT_EQ(s.normal, 0.0);
  EXPECT_EQ(s.tangential, 0.0);
  s = AdvanceContact(p, 30.0 * (1.0 + 1e-13), 0.0, 0.01);  // touching the limit sticks
  EXPECT_EQ(s.state, ContactState::kStick);
}

TEST(ContactLaw, RejectsBadInput) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(8), v = Eigen::VectorXd::Zero(7);
  ContactLawResult r;
  EXPECT_THROW(EvaluateContactLaw(kParams, u, v, 0.0, false, &r), std::invalid_argument);
  v.resize(8);
  v.setZero();
  EXPECT_THROW(EvaluateContactLaw(kParams, u, v, 1.5, false, &r), std::invalid_argument);
}

// The closed form for a contact stuck over the whole period (EvaluateStuckContactLaw) against the
// sequential law on random motions that stick, slip near the limit, graze it (α = ±1 puts T(0)
// on it) or lift off: where the closed form answers, the law sticks at every sample too and
// both give the same forces and derivatives; where the law sticks from the initial instant on,
// clear of the limit, the closed form answers.
TEST(ContactLaw, StuckClosedFormAgreesWithTheSequentialLaw) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const ContactLawParams preloaded{3e5, 2e5, 0.5, 2.0};
  int answered = 0, declined_stuck = 0, at_limit = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // Amplitudes from far inside the stick range (~5e-7 m) to beyond it.
    const double scale = std::pow(10.0, -7.5 + 2.0 * (trial % 100) / 100.0);
    const double alpha = trial % 5 == 0 ? (trial % 10 == 0 ? 1.0 : -1.0) : unit(gen);
    // α = ±1: T(0) on the limit; u(0) the extreme of u on the side that moves T inwards and a
    // nearly constant normal load, so that most of these stick (a slip would follow at once
    // otherwise).
    const double u1 = scale * (1 + unit(gen)), v1 = scale * (1 + unit(gen));
    Eigen::VectorXd u, v;
    Harmonic(unit(gen) * scale, std::abs(alpha) == 1.0 ? alpha * u1 : u1, 3 * unit(gen),
             unit(gen) * 4e-6, std::abs(alpha) == 1.0 ? 1e-3 * v1 : v1, &u, &v);
    ContactLawResult law, fast;
    EvaluateContactLaw(preloaded, u, v, alpha, true, &law);
    const bool stuck = ClassifyRegime(law.states) == ContactRegime::kFullStick;
    if (!EvaluateStuckContactLaw(preloaded, u, v, alpha, true, &fast)) {
      if (!stuck) continue;
      // Declined although the law sticks over the returned period: it slipped in the first
      // (its stick anchor is not the initial instant), or T comes within 1e-9 of the limit.
      ++declined_stuck;
      bool anchored_later = false;
      double closest = INFINITY;
      for (int k = 0; k < kSamples; ++k) {
        anchored_later = anchored_later || law.dT[k].u_minus != 0;
        closest = std::min(closest, preloaded.mu * law.normal[k] - std::abs(law.tangential[k]));
      }
      EXPECT_TRUE(anchored_later || closest < 1e-9 * preloaded.mu * law.normal.maxCoeff()) << trial;
      continue;
    }
    ++answered;
    at_limit += std::abs(alpha) == 1.0;
    ASSERT_TRUE(stuck) << trial;
    ASSERT_EQ(fast.states, law.states) << trial;
    const double tscale = law.tangential.cwiseAbs().maxCoeff() + preloaded.normal_preload;
    EXPECT_LT((fast.tangential - law.tangential).cwiseAbs().maxCoeff(), 1e-12 * tscale) << trial;
    EXPECT_LT((fast.normal - law.normal).cwiseAbs().maxCoeff(), 1e-12 * tscale) << trial;
    EXPECT_EQ(fast.dN_dv, law.dN_dv);
    for (int k = 0; k < kSamples; ++k) {
      const TangentialDerivative &a = fast.dT[k], &b = law.dT[k];
      EXPECT_EQ(a.u_plus, b.u_plus);
      EXPECT_EQ(a.u_minus, b.u_minus);
      EXPECT_EQ(a.v_index, b.v_index);
      EXPECT_NEAR(a.dv, b.dv, 1e-12 * preloaded.mu * preloaded.kn);
      EXPECT_NEAR(a.dalpha, b.dalpha, 1e-12 * tscale);
    }
  }
  EXPECT_GT(answered, 200);
  EXPECT_GT(at_limit, 20);  // α = ±1: T(0) on the limit, still the closed form
  std::printf("[stuck closed form] %d of 2000 answered (%d at alpha = +-1), %d stuck declined\n",
              answered, at_limit, declined_stuck);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(8), v = Eigen::VectorXd::Zero(8);
  ContactLawResult r;
  EXPECT_THROW(EvaluateStuckContactLaw(kParams, u, v, 1.5, false, &r), std::invalid_argument);
  // The closed form's reductions are vectorised: a NaN or an infinity at any one sample (where
  // a reduction could drop it) still sends the contact to the sequential law.
  ASSERT_TRUE(EvaluateStuckContactLaw(preloaded, u, v, 0.2, false, &r));
  for (int k = 0; k < 8; ++k) {
    for (const double bad : {NAN, INFINITY, -INFINITY}) {
      Eigen::VectorXd ub = u, vb = v;
      ub[k] = bad;
      EXPECT_FALSE(EvaluateStuckContactLaw(preloaded, ub, v, 0.2, false, &r)) << k << " u " << bad;
      vb[k] = bad;
      EXPECT_FALSE(EvaluateStuckContactLaw(preloaded, u, vb, 0.2, false, &r)) << k << " v " << bad;
    }
  }
}

// The returned period is the second of two stepped from the initial condition: T, N and the
// states must equal plain stepping with AdvanceContact bit for bit, in every regime (a guard for
// any shortcut through the law's loop), and the sparse derivative records must equal dense
// forward-mode sensitivities carried through the same steps (an independent route: rows of
// ∂T/∂u, ∂T/∂v and ∂T/∂α updated step by step; their entries are ±kt or sums cancelling exactly).
TEST(ContactLaw, SecondPeriodEqualsPlainSteppingBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int events_seen = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::VectorXd u(kSamples), v(kSamples);
    const double ua = 4e-4 * std::abs(unit(rng)), v0 = 2e-4 * unit(rng) + 1e-4;
    const double va = 2e-4 * std::abs(unit(rng));
    for (int k = 0; k < kSamples; ++k) {
      const double th = 2 * std::numbers::pi * k / kSamples;
      u[k] = ua * (std::cos(th) + 0.3 * std::sin(3 * th)) + 1e-6 * unit(rng);
      v[k] = v0 + va * std::cos(th + 0.5);
    }
    const double alpha = unit(rng);
    ContactLawResult r;
    EvaluateContactLaw(kParams, u, v, alpha, trial % 2 == 0, &r);
    const double n0 = std::max(kParams.normal_preload + kParams.kn * v[0], 0.0);
    double t = alpha * kParams.mu * n0;
    Eigen::RowVectorXd gu = Eigen::RowVectorXd::Zero(kSamples), gv = gu;
    double ga = 0.0;
    if (n0 > 0.0) {
      gv[0] = alpha * kParams.mu * kParams.kn;
      ga = kParams.mu * n0;
    }
    for (int step = 1; step < 2 * kSamples; ++step) {
      const int k = step % kSamples, km1 = (step - 1) % kSamples;
      const ContactStep s = AdvanceContact(kParams, t, u[k] - u[km1], v[k]);
      t = s.tangential;
      if (s.state == ContactState::kStick) {
        gu[k] += kParams.kt;
        gu[km1] -= kParams.kt;
      } else {
        gu.setZero();
        gv.setZero();
        ga = 0.0;
        if (s.state != ContactState::kLiftOff)
          gv[k] = (s.state == ContactState::kSlipPositive ? 1.0 : -1.0) * kParams.mu * kParams.kn;
      }
      if (step < kSamples) continue;
      events_seen += s.state != ContactState::kStick;
      ASSERT_EQ(r.tangential[k], s.tangential) << "trial " << trial << " sample " << k;
      ASSERT_EQ(r.normal[k], s.normal) << "trial " << trial << " sample " << k;
      ASSERT_EQ(r.states[k], s.state) << "trial " << trial << " sample " << k;
      if (trial % 2 != 0) continue;
      const TangentialDerivative& d = r.dT[k];
      Eigen::RowVectorXd ru = Eigen::RowVectorXd::Zero(kSamples), rv = ru;
      if (d.u_plus >= 0) ru[d.u_plus] += kParams.kt;
      if (d.u_minus >= 0) ru[d.u_minus] -= kParams.kt;
      if (d.v_index >= 0) rv[d.v_index] += d.dv;
      ASSERT_EQ(ru, gu) << "trial " << trial << " sample " << k;
      ASSERT_EQ(rv, gv) << "trial " << trial << " sample " << k;
      ASSERT_EQ(d.dalpha, ga) << "trial " << trial << " sample " << k;
      ASSERT_EQ(r.dN_dv[k], s.normal > 0.0 ? kParams.kn : 0.0);
    }
  }
  EXPECT_GT(events_seen, 1000);  // slips and lift-offs were exercised, not only stick
}

// Exact sparse derivatives against central differences, sample by sample, in every regime.
// Points where a perturbation flips a state are skipped (the law has kinks there).
class ContactDerivatives : public ::testing::TestWithParam<std::tuple<double, double, double>> {};

TEST_P(ContactDerivatives, MatchCentralDifferences) {
  const auto [u1, v0, v1] = GetParam();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  Eigen::VectorXd u, v;
  Harmonic(1e-5, u1, 0.7, v0, v1, &u, &v);
  for (int k = 0; k < kSamples; ++k) {
    u[k] += 0.1 * u1 * noise(rng);
    v[k] += 0.05 * std::abs(v1) * noise(rng);
  }
  const double alpha = 0.3;
  ContactLawResult r;
  EvaluateContactLaw(kParams, u, v, alpha, true, &r);
  // Dense derivative matrices from the sparse records.
  Eigen::MatrixXd du = Eigen::MatrixXd::Zero(kSamples, kSamples), dv = du;
  Eigen::VectorXd da(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const TangentialDerivative& d = r.dT[k];
    if (d.u_plus >= 0) du(k, d.u_plus) += kParams.kt;
    if (d.u_minus >= 0) du(k, d.u_minus) -= kParams.kt;
    if (d.v_index >= 0) dv(k, d.v_index) += d.dv;
    da[k] = d.dalpha;
  }
  const double hu = 1e-9, ha = 1e-7;
  int compared = 0;
  auto check_column = [&](const Eigen::VectorXd& up, const Eigen::VectorXd& vp,
                          const Eigen::VectorXd& um, const Eigen::VectorXd& vm, double ap,
                          double am, double h, const Eigen::VectorXd& exact_t,
                          const Eigen::VectorXd* exact_n) {
    ContactLawResult p, m;
    EvaluateContactLaw(kParams, up, vp, ap, false, &p);
    EvaluateContactLaw(kParams, um, vm, am, false, &m);
    if (p.states != r.states || m.states != r.states) return;  // crossed a kink
    ++compared;
    const Eigen::VectorXd fd_t = (p.tangential - m.tangential) / (2 * h);
    EXPECT_LE((fd_t - exact_t).norm(), 1e-6 * std::max(1.0, exact_t.norm()));
    if (exact_n) {
      const Eigen::VectorXd fd_n = (p.normal - m.normal) / (2 * h);
      EXPECT_LE((fd_n - *exact_n).norm(), 1e-6 * std::max(1.0, exact_n->norm()));
    }
  };
  for (int j = 0; j < kSamples; j += 3) {
    Eigen::VectorXd up = u, um = u;
    up[j] += hu;
    um[j] -= hu;
    check_column(up, v, um, v, alpha, alpha, hu, du.col(j), nullptr);
    Eigen::VectorXd vp = v, vm = v;
    vp[j] += hu;
    vm[j] -= hu;
    Eigen::VectorXd dn = Eigen::VectorXd::Zero(kSamples);
    dn[j] = r.dN_dv[j];
    check_column(u, vp, u, vm, alpha, alpha, hu, dv.col(j), &dn);
  }
  check_column(u, v, u, v, alpha + ha, alpha - ha, ha, da, nullptr);
  EXPECT_GT(compared, kSamples / 2);
}

INSTANTIATE_TEST_SUITE_P(Regimes, ContactDerivatives,
                         ::testing::Values(std::make_tuple(2e-5, 3e-4, 1e-5),    // full stick
                                           std::make_tuple(3e-4, 2e-4, 5e-5),    // stick-slip
                                           std::make_tuple(3e-3, 1e-4, 2e-5),    // nearly full slip
                                           std::make_tuple(2e-4, 5e-5, 1e-4)));  // lift-off

}  // namespace
}  // namespace fricrom
