// Hill stability against independent routes: a linear system's Floquet exponents are the
// eigenvalues of its state matrix (any H); the Duffing oscillator's middle branch is unstable
// between its folds and the outer ones stable, as time integration from each solution shows; the
// lumped benchmark's full-stick solution has the full-stick system's exponents, and its bound
// solutions at 266 Hz are stable where time integration from them stays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "fricrom/condensed_system.h"
#include "fricrom/frf.h"
#include "fricrom/linear.h"
#include "fricrom/stability.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

// The linear part Z(ω) of a balance in the hbm_system.h layout, written from the definition
// q = q̂0 + Σ a_h cos hωt + b_h sin hωt (not from HbmSystem).
Eigen::MatrixXd LinearJacobian(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                               const Eigen::MatrixXd& c, int harmonics, double omega) {
  const Eigen::Index n = k.rows(), nc = 2 * harmonics + 1;
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n * nc, n * nc);
  z.topLeftCorner(n, n) = k;
  for (int h = 1; h <= harmonics; ++h) {
    const Eigen::Index a = (2 * h - 1) * n, b = 2 * h * n;
    const Eigen::MatrixXd diag = k - (h * omega) * (h * omega) * m;
    z.block(a, a, n, n) = diag;
    z.block(b, b, n, n) = diag;
    z.block(a, b, n, n) = h * omega * c;   // cosine row: C times the velocity's cosine hω b
    z.block(b, a, n, n) = -h * omega * c;  // sine row: C times −hω a
  }
  return z;
}

// Eigenvalues of the state matrix [[0, I], [−M⁻¹K, −M⁻¹C]], by decreasing real part.
std::vector<std::complex<double>> StateEigenvalues(const Eigen::MatrixXd& k,
                                                   const Eigen::MatrixXd& m,
                                                   const Eigen::MatrixXd& c) {
  const Eigen::Index n = k.rows();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m.llt().solve(k);
  a.bottomRightCorner(n, n) = -m.llt().solve(c);
  const Eigen::VectorXcd l = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
  std::vector<std::complex<double>> v(l.data(), l.data() + l.size());
  return v;
}

// Every expected exponent has a computed one with the same Floquet multiplier exp(λT), T = 2π/ω,
// within tol (exponents are defined up to i h ω; a matching, not an ordering).
void ExpectSameSpectrum(const Eigen::VectorXcd& got, std::vector<std::complex<double>> want,
                        double omega, double tol) {
  ASSERT_EQ(static_cast<size_t>(got.size()), want.size());
  const double period = 2 * M_PI / omega;
  const auto mult = [&](std::complex<double> l) { return std::exp(l * period); };
  for (Eigen::Index i = 0; i < got.size(); ++i) {
    auto best = std::min_element(want.begin(), want.end(), [&](auto a, auto b) {
      return std::abs(mult(a) - mult(got[i])) < std::abs(mult(b) - mult(got[i]));
    });
    EXPECT_LT(std::abs(mult(*best) - mult(got[i])), tol) << got[i] << " vs " << *best;
    EXPECT_NEAR(best->real(), got[i].real(), tol * omega) << got[i] << " vs " << *best;
    want.erase(best);
  }
}

TEST(Hill, ALinearSystemHasItsStateMatrixEigenvaluesAtAnyH) {
  Eigen::Matrix3d k, m, c;
  k << 4e4, -1e4, 0, -1e4, 3e4, -2e4, 0, -2e4, 5e4;
  m = Eigen::Vector3d(1.0, 2.0, 0.5).asDiagonal();
  c = 1e-3 * k + 0.5 * m;
  c(0, 0) += 3.0;  // not proportional
  const double omega = 123.0;
  for (int h : {1, 3}) {
    const HillResult r = HillStability(LinearJacobian(k, m, c, h, omega), m, c, h, omega);
    EXPECT_TRUE(r.stable) << r.BriefReport();
    ExpectSameSpectrum(r.exponents, StateEigenvalues(k, m, c), omega, 1e-8);
  }
  // Negative damping makes it grow.
  const Eigen::Matrix3d neg = -0.1 * m;
  EXPECT_FALSE(HillStability(LinearJacobian(k, m, neg, 1, omega), m, neg, 1, omega).stable);
  EXPECT_THROW(HillStability(Eigen::MatrixXd::Zero(3, 3), m, c, 1, omega), std::invalid_argument);
}

