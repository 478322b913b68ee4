// Direct time integration to steady state, the independent check of the HBM (time_integration.h).
//
// Scheme: central differences (explicit), with the contact forces evaluated at the current
// displacement q_n and the damping on the centred velocity (q_{n+1} − q_{n−1}) / 2dt:
//   (M/dt² + C/2dt) q_{n+1} = F(t_n) − K q_n − F_C(q_n) + (2M/dt²) q_n − (M/dt² − C/2dt) q_{n−1}.
// Why this scheme for the nonsmooth contact law:
//  - The contact law is exactly the AFT's incremental predictor–corrector, fed with one new
//    displacement per step: no iteration on stick/slip/lift-off switches (an implicit scheme would
//    need a nonsmooth Newton per step, with chattering active sets at the transitions), and the
//    tangential history is advanced exactly once per sample, as in EvaluateContactLaw.
//  - The law is at most as stiff as the full-stick springs (slip and lift-off remove stiffness),
//    so the linear stability limit dt < 2/ω_max of the full-stick system bounds every state; it is
//    checked before integrating. For the lumped benchmark ω_max dt ≈ 0.04 at 256 steps/period,
//    far inside the limit: the step is set by the sampling of the contact law, not by stability.
//  - Second-order accurate, no numerical damping (the steady amplitude of a lightly damped
//    resonance is not biased by algorithmic dissipation), and damping with the centred velocity
//    keeps the limit ω dt < 2 for any C.
//  - (M/dt² + C/2dt) is constant: it is inverted once, and a step costs three small mat-vecs.
#include "fricrom/time_integration.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "fricrom/contact_law.h"
#include "fricrom/linear.h"
#include "fricrom/units.h"
#include "linear/dense_lapack.h"
#include "verify/time_stepping.h"

namespace fricrom {

using time_stepping::ContactTerm;

TimeIntegrationResult IntegrateImplicitModal(const Model& model, const Eigen::VectorXd& alpha,
                                             const TimeIntegrationOptions& options,
                                             const ModalResult& stick, const PeriodicStart* start);

namespace {

// Central differences from the static state (file comment); stick: the full-stick modes.
TimeIntegrationResult IntegrateCentralDifference(const Model& model,
                                                 const Eigen::VectorXd& initial_alpha,
                                                 const TimeIntegrationOptions& options,
                                                 double omega_max);

}  // namespace

namespace {

// The full-stick system is the stiffest state the contacts can take: its ω_max sets the explicit
// limit, its modes are the implicit scheme's basis (throws if M is not positive definite).
// FE-sized systems use LAPACK's dsygvd; small ones keep Eigen's solver, bit for bit.
ModalResult FullStickModes(const Model& model, const std::string& caller) {
  RequireNoCyclicContacts(model, caller);
  ModalResult stick;
  if (model.num_dofs() <= 200) return StickSystemModes(model);
  Eigen::VectorXd lambda;
  if (!dense::SymmetricGeneralizedEigen(model.stiffness + ContactStickStiffness(model), model.mass,
                                        &lambda, &stick.shapes)) {
    throw std::invalid_argument(caller +
                                ": the mass matrix is not positive definite (directions without "
                                "mass, e.g. a superelement's semi-definite mass): time "
                                "integration needs mass in every direction");
  }
  stick.frequencies_hz = lambda.unaryExpr(&HzFromEigenvalue);
  return stick;
}

}  // namespace

bool TimeIntegrationOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(std::isfinite(freq_hz) && freq_hz > 0.0)) {
    return fail("freq_hz must be finite and > 0, got " + std::to_string(freq_hz));
  }
  if (steps_per_period < 8) {
    return fail("steps_per_period must be >= 8, got " + std::to_string(steps_per_period));
  }
  if (min_periods < 1 || max_periods < min_periods) {
    return fail("need 1 <= min_periods <= max_periods, got " + std::to_string(min_periods) +
                " and " + std::to_string(max_periods));
  }
  if (ramp_periods < -1 || ramp_periods >= max_periods) {
    return fail("ramp_periods must be -1 (automatic) or lie in [0, max_periods), got " +
                std::to_string(ramp_periods));
  }
  if (window_periods < 1) {
    return fail("window_periods must be >= 1, got " + std::to_string(window_periods));
  }
  if (block_periods < 1) {
    return fail("block_periods must be >= 1, got " + std::to_string(block_periods));
  }
  if (!(std::isfinite(steady_tolerance) && steady_tolerance >= 0.0)) {
    return fail("steady_tolerance must be finite and >= 0 (0: automatic), got " +
                std::to_string(steady_tolerance));
  }
  if (!(stability_fraction > 0.0 && stability_fraction <= 1.0)) {
    return fail("stability_fraction must lie in (0, 1], got " + std::to_string(stability_fraction));
  }
  if (!(std::isfinite(modal_cutoff_factor) && modal_cutoff_factor >= 1.0)) {
    return fail("modal_cutoff_factor must be finite and >= 1, got " +
                std::to_string(modal_cutoff_factor));
  }
  if (max_contact_iterations < 1) {
    return fail("max_contact_iterations must be >= 1, got " +
                std::to_string(max_contact_iterations));
  }
  return true;
}

