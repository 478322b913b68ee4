// Direct time integration as an independent check of the harmonic balance.
#include "fricrom/time_integration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/linear.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace fricrom {
namespace {

using Status = TimeIntegrationResult::Status;

TimeIntegrationOptions At(double freq_hz) {
  TimeIntegrationOptions o;
  o.freq_hz = freq_hz;
  return o;
}

// Without contacts the model is linear: the steady state must be the linear free response
// (central differences with 256 steps/period: dispersion error (ωdt)²/12 ≈ 5e-5, amplified by the
// distance to the 246.6 Hz resonance; measured 3.5e-5 at 200 Hz and 3.5e-4 at 266 Hz).
TEST(TimeIntegration, WithoutContactsMatchesTheLinearFreeResponse) {
  Model model = testing::LoadBaseline().model;
  model.contacts.clear();
  for (double f : {200.0, 266.0}) {
    const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::VectorXd(0), At(f));
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    const double linear = LinearResponseAmplitude(model, LinearSystemKind::kFree, {f})[0];
    std::printf("[ linear ] %g Hz: time integration %.6e m, linear %.6e m, rel %.2e (%d periods)\n",
                f, r.amplitude, linear, r.amplitude / linear - 1.0, r.periods);
    EXPECT_NEAR(r.amplitude, linear, 1e-3 * linear) << f << " Hz";
    EXPECT_TRUE(r.regimes.empty());
    EXPECT_EQ(r.last_period_response.size(), 256);
  }
}

// A Jenkins oscillator in stick-slip: the only difference to the HBM is harmonic truncation
// (H = 5 here; measured differences ≈ 1e-4).
TEST(TimeIntegration, JenkinsOscillatorMatchesHbm) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  HbmSystem sys(model, HbmOptions{5, 512});
  const Eigen::VectorXd alpha = Eigen::VectorXd::Zero(1);
  const auto pts = SolveAtFrequencies(sys, alpha, {14.0, 16.0, 20.0}, FrfOptions{});
  int stick_slip = 0;
  for (const FrfPoint& p : pts) {
    ASSERT_EQ(p.status, SolverStatus::kConverged) << p.freq_hz;
    const TimeIntegrationResult r = IntegrateToSteadyState(model, alpha, At(p.freq_hz));
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    std::printf("[ jenkins ] %g Hz: time integration %.6e m, HBM(H=5) %.6e m, rel %.2e, %s\n",
                p.freq_hz, r.amplitude, p.amplitude, r.amplitude / p.amplitude - 1.0,
                ToString(r.regimes[0]).c_str());
    EXPECT_NEAR(r.amplitude, p.amplitude, 0.02 * p.amplitude) << p.freq_hz << " Hz";
    EXPECT_EQ(r.regimes[0], p.regimes[0]) << p.freq_hz << " Hz";
    stick_slip += r.regimes[0] == ContactRegime::kStickSlip;
  }
  EXPECT_GE(stick_slip, 2) << "the comparison must cover the stick-slip regime";
}