// Duffing oscillator m ẍ + c ẋ + k x + g x³ = F cos ωt at H = 1: the amplitude A of x ≈ a cos +
// b sin solves [(k − mω² + ¾gA²)² + (cω)²] A² = F²; between the folds it has three roots.
struct Duffing {
  double m = 1.0, c = 0.05, k = 1.0, g = 1.0, f = 0.3;
  // Real roots A of the amplitude equation at ω (ascending).
  std::vector<double> Amplitudes(double omega) const {
    std::vector<double> roots;
    // In s = A²: (9/16 g²) s³ + (3/2 g d) s² + (d² + c²ω²) s − F² = 0, d = k − mω².
    const double d = k - m * omega * omega;
    const double a3 = 9.0 / 16.0 * g * g, a2 = 1.5 * g * d, a1 = d * d + c * c * omega * omega,
                 a0 = -f * f;
    Eigen::Matrix3d comp;
    comp << -a2 / a3, -a1 / a3, -a0 / a3, 1, 0, 0, 0, 1, 0;
    const Eigen::VectorXcd s = Eigen::EigenSolver<Eigen::Matrix3d>(comp, false).eigenvalues();
    for (int i = 0; i < 3; ++i) {
      if (std::abs(s[i].imag()) < 1e-9 && s[i].real() > 0) roots.push_back(std::sqrt(s[i].real()));
    }
    std::sort(roots.begin(), roots.end());
    return roots;
  }
  // The HB unknowns (q0, a, b) of the root A (phase from the balance of the cosine row).
  Eigen::Vector3d Coefficients(double amplitude, double omega) const {
    const double d = k - m * omega * omega + 0.75 * g * amplitude * amplitude;
    // (d a + cω b, −cω a + d b) = (F, 0): a = F d / (d² + c²ω²), b = F cω / (d² + c²ω²).
    const double den = d * d + c * c * omega * omega;
    return {0.0, f * d / den, f * c * omega / den};
  }
  // ∂R/∂x at H = 1 (AFT of g x³ in closed form: ∂/∂(a, b) of the first-harmonic part of x³).
  Eigen::Matrix3d Jacobian(const Eigen::Vector3d& x, double omega) const {
    const double a = x[1], b = x[2];
    Eigen::Matrix3d j =
        LinearJacobian(Eigen::MatrixXd::Constant(1, 1, k), Eigen::MatrixXd::Constant(1, 1, m),
                       Eigen::MatrixXd::Constant(1, 1, c), 1, omega);
    // Static row/column of x³ at q0 = 0: ∂(mean of x³)/∂q0 = 3 mean(x²) = 1.5 (a² + b²).
    j(0, 0) += g * 1.5 * (a * a + b * b);
    // Cosine part of x³ = ¾ a (a² + b²), sine part ¾ b (a² + b²).
    j(1, 1) += g * 0.75 * (3 * a * a + b * b);
    j(1, 2) += g * 0.75 * 2 * a * b;
    j(2, 1) += g * 0.75 * 2 * a * b;
    j(2, 2) += g * 0.75 * (a * a + 3 * b * b);
    return j;
  }
  // RK4 from the periodic state for `periods`; returns the first-harmonic amplitude of the last.
  double IntegratedAmplitude(const Eigen::Vector3d& x, double omega, int periods) const {
    const int steps = 400;
    const double dt = 2 * M_PI / omega / steps;
    double q = x[0] + x[1], v = omega * x[2], t = 0;
    const auto acc = [&](double tt, double qq, double vv) {
      return (f * std::cos(omega * tt) - c * vv - k * qq - g * qq * qq * qq) / m;
    };
    double ca = 0, sa = 0;
    for (int p = 0; p < periods; ++p) {
      ca = sa = 0;
      for (int s = 0; s < steps; ++s) {
        const double k1q = v, k1v = acc(t, q, v);
        const double k2q = v + 0.5 * dt * k1v, k2v = acc(t + 0.5 * dt, q + 0.5 * dt * k1q, k2q);
        const double k3q = v + 0.5 * dt * k2v, k3v = acc(t + 0.5 * dt, q + 0.5 * dt * k2q, k3q);
        const double k4q = v + dt * k3v, k4v = acc(t + dt, q + dt * k3q, k4q);
        q += dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
        v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
        t += dt;
        ca += q * std::cos(omega * t) * 2.0 / steps;
        sa += q * std::sin(omega * t) * 2.0 / steps;
      }
    }
    return std::hypot(ca, sa);
  }
};

