// Shared pieces of the time integrators (time_stepping.h).
#include "verify/time_stepping.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "fricrom/units.h"

namespace fricrom::time_stepping {
namespace {
constexpr Eigen::Index kFullPivotLimit = 200;
}  // namespace

void ContactTerm::Relative(const Eigen::VectorXd& q, double* u, double* v) const {
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

void ContactTerm::Scatter(double normal, double tangential, Eigen::VectorXd* fc) const {
  for (size_t i = 0; i < dof_a.size(); ++i) {
    (*fc)[dof_a[i]] += normal * n_a[i] + tangential * t_a[i];
  }
  for (size_t i = 0; i < dof_b.size(); ++i) {
    (*fc)[dof_b[i]] -= normal * n_b[i] + tangential * t_b[i];
  }
}

ContactState ContactTerm::Advance(double u, double v, double* normal, double* tangential) {
  const ContactStep at = AdvanceContact(Params(), t_prev, u - u_prev, v);
  t_prev = at.tangential;
  u_prev = u;
  *normal = at.normal;
  *tangential = at.tangential;
  return at.state;
}

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
    // Full pivoting on small (lumped) systems; FE-sized ones take the blocked partial-pivot LU
    // (FullPivLU is unblocked: seconds per active set at ~10³ DOFs) with a condition check.
    bool singular = false;
    if (a.rows() <= kFullPivotLimit) {
      Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
      singular = !lu.isInvertible();
      if (!singular) *q = lu.solve(rhs);
    } else {
      Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
      singular = !(lu.rcond() > 1e-14);
      if (!singular) *q = lu.solve(rhs);
    }
    if (singular) {
      *message = "static problem is singular (unconstrained DOFs with the current contact set)";
      return false;
    }
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

double SmoothRamp(double t, double t_ramp) {
  if (t_ramp <= 0.0 || t >= t_ramp) return 1.0;
  if (t <= 0.0) return 0.0;
  const double s = t / t_ramp;
  const double a = std::exp(-1.0 / s), b = std::exp(-1.0 / (1.0 - s));
  return a / (a + b);
}

void SeatContacts(const Eigen::VectorXd& q, const Eigen::VectorXd& contact_alpha,
                  std::vector<ContactTerm>* terms) {
  for (size_t c = 0; c < terms->size(); ++c) {
    ContactTerm& ct = (*terms)[c];
    double u, v;
    ct.Relative(q, &u, &v);
    const double nk = std::max(ct.n0 + ct.kn * v, 0.0);
    ct.u_prev = u;
    ct.t_prev = nk > 0.0 ? contact_alpha[static_cast<Eigen::Index>(c)] * ct.mu * nk : 0.0;
  }
}

LoadBasis BuildLoadBasis(const Model& model) {
  LoadBasis b;
  int harmonic_loads = 0;
  for (const HarmonicLoad& l : model.loads) harmonic_loads += l.harmonic != 0;
  b.vectors = Eigen::MatrixXd::Zero(model.num_dofs(), 1 + 2 * harmonic_loads);
  int col = 1;
  for (const HarmonicLoad& l : model.loads) {
    if (l.harmonic == 0) {
      b.vectors.col(0) += l.cos;
      continue;
    }
    b.vectors.col(col++) = l.cos;
    b.vectors.col(col++) = l.sin;
    b.harmonics.push_back(l.harmonic);
  }
  return b;
}

Eigen::VectorXd LoadBasis::Weights(long long step, int steps_per_period, double ramp) const {
  Eigen::VectorXd w(vectors.cols());
  w[0] = 1.0;
  for (size_t i = 0; i < harmonics.size(); ++i) {
    // Reduce h·k mod N first: exact phases over arbitrarily many periods.
    const double theta =
        kTwoPi * static_cast<double>((harmonics[i] * step) % steps_per_period) / steps_per_period;
    w[static_cast<Eigen::Index>(1 + 2 * i)] = ramp * std::cos(theta);
    w[static_cast<Eigen::Index>(2 + 2 * i)] = ramp * std::sin(theta);
  }
  return w;
}

bool SteadyTest::Settled(int done, double amplitude, TimeIntegrationResult* result) {
  if (done % options_.block_periods != 0 || done <= options_.ramp_periods) return false;
  if (prev_block_amplitude_ >= 0.0) {
    const double diff = std::abs(amplitude - prev_block_amplitude_);
    result->relative_change = diff == 0.0 ? 0.0 : diff / std::max(amplitude, 1e-300);
    if (result->relative_change <= options_.steady_tolerance && done >= options_.min_periods) {
      result->status = TimeIntegrationResult::Status::kSteadyState;
      return true;
    }
  }
  prev_block_amplitude_ = amplitude;
  return false;
}

void FinishResult(const Model& model, const Eigen::MatrixXd& disp, const Eigen::MatrixXd& tang,
                  const Eigen::MatrixXd& norm, const std::vector<std::vector<ContactState>>& states,
                  double amplitude, const TimeIntegrationOptions& options,
                  TimeIntegrationResult* result) {
  using Status = TimeIntegrationResult::Status;
  const auto nc = static_cast<int>(model.contacts.size());
  result->amplitude = amplitude;
  result->last_period_displacements = disp;
  result->last_period_response = disp.row(model.response_dof).transpose();
  result->last_period_tangential = tang;
  result->last_period_normal = norm;
  result->regimes.clear();
  result->equivalent_alpha = Eigen::VectorXd::Zero(nc);
  for (int c = 0; c < nc; ++c) {
    result->regimes.push_back(ClassifyRegime(states[static_cast<size_t>(c)]));
    const double limit = model.contacts[static_cast<size_t>(c)].mu * norm(c, 0);
    if (limit > 0.0) result->equivalent_alpha[c] = std::clamp(tang(c, 0) / limit, -1.0, 1.0);
  }
  if (result->status == Status::kSteadyState || result->status == Status::kNotSettled) {
    std::ostringstream s;
    s << (result->status == Status::kSteadyState ? "steady state" : "not settled") << " after "
      << result->periods << " periods (relative amplitude change " << result->relative_change
      << ", tolerance " << options.steady_tolerance << "; " << result->scheme << ")";
    result->message = s.str();
  }
}

}  // namespace fricrom::time_stepping
