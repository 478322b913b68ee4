// Implicit modal time integration (time_integration.h, scheme kImplicitModal).
//
// With K_s = K + Σ (contact stick springs), the full-stick stiffness, the contact forces split
// into their stick-linear part and the rest: F_C = K_c q + Dᵀ g̃, where D stacks each contact's
// relative displacements d_c = (u, v) and g̃_c = (T − kt u, N − kn v). Then
//   M q̈ + C q̇ + K_s q = F w(t) − Dᵀ g̃(d, history).
// The full-stick modes Φ below the cutoff carry the dynamics and the rest respond quasi-
// statically: q = Φ η + R (F w − Dᵀ g̃), with the residual flexibility R = K_s⁻¹ − Φ Λ⁻¹ Φᵀ (exact
// at ω = 0; the modes above the cutoff are ≥ 20× the excitation by default). Newmark's average
// acceleration on η (unconditionally stable, no numerical damping) makes the contact rows at
// t_{n+1} an affine function of that step's g̃:
//   d = d₀ − S g̃(d),   S = β dt² Ψ M_eff⁻¹ Ψᵀ + D R Dᵀ,   Ψ = D Φ,
// solved per step by a semismooth Newton method: g̃ is piecewise linear in d (constant in stick,
// slope −kt/−kn in slip and lift-off), so only slipping or open rows enter the Newton matrix
// (I + G S)_RR, and once the stick/slip/lift-off set is right the step is exact. The law is
// AdvanceContact (the AFT's), applied from the last step's committed state, as in the explicit
// scheme. A step costs O(m·(k + changed rows)) while everything sticks.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "fricrom/linear.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"
#include "verify/time_stepping.h"

namespace fricrom {
namespace {

using time_stepping::ContactTerm;
constexpr double kBeta = 0.25, kGamma = 0.5;  // average acceleration

// The constant operators of one (model, dt, cutoff).
struct ModalOperators {
  Eigen::MatrixXd phi;     // n × k kept modes (M-orthonormal)
  Eigen::VectorXd lambda;  // k eigenvalues [rad²/s²]
  Eigen::MatrixXd psi;     // m × k  D Φ
  Eigen::MatrixXd phi_f;   // k × nL Φᵀ F
  Eigen::MatrixXd ck;      // k × k  Φᵀ C Φ
  Eigen::MatrixXd m_inv;   // k × k  (I + γ dt C_k + β dt² Λ)⁻¹
  Eigen::MatrixXd r_dt;    // n × m  R Dᵀ
  Eigen::MatrixXd r_f;     // n × nL R F
  Eigen::MatrixXd s;       // m × m
  Eigen::MatrixXd e;       // m × nL β dt² Ψ M_eff⁻¹ Φᵀ F + D R F
};

// Relative-displacement rows: 2c = u_c (tangent), 2c + 1 = v_c (normal).
Eigen::MatrixXd RelativeRows(const std::vector<ContactTerm>& terms, int n) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(2 * static_cast<Eigen::Index>(terms.size()), n);
  for (size_t c = 0; c < terms.size(); ++c) {
    const ContactTerm& t = terms[c];
    const auto ru = static_cast<Eigen::Index>(2 * c), rv = ru + 1;
    for (size_t i = 0; i < t.dof_a.size(); ++i) {
      d(ru, t.dof_a[i]) += t.t_a[i];
      d(rv, t.dof_a[i]) += t.n_a[i];
    }
    for (size_t i = 0; i < t.dof_b.size(); ++i) {
      d(ru, t.dof_b[i]) -= t.t_b[i];
      d(rv, t.dof_b[i]) -= t.n_b[i];
    }
  }
  return d;
}

// False (with a message) if the full-stick stiffness is not positive definite.
bool BuildOperators(const Model& model, const ModalResult& stick, const Eigen::MatrixXd& d,
                    const Eigen::MatrixXd& f, double dt, double cutoff_hz, ModalOperators* op,
                    std::string* message) {
  Eigen::Index k = 0;
  while (k < stick.frequencies_hz.size() && stick.frequencies_hz[k] <= cutoff_hz) ++k;
  k = std::max<Eigen::Index>(k, 1);
  op->phi = stick.shapes.leftCols(k);
  op->lambda =
      stick.frequencies_hz.head(k).unaryExpr([](double hz) { return EigenvalueFromHz(hz); });
  const Eigen::LLT<Eigen::MatrixXd> ks(model.stiffness + ContactStickStiffness(model));
  if (ks.info() != Eigen::Success) {
    *message = "full-stick stiffness is not positive definite (a body without support?)";
    return false;
  }
  const Eigen::MatrixXd inv_lambda_phi_t =
      op->lambda.cwiseInverse().asDiagonal() * op->phi.transpose();
  op->psi = d * op->phi;
  op->phi_f = op->phi.transpose() * f;
  // (No contacts: no rows, and Eigen's triangular solve must not see an empty right-hand side.)
  op->r_dt =
      d.rows() > 0
          ? Eigen::MatrixXd(ks.solve(d.transpose()) - op->phi * (inv_lambda_phi_t * d.transpose()))
          : Eigen::MatrixXd(model.num_dofs(), 0);
  op->r_f = ks.solve(f) - op->phi * (inv_lambda_phi_t * f);
  op->ck = op->phi.transpose() * model.damping * op->phi;
  Eigen::MatrixXd m_eff = kGamma * dt * op->ck;
  m_eff.diagonal().array() += 1.0 + kBeta * dt * dt * op->lambda.array();
  op->m_inv = m_eff.inverse();
  const double b = kBeta * dt * dt;
  op->s = b * op->psi * op->m_inv * op->psi.transpose() + d * op->r_dt;
  op->s = 0.5 * (op->s + op->s.transpose()).eval();  // symmetric in exact arithmetic
  op->e = b * op->psi * (op->m_inv * op->phi_f) + d * op->r_f;
  return true;
}

// One contact evaluated at trial relative displacements, from its committed state.
struct ContactTrial {
  double normal = 0.0, tangential = 0.0;
  ContactState state = ContactState::kStick;
};

// Per-step solve of d + S g̃(d) = d₀ (file comment). g̃, sg = S g̃ and trials are updated in
// place, d is returned in solution; returns the Newton steps taken, or −1 if not converged.
class ContactStepSolver {
 public:
  ContactStepSolver(const std::vector<ContactTerm>& terms, const Eigen::MatrixXd& s)
      : terms_(terms), s_(s) {}