std::string ToString(TimeIntegrationResult::Status status) {
  switch (status) {
    case TimeIntegrationResult::Status::kSteadyState:
      return "steady-state";
    case TimeIntegrationResult::Status::kNotSettled:
      return "not-settled";
    case TimeIntegrationResult::Status::kUnstable:
      return "unstable";
    case TimeIntegrationResult::Status::kStaticFailed:
      return "static-failed";
    case TimeIntegrationResult::Status::kContactFailed:
      return "contact-failed";
  }
  return "unknown";
}

TimeIntegrationResult IntegrateToSteadyState(const Model& model, const Eigen::VectorXd& alpha,
                                             const TimeIntegrationOptions& options) {
  RequireNoCyclicContacts(model, "time integration");
  std::string error;
  if (!options.IsValid(&error)) {
    throw std::invalid_argument("IntegrateToSteadyState: " + error);
  }
  model.Validate();
  const int nc = static_cast<int>(model.contacts.size());
  if (alpha.size() != model.num_alpha()) {
    throw std::invalid_argument("IntegrateToSteadyState: initial_alpha needs one value per α (" +
                                std::to_string(model.num_alpha()) + "), got " +
                                std::to_string(alpha.size()));
  }
  const Eigen::VectorXd initial_alpha = model.ContactAlpha(alpha);  // per contact
  for (int c = 0; c < nc; ++c) {
    if (!(std::abs(initial_alpha[c]) <= 1.0)) {
      throw std::invalid_argument("IntegrateToSteadyState: initial_alpha[" + std::to_string(c) +
                                  "] must lie in [-1, 1], got " + std::to_string(initial_alpha[c]));
    }
  }

  const ModalResult stick = FullStickModes(model, "IntegrateToSteadyState");
  const double omega_max = RadPerS(stick.frequencies_hz.maxCoeff());
  const double ratio = omega_max / (options.freq_hz * options.steps_per_period) / 2.0;
  TimeIntegrationOptions resolved = options;
  if (options.scheme == TimeIntegrationOptions::Scheme::kImplicitModal ||
      (options.scheme == TimeIntegrationOptions::Scheme::kAuto &&
       ratio > options.stability_fraction)) {
    if (resolved.ramp_periods < 0) resolved.ramp_periods = 300;
    if (resolved.steady_tolerance == 0.0) resolved.steady_tolerance = 1e-4;
    resolved.max_periods = std::max(resolved.max_periods, resolved.ramp_periods + 1);
    TimeIntegrationResult r =
        IntegrateImplicitModal(model, initial_alpha, resolved, stick, nullptr);
    r.stability_ratio = ratio;
    return r;
  }
  if (resolved.ramp_periods < 0) resolved.ramp_periods = 20;
  if (resolved.steady_tolerance == 0.0) resolved.steady_tolerance = 1e-6;
  resolved.max_periods = std::max(resolved.max_periods, resolved.ramp_periods + 1);
  return IntegrateCentralDifference(model, initial_alpha, resolved, omega_max);
}