// The lumped benchmark at 266 Hz (paper §4.1.2): different initial static states settle to
// different steady responses. Each is one of the HBM's α-family: it lies inside the HBM envelope
// over α, and the HBM with the α equivalent to its contact state (T/μN at t = 0 of the period)
// reproduces it up to harmonic truncation (H = 3).
TEST(TimeIntegration, BaselineInitialStatesGiveDifferentSteadyStatesInsideTheHbmEnvelope) {
  const Model model = testing::LoadBaseline().model;
  const double freq = 266.0, omega = kTwoPi * freq;
  HbmSystem sys(model, HbmOptions{3, 256});

  // HBM envelope over α: all 16 corners of [−1, 1]⁴ and 200 random samples (fixed seed).
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  double hbm_lo = 1e9, hbm_hi = 0.0;
  int converged = 0;
  for (int i = 0; i < 16 + 200; ++i) {
    Eigen::Vector4d alpha;
    for (int c = 0; c < 4; ++c) alpha[c] = i < 16 ? ((i >> c) & 1 ? 1.0 : -1.0) : uniform(rng);
    const auto p = SolveAtFrequencies(sys, alpha, {freq}, FrfOptions{});
    if (p[0].status != SolverStatus::kConverged) continue;
    ++converged;
    hbm_lo = std::min(hbm_lo, p[0].amplitude);
    hbm_hi = std::max(hbm_hi, p[0].amplitude);
  }
  ASSERT_GE(converged, 200);
  std::printf("[ lumped ] HBM(H=3) envelope at %g Hz over %d alpha samples: [%.6e, %.6e] m\n", freq,
              converged, hbm_lo, hbm_hi);

  double ti_lo = 1e9, ti_hi = 0.0;
  for (const Eigen::Vector4d& alpha :
       {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, -1, 1, -1), Eigen::Vector4d(-1, 1, -1, 1),
        Eigen::Vector4d(1, 1, -1, -1), Eigen::Vector4d(-1, -1, 1, 1), Eigen::Vector4d(1, 1, 1, 1),
        Eigen::Vector4d(0.5, -0.5, 0.3, -0.8)}) {
    const TimeIntegrationResult r = IntegrateToSteadyState(model, alpha, At(freq));
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    ti_lo = std::min(ti_lo, r.amplitude);
    ti_hi = std::max(ti_hi, r.amplitude);

    // Outer contacts stick-slip, inner contacts full stick (the paper's mixed configuration).
    ASSERT_EQ(r.regimes.size(), 4u);
    EXPECT_EQ(r.regimes[0], ContactRegime::kStickSlip);
    EXPECT_EQ(r.regimes[1], ContactRegime::kFullStick);
    EXPECT_EQ(r.regimes[2], ContactRegime::kFullStick);
    EXPECT_EQ(r.regimes[3], ContactRegime::kStickSlip);

    EXPECT_GE(r.amplitude, 0.98 * hbm_lo);
    EXPECT_LE(r.amplitude, 1.02 * hbm_hi);

    // The HBM member this steady state belongs to, from the time-integration harmonics.
    Eigen::VectorXd x = LastPeriodCoefficients(r, 3);
    EXPECT_NEAR(sys.Amplitude(x), r.amplitude, 1e-12 * r.amplitude);
    const NewtonSummary s =
        SolveNewton(HbmAtFrequency(sys, omega, r.equivalent_alpha), NewtonOptions{}, &x);
    ASSERT_TRUE(s.IsSolutionUsable()) << s.BriefReport();
    const double hbm_equivalent = sys.Amplitude(x);
    const double hbm_same_alpha = SolveAtFrequencies(sys, alpha, {freq}, FrfOptions{})[0].amplitude;
    std::printf(
        "[ lumped ] alpha0 (%4.1f %4.1f %4.1f %4.1f): time integration %.6e m (%d periods) | "
        "equivalent alpha (%.3f %.3f %.3f %.3f): HBM %.6e m, rel %.2e | HBM at alpha0 %.6e m\n",
        alpha[0], alpha[1], alpha[2], alpha[3], r.amplitude, r.periods, r.equivalent_alpha[0],
        r.equivalent_alpha[1], r.equivalent_alpha[2], r.equivalent_alpha[3], hbm_equivalent,
        r.amplitude / hbm_equivalent - 1.0, hbm_same_alpha);
    EXPECT_NEAR(r.amplitude, hbm_equivalent, 5e-3 * hbm_equivalent);
  }
  std::printf("[ lumped ] time-integration amplitudes [%.6e, %.6e] m, spread %.1f%% of the max\n",
              ti_lo, ti_hi, 100.0 * (ti_hi - ti_lo) / ti_hi);
  EXPECT_GT(ti_hi - ti_lo, 0.10 * ti_hi) << "expected the non-uniqueness to show up";
}