  int Solve(const Eigen::VectorXd& d0, int max_iterations, Eigen::VectorXd* g, Eigen::VectorXd* sg,
            std::vector<ContactTrial>* trials, Eigen::VectorXd* solution) {
    Eigen::VectorXd& d = *solution;
    d = d0 - *sg;                  // predictor: last step's forces
    if (d0.size() == 0) return 0;  // no contacts: the step is linear
    const double scale = std::max(d0.lpNorm<Eigen::Infinity>(), 1e-300);
    double last_norm = INFINITY;
    for (int it = 1; it <= max_iterations; ++it) {
      Evaluate(d, g, sg, trials);
      const Eigen::VectorXd f = d + *sg - d0;
      const double norm = f.lpNorm<Eigen::Infinity>();
      if (!std::isfinite(norm)) return -1;
      if (norm <= 1e-11 * scale) return it;
      Eigen::VectorXd delta = NewtonStep(f, *trials);
      // Semismooth Newton on a piecewise-linear map can cycle between two active sets at a
      // kink: a growing residual late in the iteration halves the step.
      if (it > 8 && norm >= last_norm) delta *= 0.5;
      last_norm = norm;
      d += delta;
    }
    return -1;
  }

 private:
  // g̃(d) with sg kept equal to S g̃ by column updates of the rows that changed.
  void Evaluate(const Eigen::VectorXd& d, Eigen::VectorXd* g, Eigen::VectorXd* sg,
                std::vector<ContactTrial>* trials) const {
    for (size_t c = 0; c < terms_.size(); ++c) {
      const ContactTerm& t = terms_[c];
      const auto ru = static_cast<Eigen::Index>(2 * c), rv = ru + 1;
      const ContactStep step = AdvanceContact(t.Params(), t.t_prev, d[ru] - t.u_prev, d[rv]);
      (*trials)[c] = ContactTrial{step.normal, step.tangential, step.state};
      const double gu = step.tangential - t.kt * d[ru], gv = step.normal - t.kn * d[rv];
      if (gu != (*g)[ru]) {
        sg->noalias() += s_.col(ru) * (gu - (*g)[ru]);
        (*g)[ru] = gu;
      }
      if (gv != (*g)[rv]) {
        sg->noalias() += s_.col(rv) * (gv - (*g)[rv]);
        (*g)[rv] = gv;
      }
    }
  }