namespace {

// The loads sampled over one period (t_k = k dt): the static part f0 and the harmonic part fh.
void SampleLoads(const Model& model, int ns, Eigen::VectorXd* f0, Eigen::MatrixXd* fh) {
  const int n = model.num_dofs();
  *f0 = Eigen::VectorXd::Zero(n);
  *fh = Eigen::MatrixXd::Zero(n, ns);
  for (const HarmonicLoad& l : model.loads) {
    if (l.harmonic == 0) {
      *f0 += l.cos;
      continue;
    }
    for (int k = 0; k < ns; ++k) {
      // Reduce h·k mod N first: exact phases over arbitrarily many periods.
      const double theta =
          kTwoPi * static_cast<double>((static_cast<long long>(l.harmonic) * k) % ns) / ns;
      fh->col(k) += l.cos * std::cos(theta) + l.sin * std::sin(theta);
    }
  }
}

// Central-difference operators: q_{n+1} = A⁻¹(F − F_C) + P q_n + Q q_{n−1}.
struct CentralDifference {
  CentralDifference(const Model& model, double dt) {
    const Eigen::MatrixXd lhs = model.mass / (dt * dt) + model.damping / (2.0 * dt);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lhs_lu(lhs);
    a_inv = lhs_lu.inverse();
    p = a_inv * (2.0 * model.mass / (dt * dt) - model.stiffness);
    q = a_inv * (model.damping / (2.0 * dt) - model.mass / (dt * dt));
  }
  Eigen::MatrixXd a_inv, p, q;
};

// Whether central differences are stable at dt = period / steps_per_period (ω_max dt / 2 within
// stability_fraction); if not, the result is kUnstable and says how many steps would be.
bool StableStep(double omega_max, double period, const TimeIntegrationOptions& options,
                TimeIntegrationResult* result) {
  result->stability_ratio = omega_max * (period / options.steps_per_period) / 2.0;
  if (result->stability_ratio <= options.stability_fraction) return true;
  std::ostringstream s;
  s << "time step too large for central differences: omega_max*dt/2 = " << result->stability_ratio
    << " > " << options.stability_fraction << " (full-stick omega_max = " << Hz(omega_max)
    << " Hz); use at least "
    << static_cast<int>(std::ceil(omega_max * period / (2.0 * options.stability_fraction)))
    << " steps per period";
  result->status = TimeIntegrationResult::Status::kUnstable;
  result->message = s.str();
  return false;
}

TimeIntegrationResult IntegrateCentralDifference(const Model& model,
                                                 const Eigen::VectorXd& initial_alpha,
                                                 const TimeIntegrationOptions& options,
                                                 double omega_max) {
  using Status = TimeIntegrationResult::Status;
  using time_stepping::FinishResult;
  const int n = model.num_dofs();
  const int nc = static_cast<int>(model.contacts.size());
  std::string error;
  TimeIntegrationResult result;
  result.scheme = "central-difference";
  const int ns = options.steps_per_period;
  const double period = 1.0 / options.freq_hz;
  const double dt = period / ns;
  if (!StableStep(omega_max, period, options, &result)) return result;

  Eigen::VectorXd f0;
  Eigen::MatrixXd fh;
  SampleLoads(model, ns, &f0, &fh);

  // Static state for the prescribed α.
  std::vector<ContactTerm> terms = time_stepping::BuildContacts(model);
  Eigen::VectorXd q;
  if (!time_stepping::SolveStatic(model, terms, initial_alpha, f0, &q, &error)) {
    result.status = Status::kStaticFailed;
    result.message = error;
    return result;
  }
  result.static_displacement = q;
  time_stepping::SeatContacts(q, initial_alpha, &terms);

  const CentralDifference cd(model, dt);

  // First-harmonic tables of one period.
  Eigen::VectorXd cos_table(ns), sin_table(ns);
  for (int k = 0; k < ns; ++k) {
    cos_table[k] = std::cos(kTwoPi * k / ns);
    sin_table[k] = std::sin(kTwoPi * k / ns);
  }

  // Buffers of the current period.
  Eigen::MatrixXd disp(n, ns), tang(nc, ns), norm(nc, ns);
  std::vector<std::vector<ContactState>> states(static_cast<size_t>(nc),
                                                std::vector<ContactState>(static_cast<size_t>(ns)));

  const double t_ramp = options.ramp_periods * period;
  Eigen::VectorXd q_prev(n), q_next(n), force(n), fc(n);
  time_stepping::SteadyTest steady(options);
  double amplitude = 0.0;
  result.status = Status::kNotSettled;

  for (int p = 0; p < options.max_periods; ++p) {
    for (int k = 0; k < ns; ++k) {
      const double t = (static_cast<double>(p) * ns + k) * dt;
      fc.setZero();
      for (int c = 0; c < nc; ++c) {
        ContactTerm& ct = terms[static_cast<size_t>(c)];
        double u, v, nk, tk;
        ct.Relative(q, &u, &v);
        states[static_cast<size_t>(c)][static_cast<size_t>(k)] = ct.Advance(u, v, &nk, &tk);
        ct.Scatter(nk, tk, &fc);
        tang(c, k) = tk;
        norm(c, k) = nk;
      }
      disp.col(k) = q;
      force = f0 + time_stepping::Ramp(t, t_ramp) * fh.col(k) - fc;
      if (p == 0 && k == 0) {
        // Start from rest: q_{−1} = q_0 + dt²/2 q̈_0 (q̇_0 = 0).
        const Eigen::VectorXd acc = model.mass.llt().solve(force - model.stiffness * q);
        q_prev = q + 0.5 * dt * dt * acc;
      }
      q_next.noalias() = cd.a_inv * force;
      q_next.noalias() += cd.p * q;
      q_next.noalias() += cd.q * q_prev;
      q_prev.swap(q);
      q.swap(q_next);
    }
    const int done = p + 1;
    result.periods = done;
    result.steps = done * ns;
    if (!q.allFinite() || !disp.allFinite()) {
      result.status = Status::kUnstable;
      result.message = "solution blew up (non-finite) in period " + std::to_string(done);
      break;
    }
    amplitude = time_stepping::FirstHarmonicAmplitude(disp.row(model.response_dof).transpose(),
                                                      cos_table, sin_table);
    if (steady.Settled(done, amplitude, &result)) break;
  }

  // A blown-up run keeps amplitude NaN: a failed run is never a number.
  if (result.status != Status::kUnstable) {
    FinishResult(model, disp, tang, norm, states, amplitude, options, &result);
  }
  return result;
}

}  // namespace