TEST(Hill, DuffingMiddleBranchIsUnstableAndTimeIntegrationLeavesIt) {
  const Duffing d;
  const double omega = 1.6;  // between the folds for these parameters
  const std::vector<double> amps = d.Amplitudes(omega);
  ASSERT_EQ(amps.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const Eigen::Vector3d x = d.Coefficients(amps[i], omega);
    ASSERT_NEAR(std::hypot(x[1], x[2]), amps[i], 1e-12);
    const HillResult r = HillStability(d.Jacobian(x, omega), Eigen::MatrixXd::Constant(1, 1, d.m),
                                       Eigen::MatrixXd::Constant(1, 1, d.c), 1, omega);
    EXPECT_EQ(r.stable, i != 1) << "branch " << i << ": " << r.BriefReport();
    // Time integration from the HB state: a stable one stays (to the H = 1 truncation), the
    // unstable one leaves for another branch.
    const double after = d.IntegratedAmplitude(x, omega, 200);
    if (i == 1) {
      EXPECT_GT(std::abs(after - amps[i]), 0.2 * amps[i]) << after;
    } else {
      EXPECT_NEAR(after, amps[i], 0.05 * amps[i]);
    }
  }
}

// Along the middle branch towards a fold the growing exponent goes to zero: at the fold (where
// two branches meet) the solution changes stability, as the theory of the saddle-node says.
TEST(Hill, DuffingExponentCrossesZeroAtTheFold) {
  const Duffing d;
  // Scan ω upwards until the three branches become one: the last ω with three is next to the
  // upper fold (where the middle and upper branch meet).
  double last = 0;
  for (double w = 1.2; w < 3.0; w += 1e-4) {
    if (d.Amplitudes(w).size() == 3) last = w;
  }
  ASSERT_GT(last, 1.6);
  const auto growth = [&](double w, size_t branch) {
    const Eigen::Vector3d x = d.Coefficients(d.Amplitudes(w)[branch], w);
    return HillStability(d.Jacobian(x, w), Eigen::MatrixXd::Constant(1, 1, d.m),
                         Eigen::MatrixXd::Constant(1, 1, d.c), 1, w)
        .max_real;
  };
  const double middle_far = growth(1.6, 1), middle_near = growth(last, 1);
  EXPECT_GT(middle_far, 0.0);
  EXPECT_GT(middle_near, 0.0);
  EXPECT_LT(middle_near, 0.05 * middle_far);  // vanishing at the fold
  EXPECT_LT(growth(last, 2), 0.0);            // the upper branch stays stable up to it
}