  // Δ of (I + S G) Δ = −f with G = ∂g̃/∂d, nonzero only on slipping or open rows.
  Eigen::VectorXd NewtonStep(const Eigen::VectorXd& f, const std::vector<ContactTrial>& trials) {
    rows_.clear();
    entries_.clear();
    for (size_t c = 0; c < terms_.size(); ++c) {
      const ContactTerm& t = terms_[c];
      const auto ru = static_cast<Eigen::Index>(2 * c), rv = ru + 1;
      switch (trials[c].state) {
        case ContactState::kStick:
          break;
        case ContactState::kSlipPositive:
        case ContactState::kSlipNegative: {
          const double sign = trials[c].state == ContactState::kSlipPositive ? 1.0 : -1.0;
          rows_.push_back(ru);
          entries_.push_back({ru, -t.kt, rv, sign * t.mu * t.kn});
          break;
        }
        case ContactState::kLiftOff:
          rows_.push_back(ru);
          entries_.push_back({ru, -t.kt, rv, 0.0});
          rows_.push_back(rv);
          entries_.push_back({rv, -t.kn, rv, 0.0});
          break;
      }
    }
    const auto r = static_cast<Eigen::Index>(rows_.size());
    if (r == 0) return -f;
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(r, r);
    Eigen::VectorXd b(r);
    for (Eigen::Index i = 0; i < r; ++i) {
      const Entry& en = entries_[static_cast<size_t>(i)];
      b[i] = -(en.g1 * f[en.col1] + en.g2 * f[en.col2]);
      for (Eigen::Index j = 0; j < r; ++j) {
        const Eigen::Index rj = rows_[static_cast<size_t>(j)];
        a(i, j) += en.g1 * s_(en.col1, rj) + en.g2 * s_(en.col2, rj);
      }
    }
    const Eigen::VectorXd z = a.partialPivLu().solve(b);
    Eigen::VectorXd delta = -f;
    for (Eigen::Index j = 0; j < r; ++j) delta.noalias() -= s_.col(rows_[j]) * z[j];
    return delta;
  }

  struct Entry {
    Eigen::Index col1;
    double g1;
    Eigen::Index col2;
    double g2;
  };
  const std::vector<ContactTerm>& terms_;
  const Eigen::MatrixXd& s_;
  std::vector<Eigen::Index> rows_;
  std::vector<Entry> entries_;
};

// First-harmonic amplitude of a window of samples (whole periods) under a Hann window: exact for
// a periodic signal of the excitation's period (the window's lines miss every other harmonic),
// while a component detuned by Δf leaks only ~(Δf·T_window)⁻³ of its amplitude.
class HannWindow {
 public:
  HannWindow(int length, int steps_per_period) : length_(length), per_period_(steps_per_period) {}
  void Add(double y) {
    const double x = static_cast<double>(count_) / length_;
    const double w = std::sin(std::numbers::pi * x) * std::sin(std::numbers::pi * x);
    const double theta = kTwoPi * static_cast<double>(count_ % per_period_) / per_period_;
    re_ += w * y * std::cos(theta);
    im_ += w * y * std::sin(theta);
    weight_ += w;
    ++count_;
  }
  bool Full() const { return count_ == length_; }
  // The window's amplitude; starts the next window.
  double Amplitude() {
    const double a = 2.0 * std::hypot(re_, im_) / weight_;
    count_ = 0;
    re_ = im_ = weight_ = 0.0;
    return a;
  }