PeriodicStart PeriodicStartOf(const Model& model, const HarmonicBalance& system,
                              const Eigen::VectorXd& x, double omega,
                              const Eigen::VectorXd& alpha) {
  const int n = model.num_dofs(), h_max = system.harmonics();
  const Eigen::VectorXd dof = system.ToDofCoefficients(x, omega, alpha);
  const std::vector<ContactHistory> hist = system.ContactHistories(x, omega, alpha);
  if (dof.size() != static_cast<Eigen::Index>(n) * (2 * h_max + 1) ||
      hist.size() != model.contacts.size()) {
    throw std::invalid_argument("PeriodicStartOf: the balance is not one of this model (" +
                                std::to_string(dof.size()) + " coefficients, " +
                                std::to_string(hist.size()) + " contacts)");
  }
  // q(t) = q̂0 + Σ a_h cos hωt + b_h sin hωt at t = 0, and its derivative.
  PeriodicStart s{dof.head(n), Eigen::VectorXd::Zero(n),
                  Eigen::VectorXd::Zero(static_cast<Eigen::Index>(hist.size()))};
  for (int h = 1; h <= h_max; ++h) {
    s.displacement += dof.segment(static_cast<Eigen::Index>(2 * h - 1) * n, n);
    s.velocity += (h * omega) * dof.segment(static_cast<Eigen::Index>(2 * h) * n, n);
  }
  for (size_t c = 0; c < hist.size(); ++c) {
    const double limit = model.contacts[c].mu * hist[c].normal[0];
    // Round-off may put a slipping contact a hair beyond the limit.
    if (limit > 0.0) s.contact_alpha[c] = std::clamp(hist[c].tangential[0] / limit, -1.0, 1.0);
  }
  return s;
}