TEST(Hill, LumpedFullStickSolutionHasTheFullStickExponents) {
  const Model model = testing::LoadBaseline({{"mu", 1e9}}).model;  // stuck everywhere
  const HbmSystem sys(model, HbmOptions{1, 128});
  const Eigen::Vector4d alpha = Eigen::Vector4d::Zero();
  const FrfPoint p = SolveAtFrequency(sys, alpha, 262.0, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(p.status, SolverStatus::kConverged);
  const HillResult r = HillStability(sys, p.x, RadPerS(262.0), alpha);
  EXPECT_TRUE(r.stable) << r.BriefReport();
  const Eigen::MatrixXd ks = model.stiffness + ContactStickStiffness(model);
  ExpectSameSpectrum(r.exponents, StateEigenvalues(ks, model.mass, model.damping), RadPerS(262.0),
                     1e-8);
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

TimeIntegrationOptions HoldOptions(double freq_hz) {
  TimeIntegrationOptions o;
  o.freq_hz = freq_hz;
  o.window_periods = 50;
  o.max_periods = 400;
  o.min_periods = 1;
  return o;
}

// The lumped benchmark at 266 Hz (stick-slip on the outer contacts), H = 5: Hill says stable
// where time integration from the solution stays on it (both routes at three α, the bounds' α
// among them: the corners ±1 alternate).
TEST(Hill, LumpedSolutionsAt266HzAreStableWhereTimeIntegrationStays) {
  const Model model = testing::LoadBaseline().model;
  const HbmSystem sys(model, HbmOptions{5, 256});
  const double omega = RadPerS(266.0);
  for (const Eigen::Vector4d& alpha : {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, -1, 1, -1),
                                       Eigen::Vector4d(-1, 1, -1, 1)}) {
    const FrfPoint p = SolveAtFrequency(sys, alpha, 266.0, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(p.status, SolverStatus::kConverged);
    const HillResult r = HillStability(sys, p.x, omega, alpha);
    const TimeIntegrationResult t = IntegrateFromPeriodicState(
        model, PeriodicStartOf(model, sys, p.x, omega, alpha), HoldOptions(266.0));
    const bool stays = t.status == TimeIntegrationResult::Status::kSteadyState &&
                       std::abs(t.amplitude - p.amplitude) < 1e-3 * p.amplitude;
    EXPECT_TRUE(stays) << t.message;
    EXPECT_EQ(r.stable, stays) << alpha.transpose() << ": " << r.BriefReport();
  }
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

// The condensed balance's Hill analysis keeps every mode below the cutoff: with all of them (no
// residual left) it is the full balance's, exponent for exponent, at a stick-slip solution.
TEST(Hill, CondensedWithEveryModeIsTheFullBalance) {
  const Model model = testing::LoadBaseline().model;
  const double omega = RadPerS(266.0);
  const Eigen::Vector4d alpha(1, -1, 1, -1);
  const HbmSystem full(model, HbmOptions{3, 256});
  const CondensedSystem condensed(model, HbmOptions{3, 256});
  const FrfPoint pf = SolveAtFrequency(full, alpha, 266.0, Eigen::VectorXd(), FrfOptions{});
  const FrfPoint pc = SolveAtFrequency(condensed, alpha, 266.0, Eigen::VectorXd(), FrfOptions{});
  ASSERT_EQ(pf.status, SolverStatus::kConverged);
  ASSERT_EQ(pc.status, SolverStatus::kConverged);
  HillOptions every;
  every.modal_cutoff_factor = 1e6;
  const HillResult rf = HillStability(full, pf.x, omega, alpha);
  const HillResult rc = HillStability(condensed, pc.x, omega, alpha, every);
  std::vector<std::complex<double>> want(rf.exponents.data(),
                                         rf.exponents.data() + rf.exponents.size());
  ExpectSameSpectrum(rc.exponents, want, omega, 1e-6);
  EXPECT_EQ(rc.stable, rf.stable);
}

}  // namespace
}  // namespace fricrom
namespace fricrom {
namespace {

// At 270 Hz (α = 0) every contact ends stuck over the period, but the AFT's first pass slipped
// before it settled: the balance's Jacobian carries that transient, which gave a spurious growing
// exponent (+91 1/s) until stuck contacts entered as their springs. The perturbations of a motion
// stuck everywhere are the full-stick system's, in both balances.
TEST(Hill, ASolutionStuckAfterAFirstSlipHasTheFullStickExponents) {
  const Model model = testing::LoadBaseline().model;
  const Eigen::Vector4d alpha = Eigen::Vector4d::Zero();
  const Eigen::MatrixXd ks = model.stiffness + ContactStickStiffness(model);
  const std::vector<std::complex<double>> want = StateEigenvalues(ks, model.mass, model.damping);
  const HbmSystem full(model, HbmOptions{1, 128});
  const CondensedSystem condensed(model, HbmOptions{1, 128});
  HillOptions every;
  every.modal_cutoff_factor = 1e6;
  for (const HarmonicBalance* sys : {static_cast<const HarmonicBalance*>(&full),
                                     static_cast<const HarmonicBalance*>(&condensed)}) {
    const FrfPoint p = SolveAtFrequency(*sys, alpha, 270.0, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(p.status, SolverStatus::kConverged);
    for (ContactRegime r : sys->ContactRegimes(p.x, RadPerS(270.0), alpha)) {
      ASSERT_EQ(r, ContactRegime::kFullStick);
    }
    const HillResult r = HillStabilityOf(*sys, p.x, RadPerS(270.0), alpha, every);
    EXPECT_TRUE(r.stable) << r.BriefReport();
    ExpectSameSpectrum(r.exponents, want, RadPerS(270.0), 1e-6);
  }
}

}  // namespace
}  // namespace fricrom