 private:
  int length_, per_period_;
  int count_ = 0;
  double re_ = 0.0, im_ = 0.0, weight_ = 0.0;
};

// The time-stepping state: Newmark (average acceleration) on the modal coordinates and the
// contacts' law state, advanced one step at a time.
class ModalStepper {
 public:
  ModalStepper(const ModalOperators& op, std::vector<ContactTerm> terms,
               const time_stepping::LoadBasis& loads, double dt)
      : op_(op), terms_(std::move(terms)), loads_(loads), dt_(dt), solver_(terms_, op.s) {}

  // At rest in the static state q (contacts seated with contact_alpha).
  void Seat(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& contact_alpha,
            const Eigen::MatrixXd& d_rows) {
    time_stepping::SeatContacts(q, contact_alpha, &terms_);
    const Eigen::VectorXd d = d_rows * q;
    const auto nc = terms_.size();
    g_.resize(2 * static_cast<Eigen::Index>(nc));
    trials_.assign(nc, ContactTrial{});
    for (size_t c = 0; c < nc; ++c) {
      const ContactTerm& t = terms_[c];
      const auto ru = static_cast<Eigen::Index>(2 * c), rv = ru + 1;
      const double nk = std::max(t.n0 + t.kn * d[rv], 0.0);
      trials_[c] = {nk, t.t_prev, nk > 0.0 ? ContactState::kStick : ContactState::kLiftOff};
      g_[ru] = t.t_prev - t.kt * d[ru];
      g_[rv] = nk - t.kn * d[rv];
    }
    sg_ = g_.size() > 0 ? Eigen::VectorXd(op_.s * g_) : Eigen::VectorXd();
    d_ = d;
    w_ = loads_.Weights(0, 1, 0.0);
    eta_ = op_.phi.transpose() * model.mass * q;
    eta_d_ = Eigen::VectorXd::Zero(eta_.size());
    eta_dd_ = op_.phi_f * w_ - ContactModalForce() - op_.lambda.cwiseProduct(eta_);
  }

  // The seated state moving with velocity q̇ under load weights w (a periodic solution's t = 0).
  void Launch(const Model& model, const Eigen::VectorXd& q_dot, const Eigen::VectorXd& w) {
    w_ = w;
    eta_d_ = op_.phi.transpose() * model.mass * q_dot;
    eta_dd_ =
        op_.phi_f * w_ - ContactModalForce() - op_.ck * eta_d_ - op_.lambda.cwiseProduct(eta_);
  }

  // To load weights w at the next step; the Newton steps taken, or −1 if the contacts' solve did
  // not converge.
  int Advance(const Eigen::VectorXd& w, int max_iterations) {
    const double b = kBeta * dt_ * dt_;
    const Eigen::VectorXd eta_s = eta_ + dt_ * eta_d_ + (0.5 - kBeta) * dt_ * dt_ * eta_dd_;
    const Eigen::VectorXd eta_ds = eta_d_ + (1.0 - kGamma) * dt_ * eta_dd_;
    const Eigen::VectorXd inner = op_.ck * eta_ds + op_.lambda.cwiseProduct(eta_s);
    const Eigen::VectorXd eta_free = eta_s - b * (op_.m_inv * inner);
    int its = 0;
    if (g_.size() > 0) {  // Eigen must not see empty operands (UBSan): no contacts, no solve
      const Eigen::VectorXd d0 = op_.psi * eta_free + op_.e * w;
      its = solver_.Solve(d0, max_iterations, &g_, &sg_, &trials_, &d_);
      if (its < 0) return its;
    }
    for (size_t c = 0; c < terms_.size(); ++c) {  // commit the law's state
      terms_[c].t_prev = trials_[c].tangential;
      terms_[c].u_prev = d_[2 * static_cast<Eigen::Index>(c)];
    }
    w_ = w;
    eta_dd_ = op_.m_inv * (op_.phi_f * w - ContactModalForce() - inner);
    eta_ = eta_s + b * eta_dd_;
    eta_d_ = eta_ds + kGamma * dt_ * eta_dd_;
    return its;
  }