TimeIntegrationResult IntegrateFromPeriodicState(const Model& model, const PeriodicStart& start,
                                                 const TimeIntegrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) {
    throw std::invalid_argument("IntegrateFromPeriodicState: " + error);
  }
  model.Validate();
  RequireNoCyclicContacts(model, "time integration");
  const int n = model.num_dofs();
  if (start.displacement.size() != n || start.velocity.size() != n ||
      start.contact_alpha.size() != static_cast<Eigen::Index>(model.contacts.size())) {
    throw std::invalid_argument(
        "IntegrateFromPeriodicState: the start needs q and q-dot per DOF (" + std::to_string(n) +
        ") and alpha per contact (" + std::to_string(model.contacts.size()) + ")");
  }
  if (!start.displacement.allFinite() || !start.velocity.allFinite() ||
      !(start.contact_alpha.cwiseAbs().maxCoeff() <= 1.0 || start.contact_alpha.size() == 0)) {
    throw std::invalid_argument(
        "IntegrateFromPeriodicState: the start must be finite with |alpha| <= 1");
  }
  const ModalResult stick = FullStickModes(model, "IntegrateFromPeriodicState");
  TimeIntegrationOptions resolved = options;
  resolved.ramp_periods = 0;
  if (resolved.steady_tolerance == 0.0) resolved.steady_tolerance = 1e-4;
  TimeIntegrationResult r =
      IntegrateImplicitModal(model, start.contact_alpha, resolved, stick, &start);
  r.stability_ratio =
      RadPerS(stick.frequencies_hz.maxCoeff()) / (options.freq_hz * options.steps_per_period) / 2;
  return r;
}

Eigen::VectorXd LastPeriodCoefficients(const TimeIntegrationResult& result, int harmonics) {
  const Eigen::MatrixXd& d = result.last_period_displacements;
  const auto ns = d.cols();
  if (ns == 0 || d.rows() == 0) {
    throw std::invalid_argument("LastPeriodCoefficients: the result holds no period");
  }
  if (harmonics < 0 || 2 * harmonics >= ns) {
    throw std::invalid_argument("LastPeriodCoefficients: harmonics must lie in [0, N/2), got " +
                                std::to_string(harmonics));
  }
  const auto n = d.rows();
  Eigen::VectorXd x(n * (2 * harmonics + 1));
  x.head(n) = d.rowwise().mean();
  for (int h = 1; h <= harmonics; ++h) {
    Eigen::VectorXd c(ns), s(ns);
    for (Eigen::Index k = 0; k < ns; ++k) {
      const double theta = kTwoPi * static_cast<double>((h * k) % ns) / static_cast<double>(ns);
      c[k] = std::cos(theta);
      s[k] = std::sin(theta);
    }
    const double scale = 2.0 / static_cast<double>(ns);
    x.segment((2 * h - 1) * n, n) = scale * d * c;
    x.segment(2 * h * n, n) = scale * d * s;
  }
  return x;
}

}  // namespace fricrom