// The static state at t = 0 is an equilibrium K q + F_C = F0 with T = α μ N on every contact.
TEST(TimeIntegration, StaticStateHonoursTheInitialAlpha) {
  const Model model = testing::LoadBaseline().model;
  const Eigen::Vector4d alpha(0.5, -0.5, 0.3, -0.8);
  TimeIntegrationOptions o = At(266.0);
  o.min_periods = o.max_periods = 1;
  o.ramp_periods = 0;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, alpha, o);
  const Eigen::VectorXd& q = r.static_displacement;
  ASSERT_EQ(q.size(), model.num_dofs());
  Eigen::VectorXd residual = model.stiffness * q;
  for (const HarmonicLoad& l : model.loads) {
    if (l.harmonic == 0) residual -= l.cos;
  }
  for (size_t ci = 0; ci < model.contacts.size(); ++ci) {
    const Contact& c = model.contacts[ci];
    double v = 0.0;
    for (size_t i = 0; i < c.dofs_a.size(); ++i) {
      const double qa = c.dofs_a[i] >= 0 ? q[c.dofs_a[i]] : 0.0;
      const double qb = c.dofs_b[i] >= 0 ? q[c.dofs_b[i]] : 0.0;
      v += c.normal[static_cast<Eigen::Index>(i)] * (qa - qb);
    }
    const double normal = std::max(c.normal_preload + c.kn * v, 0.0);
    EXPECT_GT(normal, 0.0) << c.name;
    const double tangential = alpha[static_cast<Eigen::Index>(ci)] * c.mu * normal;
    for (size_t i = 0; i < c.dofs_a.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      const double f = normal * c.normal[ii] + tangential * c.tangent[ii];
      if (c.dofs_a[i] >= 0) residual[c.dofs_a[i]] += f;
      if (c.dofs_b[i] >= 0) residual[c.dofs_b[i]] -= f;
    }
  }
  EXPECT_LT(residual.norm(), 1e-9 * 150.0);
}

TEST(TimeIntegration, UnstableStepIsReportedWithoutANumber) {
  // 8 steps per period at 20 Hz is far beyond the central-difference limit of the baseline's
  // full-stick system: no period is integrated, and the amplitude is NaN, never 0.
  TimeIntegrationOptions o;
  o.scheme = TimeIntegrationOptions::Scheme::kCentralDifference;
  o.freq_hz = 20.0;
  o.steps_per_period = 8;
  const Model m = testing::LoadBaseline().model;
  const TimeIntegrationResult r =
      IntegrateToSteadyState(m, Eigen::VectorXd::Zero(static_cast<int>(m.contacts.size())), o);
  EXPECT_EQ(r.status, TimeIntegrationResult::Status::kUnstable);
  EXPECT_TRUE(std::isnan(r.amplitude));
  EXPECT_NE(r.message.find("steps per period"), std::string::npos) << r.message;
}

TEST(TimeIntegration, MisuseThrows) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  EXPECT_THROW(IntegrateToSteadyState(model, Eigen::VectorXd::Zero(2), At(14.0)),
               std::invalid_argument);
  EXPECT_THROW(IntegrateToSteadyState(model, Eigen::VectorXd::Constant(1, 1.5), At(14.0)),
               std::invalid_argument);
  EXPECT_THROW(IntegrateToSteadyState(model, Eigen::VectorXd::Zero(1), At(0.0)),
               std::invalid_argument);
  TimeIntegrationOptions o = At(14.0);
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.min_periods = o.max_periods + 1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_periods"), std::string::npos) << error;
  o = At(14.0);
  o.steady_tolerance = -1e-6;  // 0 is "automatic"
  EXPECT_FALSE(o.IsValid(&error));
  o = At(14.0);
  o.ramp_periods = -2;  // −1 is "automatic"
  EXPECT_FALSE(o.IsValid(&error));
  o = At(14.0);
  o.window_periods = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = At(14.0);
  o.steps_per_period = 4;
  EXPECT_FALSE(o.IsValid(&error));
}