  // Ψᵀ g̃: the contacts' modal forces (zero without contacts).
  Eigen::VectorXd ContactModalForce() const {
    return g_.size() > 0 ? Eigen::VectorXd(op_.psi.transpose() * g_)
                         : Eigen::VectorXd::Zero(op_.phi.cols());
  }
  // Response DOF at the current state: φ_e η + (R F w)_e − (R Dᵀ g̃)_e.
  double Response(const Eigen::RowVectorXd& phi_e, const Eigen::RowVectorXd& rf_e,
                  const Eigen::RowVectorXd& rdt_e) const {
    return phi_e.dot(eta_) + rf_e.dot(w_) + (g_.size() > 0 ? -rdt_e.dot(g_) : 0.0);
  }
  const Eigen::VectorXd& eta() const { return eta_; }
  const Eigen::VectorXd& g() const { return g_; }
  const Eigen::VectorXd& w() const { return w_; }
  const std::vector<ContactTrial>& trials() const { return trials_; }

 private:
  const ModalOperators& op_;
  std::vector<ContactTerm> terms_;
  const time_stepping::LoadBasis& loads_;
  double dt_;
  ContactStepSolver solver_;
  Eigen::VectorXd eta_, eta_d_, eta_dd_, g_, sg_, d_, w_;
  std::vector<ContactTrial> trials_;
};

// One period's samples: what the result reports of the last period.
struct PeriodRecord {
  PeriodRecord(Eigen::Index modes, int contacts, Eigen::Index loads, int samples)
      : etas(modes, samples),
        gs(2 * contacts, samples),
        ws(loads, samples),
        tang(contacts, samples),
        norm(contacts, samples),
        resp(samples),
        states(static_cast<size_t>(contacts),
               std::vector<ContactState>(static_cast<size_t>(samples))) {}
  void Record(int s, const ModalStepper& st, double response) {
    etas.col(s) = st.eta();
    if (gs.rows() > 0) gs.col(s) = st.g();
    ws.col(s) = st.w();
    resp[s] = response;
    for (size_t c = 0; c < st.trials().size(); ++c) {
      const auto ci = static_cast<Eigen::Index>(c);
      tang(ci, s) = st.trials()[c].tangential;
      norm(ci, s) = st.trials()[c].normal;
      states[c][static_cast<size_t>(s)] = st.trials()[c].state;
    }
  }
  Eigen::MatrixXd etas, gs, ws, tang, norm;
  Eigen::VectorXd resp;
  std::vector<std::vector<ContactState>> states;
};

// Steady state on Hann-windowed amplitudes (TimeIntegrationOptions::window_periods), fed one
// period at a time after the ramp.
class WindowedSteadyTest {
 public:
  WindowedSteadyTest(const TimeIntegrationOptions& options)
      : options_(options),
        window_(options.window_periods * options.steps_per_period, options.steps_per_period) {}
  // True when settled; updates the result's relative change and free vibration.
  bool Add(int done, const Eigen::VectorXd& resp, double one_period, double* amplitude,
           TimeIntegrationResult* result) {
    period_min_ = std::min(period_min_, one_period);
    period_max_ = std::max(period_max_, one_period);
    for (Eigen::Index s = 0; s < resp.size(); ++s) window_.Add(resp[s]);
    if (!window_.Full()) return false;
    *amplitude = window_.Amplitude();
    result->free_vibration = (period_max_ - period_min_) / period_max_;
    period_min_ = INFINITY;
    period_max_ = 0.0;
    const double previous = previous_;
    previous_ = *amplitude;
    if (previous < 0.0) return false;
    result->relative_change = std::abs(*amplitude - previous) / std::max(*amplitude, 1e-300);
    return result->relative_change <= options_.steady_tolerance && done >= options_.min_periods;
  }

 private:
  const TimeIntegrationOptions& options_;
  HannWindow window_;
  double previous_ = -1.0, period_min_ = INFINITY, period_max_ = 0.0;
};

}  // namespace

