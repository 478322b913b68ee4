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

namespace fricrom {
namespace {

// One contact's geometry (ground entries dropped) and its incremental law state.
struct ContactTerm {
  std::vector<int> dof_a, dof_b;  // DOF indices
  std::vector<double> n_a, t_a;   // normal/tangent components on the side-A DOFs
  std::vector<double> n_b, t_b;
  double kn = 0.0, kt = 0.0, mu = 0.0, n0 = 0.0;
  // Law state: tangential force and tangential displacement of the previous step.
  double t_prev = 0.0, u_prev = 0.0;

  void Relative(const Eigen::VectorXd& q, double* u, double* v) const {
    double uu = 0.0, vv = 0.0;
    for (size_t i = 0; i < dof_a.size(); ++i) {
      uu += t_a[i] * q[dof_a[i]];
      vv += n_a[i] * q[dof_a[i]];
    }
    for (size_t i = 0; i < dof_b.size(); ++i) {
      uu -= t_b[i] * q[dof_b[i]];
      vv -= n_b[i] * q[dof_b[i]];
    }
    *u = uu;
    *v = vv;
  }
  // Adds the generalised contact force (+F on A, −F on B in the K q + F_C convention, i.e. the
  // force N n + T t acting on B) to fc.
  void Scatter(double normal, double tangential, Eigen::VectorXd* fc) const {
    for (size_t i = 0; i < dof_a.size(); ++i) {
      (*fc)[dof_a[i]] += normal * n_a[i] + tangential * t_a[i];
    }
    for (size_t i = 0; i < dof_b.size(); ++i) {
      (*fc)[dof_b[i]] -= normal * n_b[i] + tangential * t_b[i];
    }
  }
  // The contact law advanced by one sample: the same step as the AFT's (AdvanceContact).
  ContactState Advance(double u, double v, double* normal, double* tangential) {
    const ContactStep at = AdvanceContact(ContactLawParams{kn, kt, mu, n0}, t_prev, u - u_prev, v);
    t_prev = at.tangential;
    u_prev = u;
    *normal = at.normal;
    *tangential = at.tangential;
    return at.state;
  }
};

std::vector<ContactTerm> BuildContacts(const Model& model) {
  std::vector<ContactTerm> terms;
  for (const Contact& c : model.contacts) {
    ContactTerm t;
    for (size_t i = 0; i < c.dofs_a.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      if (c.dofs_a[i] >= 0) {
        t.dof_a.push_back(c.dofs_a[i]);
        t.n_a.push_back(c.normal[ii]);
        t.t_a.push_back(c.tangent[ii]);
      }
      if (c.dofs_b[i] >= 0) {
        t.dof_b.push_back(c.dofs_b[i]);
        t.n_b.push_back(c.normal[ii]);
        t.t_b.push_back(c.tangent[ii]);
      }
    }
    t.kn = c.kn;
    t.kt = c.kt;
    t.mu = c.mu;
    t.n0 = c.normal_preload;
    terms.push_back(std::move(t));
  }
  return terms;
}

// Static equilibrium K q + F_C(q) = F0 with T = α μ N on every closed contact, by an active set on
// the open/closed status. On a closed contact N = N0 + kn v is linear in q, so each active set is
// one linear solve. Returns false (with a message) if singular or if the active set cycles.
bool SolveStatic(const Model& model, const std::vector<ContactTerm>& terms,
                 const Eigen::VectorXd& alpha, const Eigen::VectorXd& f0, Eigen::VectorXd* q,
                 std::string* message) {
  const int nc = static_cast<int>(terms.size());
  std::vector<bool> closed(static_cast<size_t>(nc), true);
  const int max_sets = 2 * nc + 10;
  for (int iter = 0; iter < max_sets; ++iter) {
    Eigen::MatrixXd a = model.stiffness;
    Eigen::VectorXd rhs = f0;
    for (int c = 0; c < nc; ++c) {
      if (!closed[static_cast<size_t>(c)]) continue;
      const ContactTerm& ct = terms[static_cast<size_t>(c)];
      const double s = alpha[c] * ct.mu;
      // Side A feels +N g with g = n + α μ t and N = N0 + kn (nᵀ q_A − nᵀ q_B); side B feels −N g.
      auto add_row = [&](int dof, double g, double sign) {
        rhs[dof] -= sign * ct.n0 * g;
        for (size_t j = 0; j < ct.dof_a.size(); ++j)
          a(dof, ct.dof_a[j]) += sign * ct.kn * g * ct.n_a[j];
        for (size_t j = 0; j < ct.dof_b.size(); ++j)
          a(dof, ct.dof_b[j]) -= sign * ct.kn * g * ct.n_b[j];
      };
      for (size_t i = 0; i < ct.dof_a.size(); ++i)
        add_row(ct.dof_a[i], ct.n_a[i] + s * ct.t_a[i], 1.0);
      for (size_t i = 0; i < ct.dof_b.size(); ++i)
        add_row(ct.dof_b[i], ct.n_b[i] + s * ct.t_b[i], -1.0);
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (!lu.isInvertible()) {
      *message = "static problem is singular (unconstrained DOFs with the current contact set)";
      return false;
    }
    *q = lu.solve(rhs);
    if (!q->allFinite()) {
      *message = "static solution is not finite";
      return false;
    }
    bool changed = false;
    for (int c = 0; c < nc; ++c) {
      double u, v;
      terms[static_cast<size_t>(c)].Relative(*q, &u, &v);
      const ContactTerm& ct = terms[static_cast<size_t>(c)];
      const bool now_closed = ct.n0 + ct.kn * v > 0.0;
      if (now_closed != closed[static_cast<size_t>(c)]) {
        closed[static_cast<size_t>(c)] = now_closed;
        changed = true;
      }
    }
    if (!changed) return true;
  }
  *message = "static contact status did not settle (open/closed set cycles)";
  return false;
}

double FirstHarmonicAmplitude(const Eigen::VectorXd& samples, const Eigen::VectorXd& cos_table,
                              const Eigen::VectorXd& sin_table) {
  const double scale = 2.0 / static_cast<double>(samples.size());
  return std::hypot(scale * samples.dot(cos_table), scale * samples.dot(sin_table));
}

// Half-cosine ramp 0 → 1 over [0, t_ramp]: continuous with a continuous first derivative.
double Ramp(double t, double t_ramp) {
  if (t_ramp <= 0.0 || t >= t_ramp) return 1.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * t / t_ramp));
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
  if (ramp_periods < 0 || ramp_periods >= max_periods) {
    return fail("ramp_periods must lie in [0, max_periods), got " + std::to_string(ramp_periods));
  }
  if (block_periods < 1) {
    return fail("block_periods must be >= 1, got " + std::to_string(block_periods));
  }
  if (!(std::isfinite(steady_tolerance) && steady_tolerance > 0.0)) {
    return fail("steady_tolerance must be finite and > 0, got " + std::to_string(steady_tolerance));
  }
  if (!(stability_fraction > 0.0 && stability_fraction <= 1.0)) {
    return fail("stability_fraction must lie in (0, 1], got " + std::to_string(stability_fraction));
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
  }
  return "unknown";
}

TimeIntegrationResult IntegrateToSteadyState(const Model& model, const Eigen::VectorXd& alpha,
                                             const TimeIntegrationOptions& options) {
  using Status = TimeIntegrationResult::Status;
  std::string error;
  if (!options.IsValid(&error)) {
    throw std::invalid_argument("IntegrateToSteadyState: " + error);
  }
  model.Validate();
  const int n = model.num_dofs();
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

  TimeIntegrationResult result;
  const int ns = options.steps_per_period;
  const double period = 1.0 / options.freq_hz;
  const double dt = period / ns;

  // Stability: the full-stick system is the stiffest state (throws if M is not positive definite).
  const ModalResult stick = StickSystemModes(model);
  const double omega_max = RadPerS(stick.frequencies_hz.maxCoeff());
  result.stability_ratio = omega_max * dt / 2.0;
  if (result.stability_ratio > options.stability_fraction) {
    std::ostringstream s;
    s << "time step too large for central differences: omega_max*dt/2 = " << result.stability_ratio
      << " > " << options.stability_fraction << " (full-stick omega_max = " << Hz(omega_max)
      << " Hz); use at least "
      << static_cast<int>(std::ceil(omega_max * period / (2.0 * options.stability_fraction)))
      << " steps per period";
    result.status = Status::kUnstable;
    result.message = s.str();
    return result;
  }

  // Loads: static part and the harmonic part sampled over one period (t_k = k dt).
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd fh = Eigen::MatrixXd::Zero(n, ns);
  for (const HarmonicLoad& l : model.loads) {
    if (l.harmonic == 0) {
      f0 += l.cos;
      continue;
    }
    for (int k = 0; k < ns; ++k) {
      // Reduce h·k mod N first: exact phases over arbitrarily many periods.
      const double theta =
          kTwoPi * static_cast<double>((static_cast<long long>(l.harmonic) * k) % ns) / ns;
      fh.col(k) += l.cos * std::cos(theta) + l.sin * std::sin(theta);
    }
  }

  // Static state for the prescribed α.
  std::vector<ContactTerm> terms = BuildContacts(model);
  Eigen::VectorXd q;
  if (!SolveStatic(model, terms, initial_alpha, f0, &q, &error)) {
    result.status = Status::kStaticFailed;
    result.message = error;
    return result;
  }
  result.static_displacement = q;
  for (int c = 0; c < nc; ++c) {
    ContactTerm& ct = terms[static_cast<size_t>(c)];
    double u, v;
    ct.Relative(q, &u, &v);
    const double nk = std::max(ct.n0 + ct.kn * v, 0.0);
    ct.u_prev = u;
    ct.t_prev = nk > 0.0 ? initial_alpha[c] * ct.mu * nk : 0.0;
  }

  // Central-difference operators: q_{n+1} = A⁻¹(F − F_C) + P q_n + Q q_{n−1}.
  const Eigen::MatrixXd lhs = model.mass / (dt * dt) + model.damping / (2.0 * dt);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lhs_lu(lhs);
  const Eigen::MatrixXd a_inv = lhs_lu.inverse();
  const Eigen::MatrixXd p_mat = a_inv * (2.0 * model.mass / (dt * dt) - model.stiffness);
  const Eigen::MatrixXd q_mat = a_inv * (model.damping / (2.0 * dt) - model.mass / (dt * dt));

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
  double prev_block_amplitude = -1.0;  // amplitude at the previous fully excited block end
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
      force = f0 + Ramp(t, t_ramp) * fh.col(k) - fc;
      if (p == 0 && k == 0) {
        // Start from rest: q_{−1} = q_0 + dt²/2 q̈_0 (q̇_0 = 0).
        const Eigen::VectorXd acc = model.mass.llt().solve(force - model.stiffness * q);
        q_prev = q + 0.5 * dt * dt * acc;
      }
      q_next.noalias() = a_inv * force;
      q_next.noalias() += p_mat * q;
      q_next.noalias() += q_mat * q_prev;
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
    amplitude =
        FirstHarmonicAmplitude(disp.row(model.response_dof).transpose(), cos_table, sin_table);
    if (done % options.block_periods != 0 || done <= options.ramp_periods) continue;
    if (prev_block_amplitude >= 0.0) {
      const double diff = std::abs(amplitude - prev_block_amplitude);
      result.relative_change = diff == 0.0 ? 0.0 : diff / std::max(amplitude, 1e-300);
      if (result.relative_change <= options.steady_tolerance && done >= options.min_periods) {
        result.status = Status::kSteadyState;
        break;
      }
    }
    prev_block_amplitude = amplitude;
  }

  result.amplitude = amplitude;
  result.last_period_displacements = disp;
  result.last_period_response = disp.row(model.response_dof).transpose();
  result.last_period_tangential = tang;
  result.last_period_normal = norm;
  result.regimes.clear();
  result.equivalent_alpha = Eigen::VectorXd::Zero(nc);
  for (int c = 0; c < nc; ++c) {
    result.regimes.push_back(ClassifyRegime(states[static_cast<size_t>(c)]));
    const double limit = model.contacts[static_cast<size_t>(c)].mu * norm(c, 0);
    if (limit > 0.0) result.equivalent_alpha[c] = std::clamp(tang(c, 0) / limit, -1.0, 1.0);
  }
  if (result.status != Status::kUnstable) {
    std::ostringstream s;
    s << (result.status == Status::kSteadyState ? "steady state" : "not settled") << " after "
      << result.periods << " periods (relative amplitude change " << result.relative_change
      << ", tolerance " << options.steady_tolerance << ")";
    result.message = s.str();
  }
  return result;
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