// 8 steps per 14 Hz period violate the central-difference limit of the 503 Hz normal DOF.
TEST(TimeIntegration, TooLargeStepIsReportedNotIntegrated) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  TimeIntegrationOptions o = At(14.0);
  o.scheme = TimeIntegrationOptions::Scheme::kCentralDifference;
  o.steps_per_period = 8;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::VectorXd::Zero(1), o);
  EXPECT_EQ(r.status, Status::kUnstable);
  EXPECT_GT(r.stability_ratio, 1.0);
  EXPECT_EQ(r.periods, 0);
  EXPECT_NE(r.message.find("steps per period"), std::string::npos) << r.message;
}

TEST(TimeIntegration, StopsAtMaxPeriodsWhenNotSettled) {
  const Model model = testing::LoadBaseline().model;
  TimeIntegrationOptions o = At(266.0);
  o.min_periods = 30;
  o.max_periods = 30;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::Vector4d::Zero(), o);
  EXPECT_EQ(r.status, Status::kNotSettled) << r.message;
  EXPECT_EQ(r.periods, 30);
  EXPECT_EQ(r.steps, 30 * 256);
  EXPECT_GT(r.amplitude, 0.0);
}

// ---- implicit modal scheme (the FE route) against independent references ----

TimeIntegrationOptions Implicit(double freq_hz, double cutoff_factor) {
  TimeIntegrationOptions o = At(freq_hz);
  o.scheme = TimeIntegrationOptions::Scheme::kImplicitModal;
  o.modal_cutoff_factor = cutoff_factor;
  return o;
}

// Linear (no contacts): the steady state is the linear free response; Newmark's period error
// (ωdt)²/12 ≈ 5e-5 at 256 steps, as for central differences.
TEST(ImplicitModal, WithoutContactsMatchesTheLinearFreeResponse) {
  Model model = testing::LoadBaseline().model;
  model.contacts.clear();
  for (double f : {200.0, 266.0}) {
    const TimeIntegrationResult r =
        IntegrateToSteadyState(model, Eigen::VectorXd(0), Implicit(f, 1e6));
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    EXPECT_EQ(r.scheme, "implicit-modal");
    const double linear = LinearResponseAmplitude(model, LinearSystemKind::kFree, {f})[0];
    std::printf("[ implicit linear ] %g Hz: %.6e m, linear %.6e m, rel %.2e (%d periods)\n", f,
                r.amplitude, linear, r.amplitude / linear - 1.0, r.periods);
    EXPECT_NEAR(r.amplitude, linear, 1e-3 * linear) << f << " Hz";
  }
}

// The same friction steady states as central differences on the lumped benchmark (both O(dt²)
// in the step, from the same static states): with all modes to 1e-3, and
// with the two modes above 1.5× the excitation taken quasi-statically (residual flexibility) to
// 5e-3 (measured 1.1e-3 to 3.2e-3: the quasi-static error of modes that close to the excitation).
// Same ramp length for both: the stuck state reached depends on the history (measured with all
// modes: 9e-5 to 1.9e-4).
TEST(ImplicitModal, MatchesCentralDifferencesOnTheLumpedBenchmark) {
  const Model model = testing::LoadBaseline().model;
  for (const Eigen::Vector4d& alpha : {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, -1, 1, -1),
                                       Eigen::Vector4d(-1, 1, -1, 1)}) {
    TimeIntegrationOptions o = At(266.0);
    o.scheme = TimeIntegrationOptions::Scheme::kCentralDifference;
    const TimeIntegrationResult ref = IntegrateToSteadyState(model, alpha, o);
    ASSERT_EQ(ref.status, Status::kSteadyState) << ref.message;
    for (double cutoff : {1e6, 1.5}) {
      TimeIntegrationOptions io = Implicit(266.0, cutoff);
      io.ramp_periods = 20;  // the history decides the stuck state: the same ramp length
      const TimeIntegrationResult r = IntegrateToSteadyState(model, alpha, io);
      ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
      std::printf(
          "[ implicit lumped ] alpha0 (%g %g %g %g) cutoff %gx: %d of %d modes, %.6e m vs central "
          "%.6e m, rel %.2e, %lld Newton steps (max %d per step)\n",
          alpha[0], alpha[1], alpha[2], alpha[3], cutoff, r.modes_integrated, model.num_dofs(),
          r.amplitude, ref.amplitude, r.amplitude / ref.amplitude - 1.0, r.contact_iterations,
          r.max_step_iterations);
      EXPECT_NEAR(r.amplitude, ref.amplitude, (cutoff > 10 ? 1e-3 : 5e-3) * ref.amplitude);
      EXPECT_EQ(r.regimes, ref.regimes);
      if (cutoff < 10) {
        EXPECT_LT(r.modes_integrated, model.num_dofs());
      }
    }
  }
}