// Declared in time_integration.cpp, which validates the inputs and computes the stick modes.
TimeIntegrationResult IntegrateImplicitModal(const Model& model,
                                             const Eigen::VectorXd& initial_alpha,
                                             const TimeIntegrationOptions& options,
                                             const ModalResult& stick, const PeriodicStart* start) {
  using Status = TimeIntegrationResult::Status;
  namespace ts = time_stepping;
  const int n = model.num_dofs();
  const int nc = static_cast<int>(model.contacts.size());
  const int ns = options.steps_per_period;
  const double period = 1.0 / options.freq_hz, dt = period / ns;
  TimeIntegrationResult result;
  result.scheme = "implicit-modal";
  result.cutoff_hz = options.modal_cutoff_factor * options.freq_hz;

  const std::vector<ContactTerm> terms = ts::BuildContacts(model);
  const ts::LoadBasis loads = ts::BuildLoadBasis(model);
  const Eigen::MatrixXd d_rows = RelativeRows(terms, n);
  ModalOperators op;
  if (!BuildOperators(model, stick, d_rows, loads.vectors, dt, result.cutoff_hz, &op,
                      &result.message)) {
    result.status = Status::kUnstable;
    return result;
  }
  result.modes_integrated = static_cast<int>(op.phi.cols());

  // Static state for the prescribed α, then the modal state at rest that reproduces it; or the
  // given periodic state, moving, under the full loads.
  Eigen::VectorXd q;
  if (start) {
    q = start->displacement;
  } else if (!ts::SolveStatic(model, terms, initial_alpha, loads.vectors.col(0), &q,
                              &result.message)) {
    result.status = Status::kStaticFailed;
    return result;
  }
  result.static_displacement = q;
  ModalStepper stepper(op, terms, loads, dt);
  stepper.Seat(model, q, initial_alpha, d_rows);
  if (start) stepper.Launch(model, start->velocity, loads.Weights(0, ns, 1.0));

  PeriodRecord rec(op.phi.cols(), nc, loads.vectors.cols(), ns);
  Eigen::VectorXd cos_table(ns), sin_table(ns);
  for (int s = 0; s < ns; ++s) {
    cos_table[s] = std::cos(kTwoPi * s / ns);
    sin_table[s] = std::sin(kTwoPi * s / ns);
  }
  const Eigen::RowVectorXd phi_e = op.phi.row(model.response_dof);
  const Eigen::RowVectorXd rf_e = op.r_f.row(model.response_dof);
  const Eigen::RowVectorXd rdt_e = op.r_dt.cols() > 0
                                       ? Eigen::RowVectorXd(op.r_dt.row(model.response_dof))
                                       : Eigen::RowVectorXd();
  const double t_ramp = options.ramp_periods * period;
  WindowedSteadyTest steady(options);
  double amplitude = NAN;
  result.status = Status::kNotSettled;
  for (int p = 0; p < options.max_periods && result.status == Status::kNotSettled; ++p) {
    for (int s = 0; s < ns; ++s) {
      // Sample s of period p is the state at t = (p N + s) dt; then the step to the next.
      rec.Record(s, stepper, stepper.Response(phi_e, rf_e, rdt_e));
      const long long step = static_cast<long long>(p) * ns + s + 1;
      const double t = static_cast<double>(step) * dt;
      const int its = stepper.Advance(loads.Weights(step, ns, ts::SmoothRamp(t, t_ramp)),
                                      options.max_contact_iterations);
      if (its < 0) {
        std::ostringstream m;
        m << "contact solve did not converge in " << options.max_contact_iterations
          << " Newton steps at t = " << t << " s (period " << p + 1 << ", step " << s + 1 << ")";
        result.status = Status::kContactFailed;
        result.message = m.str();
        return result;  // amplitude stays NaN: a failed run is never a number
      }
      result.contact_iterations += its;
      result.max_step_iterations = std::max(result.max_step_iterations, its);
    }
    const int done = p + 1;
    result.periods = done;
    result.steps = done * ns;
    if (!stepper.eta().allFinite() || !rec.resp.allFinite()) {
      result.status = Status::kUnstable;
      result.message = "solution blew up (non-finite) in period " + std::to_string(done);
      return result;
    }
    if (done <= options.ramp_periods) continue;
    const double one_period = ts::FirstHarmonicAmplitude(rec.resp, cos_table, sin_table);
    if (steady.Add(done, rec.resp, one_period, &amplitude, &result)) {
      result.status = Status::kSteadyState;
    }
  }
  Eigen::MatrixXd disp = op.phi * rec.etas + op.r_f * rec.ws;
  if (nc > 0) disp -= op.r_dt * rec.gs;
  ts::FinishResult(model, disp, rec.tang, rec.norm, rec.states, amplitude, options, &result);
  return result;
}

}  // namespace fricrom
