// The AFT evaluation of one contact (AftContactForces): its two transform routes (direct sums up
// to 2H+1 = 15 coefficients, FFTW beyond) against a naive Fourier sum of the contact law's
// samples and against each other, and its coefficient-level derivatives against central
// differences on both routes.
#include "fricrom/contact_forces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace fricrom {
namespace {

const ContactLawParams kPreloaded{3e5, 2e5, 0.5, 2.0};  // kn, kt [N/m], μ, preload [N]

// Stick-slip with lift-off over part of the period: every branch of the law is visited.
void Motion(int harmonics, Eigen::VectorXd* uh, Eigen::VectorXd* vh) {
  const int nh = 2 * harmonics + 1;
  *uh = Eigen::VectorXd::Zero(nh);
  *vh = Eigen::VectorXd::Zero(nh);
  (*uh)[0] = 1e-6;
  (*uh)[1] = 2e-5;
  (*uh)[2] = -7e-6;
  (*vh)[0] = -1e-6;
  (*vh)[1] = 8e-6;
  (*vh)[2] = 3e-6;
  for (int h = 2; h <= harmonics; ++h) {
    (*uh)[2 * h - 1] = 2e-6 / h;
    (*vh)[2 * h] = -1e-6 / h;
  }
}

// Coefficients by the definition: samples by explicit cosine/sine sums, the contact law, and
// the rectangle rule over the period.
void NaiveAft(const Eigen::VectorXd& uh, const Eigen::VectorXd& vh, double alpha, int samples,
              Eigen::VectorXd* t, Eigen::VectorXd* n) {
  const int nh = static_cast<int>(uh.size());
  Eigen::VectorXd u(samples), v(samples);
  for (int k = 0; k < samples; ++k) {
    const double th = 2 * std::numbers::pi * k / samples;
    u[k] = uh[0];
    v[k] = vh[0];
    for (int h = 1; 2 * h < nh; ++h) {
      u[k] += uh[2 * h - 1] * std::cos(h * th) + uh[2 * h] * std::sin(h * th);
      v[k] += vh[2 * h - 1] * std::cos(h * th) + vh[2 * h] * std::sin(h * th);
    }
  }
  ContactLawResult law;
  EvaluateContactLaw(kPreloaded, u, v, alpha, false, &law);
  *t = Eigen::VectorXd::Zero(nh);
  *n = Eigen::VectorXd::Zero(nh);
  for (int k = 0; k < samples; ++k) {
    const double th = 2 * std::numbers::pi * k / samples;
    (*t)[0] += law.tangential[k] / samples;
    (*n)[0] += law.normal[k] / samples;
    for (int h = 1; 2 * h < nh; ++h) {
      (*t)[2 * h - 1] += 2.0 / samples * law.tangential[k] * std::cos(h * th);
      (*t)[2 * h] += 2.0 / samples * law.tangential[k] * std::sin(h * th);
      (*n)[2 * h - 1] += 2.0 / samples * law.normal[k] * std::cos(h * th);
      (*n)[2 * h] += 2.0 / samples * law.normal[k] * std::sin(h * th);
    }
  }
}

// The displacement derivative blocks d (at uh, vh, α) against central differences. The forces
// are piecewise linear in the coefficients: a step small enough not to switch a sample's state
// gives the derivative to round-off.
void ExpectBlocksMatchCentralDifferences(const AftContactForces& aft, const Eigen::VectorXd& uh,
                                         const Eigen::VectorXd& vh, double alpha,
                                         const ContactForceBlocks& d) {
  const double step = 1e-13;
  ContactForceBlocks p, m;
  for (int l = 0; l < uh.size(); ++l) {
    Eigen::VectorXd up = uh, um = uh, vp = vh, vm = vh;
    up[l] += step;
    um[l] -= step;
    aft.Evaluate(kPreloaded, up, vh, alpha, AftDerivatives{}, &p);
    aft.Evaluate(kPreloaded, um, vh, alpha, AftDerivatives{}, &m);
    EXPECT_LT(((p.t - m.t) / (2 * step) - d.dt_du.col(l)).norm(), 1e-3 * kPreloaded.kt) << l;
    vp[l] += step;
    vm[l] -= step;
    aft.Evaluate(kPreloaded, uh, vp, alpha, AftDerivatives{}, &p);
    aft.Evaluate(kPreloaded, uh, vm, alpha, AftDerivatives{}, &m);
    EXPECT_LT(((p.t - m.t) / (2 * step) - d.dt_dv.col(l)).norm(), 1e-3 * kPreloaded.kn) << l;
    EXPECT_LT(((p.n - m.n) / (2 * step) - d.dn_dv.col(l)).norm(), 1e-3 * kPreloaded.kn) << l;
  }
}

class AftRoutes : public ::testing::TestWithParam<int> {};  // harmonics: 1, 3, 7 direct; 8, 12 FFTW

TEST_P(AftRoutes, CoefficientsAreTheFourierSumsOfTheLawsSamples) {
  const int harmonics = GetParam();
  for (int samples : {64, 128}) {
    const AftContactForces aft(HbmOptions{harmonics, samples});
    Eigen::VectorXd uh, vh, t, n;
    Motion(harmonics, &uh, &vh);
    ContactForceBlocks out;
    aft.Evaluate(kPreloaded, uh, vh, 0.3, AftDerivatives{}, &out);
    NaiveAft(uh, vh, 0.3, samples, &t, &n);
    ASSERT_EQ(ClassifyRegime(out.law.states), ContactRegime::kStickSlipLiftOff);
    EXPECT_LT((out.t - t).norm(), 1e-12 * t.norm()) << samples;
    EXPECT_LT((out.n - n).norm(), 1e-12 * n.norm()) << samples;
  }
}

TEST_P(AftRoutes, DerivativesMatchCentralDifferences) {
  const int harmonics = GetParam();
  const AftContactForces aft(HbmOptions{harmonics, 128});
  Eigen::VectorXd uh, vh;
  Motion(harmonics, &uh, &vh);
  const double alpha = 0.3;
  ContactForceBlocks d;
  aft.Evaluate(kPreloaded, uh, vh, alpha, AftDerivatives{true, true}, &d);
  ExpectBlocksMatchCentralDifferences(aft, uh, vh, alpha, d);
  ContactForceBlocks p, m;
  EXPECT_GT(d.dt_du.norm(), 0.1 * kPreloaded.kt);  // not a trivially zero block
  // ∂T̂/∂α: zero here (every sample after a slip or a lift-off forgets α); on a motion 100x
  // smaller the contact sticks all period and α sets the mean μ N(0) α.
  for (const double scale : {1.0, 0.01}) {
    const Eigen::VectorXd us = scale * uh, vs = scale * vh;
    aft.Evaluate(kPreloaded, us, vs, alpha, AftDerivatives{false, true}, &d);
    aft.Evaluate(kPreloaded, us, vs, alpha + 1e-7, AftDerivatives{}, &p);
    aft.Evaluate(kPreloaded, us, vs, alpha - 1e-7, AftDerivatives{}, &m);
    EXPECT_LT(((p.t - m.t) / 2e-7 - d.dt_dalpha).norm(), 1e-6 * (1.0 + d.dt_dalpha.norm()));
    if (scale < 1.0) {
      EXPECT_GT(std::abs(d.dt_dalpha[0]), 0.1 * kPreloaded.mu * kPreloaded.normal_preload);
    }
  }
}

// A contact stuck over the whole period takes the closed form (T and N linear in the samples):
// its coefficients equal the Fourier sums of the sequential law's samples, its derivative blocks
// central differences, and the harmonics h ≥ 1 of T − kt u and N − kn v vanish exactly.
TEST_P(AftRoutes, StuckContactsTakeTheClosedForm) {
  const int harmonics = GetParam(), nh = 2 * harmonics + 1;
  const AftContactForces aft(HbmOptions{harmonics, 64});
  Eigen::VectorXd uh, vh, t, n;
  Motion(harmonics, &uh, &vh);
  uh *= 0.01;
  vh *= 0.01;
  for (const double alpha : {-0.3, 0.6}) {
    ContactForceBlocks d, p, m;
    aft.Evaluate(kPreloaded, uh, vh, alpha, AftDerivatives{true, true}, &d);
    ASSERT_EQ(ClassifyRegime(d.law.states), ContactRegime::kFullStick) << alpha;
    NaiveAft(uh, vh, alpha, 64, &t, &n);
    EXPECT_LT((d.t - t).norm(), 1e-12 * t.norm()) << alpha;
    EXPECT_LT((d.n - n).norm(), 1e-12 * n.norm()) << alpha;
    EXPECT_EQ((d.t - kPreloaded.kt * uh).tail(nh - 1).cwiseAbs().maxCoeff(), 0.0) << alpha;
    EXPECT_EQ((d.n - kPreloaded.kn * vh).tail(nh - 1).cwiseAbs().maxCoeff(), 0.0) << alpha;
    ExpectBlocksMatchCentralDifferences(aft, uh, vh, alpha, d);
    aft.Evaluate(kPreloaded, uh, vh, alpha + 1e-7, AftDerivatives{}, &p);
    aft.Evaluate(kPreloaded, uh, vh, alpha - 1e-7, AftDerivatives{}, &m);
    EXPECT_LT(((p.t - m.t) / 2e-7 - d.dt_dalpha).norm(), 1e-6 * d.dt_dalpha.norm());
  }
}

// A Newton step linearises where it evaluated: AddDerivatives completes a plain Evaluate's
// blocks (the closed form's without a new pass over the samples). Whatever the route, the
// blocks equal those of Evaluate with derivatives bit for bit — stuck (the motion scaled down),
// stick-slip with lift-off, and a block left by another contact's evaluation (the flag cleared).
TEST_P(AftRoutes, AddedDerivativesEqualAnEvaluationWithThemBitForBit) {
  const int harmonics = GetParam();
  const AftContactForces aft(HbmOptions{harmonics, 64});
  Eigen::VectorXd uh, vh;
  Motion(harmonics, &uh, &vh);
  int stuck_forms = 0;
  for (const double scale : {0.01, 1.0}) {
    const Eigen::VectorXd us = scale * uh, vs = scale * vh;
    ContactForceBlocks with, added;
    aft.Evaluate(kPreloaded, us, vs, 0.6, AftDerivatives{true, true}, &with);
    aft.Evaluate(kPreloaded, us, vs, 0.6, AftDerivatives{}, &added);
    stuck_forms += added.stuck_form;
    EXPECT_EQ(added.stuck_form, scale < 1.0) << scale;
    aft.AddDerivatives(kPreloaded, us, vs, 0.6, AftDerivatives{true, true}, &added);
    EXPECT_EQ(added.t, with.t) << scale;
    EXPECT_EQ(added.n, with.n) << scale;
    EXPECT_EQ(added.dt_du, with.dt_du) << scale;
    EXPECT_EQ(added.dt_dv, with.dt_dv) << scale;
    EXPECT_EQ(added.dn_dv, with.dn_dv) << scale;
    EXPECT_EQ(added.dt_dalpha, with.dt_dalpha) << scale;
    EXPECT_EQ(added.law.states, with.law.states) << scale;
  }
  EXPECT_EQ(stuck_forms, 1);
}

INSTANTIATE_TEST_SUITE_P(DirectAndFftw, AftRoutes, ::testing::Values(1, 3, 7, 8, 12));

// The same motion (harmonics above 7 zero) through the direct route at H = 7 and FFTW at H = 8:
// the same forces in the 15 shared coefficients.
TEST(AftRoutes, DirectAndFftwAgree) {
  const AftContactForces direct(HbmOptions{7, 64}), fftw(HbmOptions{8, 64});
  Eigen::VectorXd uh7, vh7;
  Motion(7, &uh7, &vh7);
  Eigen::VectorXd uh8 = Eigen::VectorXd::Zero(17), vh8 = Eigen::VectorXd::Zero(17);
  uh8.head(15) = uh7;
  vh8.head(15) = vh7;
  ContactForceBlocks a, b;
  direct.Evaluate(kPreloaded, uh7, vh7, -0.4, AftDerivatives{true, true}, &a);
  fftw.Evaluate(kPreloaded, uh8, vh8, -0.4, AftDerivatives{true, true}, &b);
  EXPECT_LT((a.t - b.t.head(15)).norm(), 1e-12 * a.t.norm());
  EXPECT_LT((a.n - b.n.head(15)).norm(), 1e-12 * a.n.norm());
  EXPECT_LT((a.dt_du - b.dt_du.topLeftCorner(15, 15)).norm(), 1e-12 * a.dt_du.norm());
  EXPECT_LT((a.dn_dv - b.dn_dv.topLeftCorner(15, 15)).norm(), 1e-12 * a.dn_dv.norm());
  EXPECT_LE((a.dt_dalpha - b.dt_dalpha.head(15)).norm(), 1e-12 * a.dt_dalpha.norm());
}

}  // namespace
}  // namespace fricrom