// Stick-slip of a Jenkins oscillator: the implicit step matches the HBM like the explicit one.
TEST(ImplicitModal, JenkinsOscillatorMatchesHbm) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  HbmSystem sys(model, HbmOptions{5, 512});
  const Eigen::VectorXd alpha = Eigen::VectorXd::Zero(1);
  const auto pts = SolveAtFrequencies(sys, alpha, {14.0, 16.0, 20.0}, FrfOptions{});
  for (const FrfPoint& p : pts) {
    ASSERT_EQ(p.status, SolverStatus::kConverged) << p.freq_hz;
    const TimeIntegrationResult r = IntegrateToSteadyState(model, alpha, Implicit(p.freq_hz, 1e6));
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    EXPECT_NEAR(r.amplitude, p.amplitude, 0.02 * p.amplitude) << p.freq_hz << " Hz";
    EXPECT_EQ(r.regimes[0], p.regimes[0]) << p.freq_hz << " Hz";
  }
}

// kAuto keeps central differences where they are stable and switches beyond the limit.
TEST(ImplicitModal, AutoSchemeSwitchesBeyondTheExplicitLimit) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  TimeIntegrationOptions o = At(14.0);
  EXPECT_EQ(IntegrateToSteadyState(model, Eigen::VectorXd::Zero(1), o).scheme,
            "central-difference");
  o.steps_per_period = 8;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::VectorXd::Zero(1), o);
  EXPECT_EQ(r.scheme, "implicit-modal");
  EXPECT_GT(r.stability_ratio, 1.0);
  EXPECT_NE(r.status, Status::kUnstable) << r.message;
  EXPECT_TRUE(std::isfinite(r.amplitude));
}

// The windowed amplitude sees the forced response through free vibration that never decays: a
// 2-DOF system whose second mode (13 Hz) has no damping at all, started abruptly (no ramp) at
// 11.5 Hz. One-period amplitudes beat by tens of percent for ever; the Hann-windowed first
// harmonic over 200 periods settles on the linear forced response (leakage ~(Δf·T)⁻³ at
// Δf·T = 26 bins), which is what the harmonic balance computes.
TEST(ImplicitModal, WindowedAmplitudeSeesThroughUndampedFreeVibration) {
  Model model;
  model.dof_names = {"a.x", "b.x"};
  model.mass = Eigen::Matrix2d::Identity();
  Eigen::Matrix2d phi;
  phi << 1.0, 1.0, 1.0, -1.0;
  phi /= std::sqrt(2.0);
  const double w1 = kTwoPi * 10.0, w2 = kTwoPi * 13.0;
  model.stiffness = phi * Eigen::Vector2d(w1 * w1, w2 * w2).asDiagonal() * phi.transpose();
  model.damping = phi * Eigen::Vector2d(2 * 0.02 * w1, 0.0).asDiagonal() * phi.transpose();
  model.loads.push_back(HarmonicLoad{1, Eigen::VectorXd{{100.0, 0.0}}, Eigen::VectorXd::Zero(2)});
  model.response_dof = 0;
  model.free_dofs = {0, 1};
  TimeIntegrationOptions o = Implicit(11.5, 1e6);
  o.ramp_periods = 0;
  // 1024 steps: Newmark's period error, amplified by the undamped mode next to the excitation,
  // is 2.9e-3 at 256 steps and 2.1e-4 here (O(dt²): the window itself adds nothing visible).
  o.steps_per_period = 1024;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::VectorXd(0), o);
  ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
  const double linear = LinearResponseAmplitude(model, LinearSystemKind::kFree, {11.5})[0];
  std::printf(
      "[ free vibration ] windowed %.6e m, linear %.6e m, rel %.2e, one-period spread %.2f\n",
      r.amplitude, linear, r.amplitude / linear - 1.0, r.free_vibration);
  EXPECT_GT(r.free_vibration, 0.1) << "the test needs free vibration that does not decay";
  EXPECT_NEAR(r.amplitude, linear, 1e-3 * linear);
}

// A contact solve that cannot converge stops the run with no number: one Newton step per time
// step is enough while the Jenkins contact sticks, not at its first slip.
TEST(ImplicitModal, ContactSolveFailureIsReportedWithoutANumber) {
  const Model model = testing::JenkinsOscillator(1.0, 1e4, 1.0, 1e4, 1.0, 5.0, 8.0);
  TimeIntegrationOptions o = Implicit(16.0, 1e6);
  o.max_contact_iterations = 1;
  const TimeIntegrationResult r = IntegrateToSteadyState(model, Eigen::VectorXd::Zero(1), o);
  EXPECT_EQ(r.status, Status::kContactFailed) << r.message;
  EXPECT_TRUE(std::isnan(r.amplitude));
  EXPECT_NE(r.message.find("did not converge"), std::string::npos) << r.message;
  EXPECT_EQ(ToString(r.status), "contact-failed");
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

// A harmonic-balance solution integrated from its own state at t = 0 stays on it: the lumped
// benchmark at 266 Hz (stick-slip on the outer contacts) at three α, H = 5. The run settles after
// its first two windows (nothing to ramp, no static state to leave) on the HBM amplitude to the
// truncation error.
TEST(PeriodicStart, AHarmonicBalanceSolutionHoldsUnderTimeIntegration) {
  const Model model = testing::LoadBaseline().model;
  const HbmSystem sys(model, HbmOptions{5, 256});
  for (const Eigen::Vector4d& alpha : {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(1, -1, 1, -1),
                                       Eigen::Vector4d(-0.5, 0.5, 0.3, -0.2)}) {
    const FrfPoint p = SolveAtFrequency(sys, alpha, 266.0, Eigen::VectorXd(), FrfOptions{});
    ASSERT_EQ(p.status, SolverStatus::kConverged);
    const double omega = RadPerS(266.0);
    const PeriodicStart start = PeriodicStartOf(model, sys, p.x, omega, alpha);
    TimeIntegrationOptions o = At(266.0);
    o.window_periods = 50;
    o.max_periods = 400;
    o.min_periods = 1;
    const TimeIntegrationResult r = IntegrateFromPeriodicState(model, start, o);
    ASSERT_EQ(r.status, Status::kSteadyState) << r.message;
    EXPECT_EQ(r.periods, 2 * o.window_periods);
    // Measured: 1e-4 to 3e-4 relative (H = 5), window-to-window change 7e-7 to 8e-6.
    EXPECT_NEAR(r.amplitude, p.amplitude, 1e-3 * p.amplitude);
    EXPECT_LT(r.relative_change, 1e-4);
    EXPECT_LT(r.free_vibration, 1e-4);
  }
}

TEST(PeriodicStart, MisuseThrows) {
  const Model model = testing::LoadBaseline().model;
  const HbmSystem sys(model, HbmOptions{1, 64});
  EXPECT_THROW(PeriodicStartOf(model, sys, Eigen::VectorXd::Zero(3), 1.0, Eigen::VectorXd::Zero(4)),
               std::invalid_argument);
  PeriodicStart s{Eigen::VectorXd::Zero(model.num_dofs()), Eigen::VectorXd::Zero(model.num_dofs()),
                  Eigen::VectorXd::Zero(4)};
  s.contact_alpha[0] = 1.5;
  EXPECT_THROW(IntegrateFromPeriodicState(model, s, At(266.0)), std::invalid_argument);
  s.contact_alpha[0] = 0.0;
  s.velocity.resize(2);
  EXPECT_THROW(IntegrateFromPeriodicState(model, s, At(266.0)), std::invalid_argument);
}

}  // namespace
}  // namespace fricrom
