#include "fricrom/contact_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fricrom {

std::string ToString(ContactRegime regime) {
  switch (regime) {
    case ContactRegime::kFullStick:
      return "full-stick";
    case ContactRegime::kStickSlip:
      return "stick-slip";
    case ContactRegime::kFullSlip:
      return "full-slip";
    case ContactRegime::kStickSlipLiftOff:
      return "stick-slip-liftoff";
    case ContactRegime::kFullLiftOff:
      return "lift-off";
  }
  return "unknown";
}

ContactRegime ClassifyRegime(const std::vector<ContactState>& states) {
  int stick = 0, slip = 0, lift = 0;
  for (ContactState s : states) {
    if (s == ContactState::kStick)
      ++stick;
    else if (s == ContactState::kLiftOff)
      ++lift;
    else
      ++slip;
  }
  const int n = static_cast<int>(states.size());
  if (lift == n) return ContactRegime::kFullLiftOff;
  if (lift > 0) return ContactRegime::kStickSlipLiftOff;
  if (stick == n) return ContactRegime::kFullStick;
  if (slip == n) return ContactRegime::kFullSlip;
  return ContactRegime::kStickSlip;
}

namespace {

// AdvanceContact once N = max(N0 + kn v, 0) is known (the AFT computes every sample's at once).
inline ContactStep AdvanceWithNormal(const ContactLawParams& p, double tangential_prev,
                                     double tangential_increment, double normal) {
  ContactStep out;
  out.normal = normal;
  if (out.normal <= 0.0) {
    out.state = ContactState::kLiftOff;
    return out;
  }
  const double predictor = tangential_prev + p.kt * tangential_increment;
  const double limit = p.mu * out.normal;
  if (std::abs(predictor) <= limit * (1.0 + 1e-12)) {
    out.tangential = predictor;
    return out;
  }
  out.tangential = predictor > 0.0 ? limit : -limit;
  out.state = predictor > 0.0 ? ContactState::kSlipPositive : ContactState::kSlipNegative;
  return out;
}

}  // namespace

ContactStep AdvanceContact(const ContactLawParams& p, double tangential_prev,
                           double tangential_increment, double normal_gap) {
  return AdvanceWithNormal(p, tangential_prev, tangential_increment,
                           std::max(p.normal_preload + p.kn * normal_gap, 0.0));
}

namespace {

void CheckLawInputs(const Eigen::VectorXd& u, const Eigen::VectorXd& v, double alpha) {
  if (u.size() < 2 || v.size() != u.size()) {
    throw std::invalid_argument("EvaluateContactLaw: u and v need the same length >= 2 (got " +
                                std::to_string(u.size()) + " and " + std::to_string(v.size()) +
                                ")");
  }
  if (!(std::abs(alpha) <= 1.0)) {
    throw std::invalid_argument("EvaluateContactLaw: alpha must lie in [-1, 1], got " +
                                std::to_string(alpha));
  }
}

}  // namespace

bool EvaluateStuckContactLaw(const ContactLawParams& p, const Eigen::VectorXd& u,
                             const Eigen::VectorXd& v, double alpha, bool with_derivatives,
                             ContactLawResult* result) {
  CheckLawInputs(u, v, alpha);
  const int n = static_cast<int>(u.size());
  const double n0 = p.normal_preload + p.kn * v[0];
  if (!(n0 > 0.0)) return false;
  const double t0 = alpha * p.mu * n0;
  // The sequential law sums up to 2n increments kt (u_k − u_{k−1}) from T(0): its T_k differs
  // from t0 + kt (u_k − u_0) by at most ~2n·eps times the largest force along the path. A sample
  // whose T_k lies within AdvanceContact's limit μN (1 + 1e-12) by more than that sticks in
  // both (α = ±1 included: T_0 = ±μN(0)); samples closer to the limit go to the full law.
  // The samples are written before they are tested (the caller overwrites them if not).
  ContactLawResult& r = *result;
  // Whole-array passes (vectorised) rather than one loop with an exit per sample: ~70 % of the
  // FE cascade's laws stick, so the exits rarely save work, and the branches kept the loop
  // scalar. Each sample's arithmetic is the one the sequential law does (no contraction).
  r.normal = p.normal_preload + p.kn * v.array();
  r.tangential = t0 + p.kt * (u.array() - u[0]);
  const auto limit = p.mu * r.normal.array();
  const auto slack = limit * (1.0 + 1e-12) - r.tangential.array().abs();
  const double scale =
      std::max({std::abs(t0), limit.maxCoeff(), (p.kt * (u.array() - u[0])).abs().maxCoeff()});
  // The vectorised reductions may drop a NaN: a non-finite sum of the slacks (any NaN, or an
  // infinite force) sends the law to the sequential route, which is right for any input.
  if (!(r.normal.minCoeff() > 0.0 && std::isfinite(slack.sum()) &&
        slack.minCoeff() >= 16.0 * n * std::numeric_limits<double>::epsilon() * scale)) {
    return false;
  }
  r.states.assign(n, ContactState::kStick);
  if (with_derivatives) {
    // As EvaluateContactLaw's stick samples anchored at the initial instant (sample 0).
    TangentialDerivative d;
    d.u_minus = 0;
    d.v_index = 0;
    d.dv = alpha * p.mu * p.kn;
    d.dalpha = p.mu * n0;
    r.dT.assign(n, d);
    for (int k = 0; k < n; ++k) r.dT[k].u_plus = k;
    r.dN_dv.setConstant(n, p.kn);
  }
  return true;
}

void EvaluateContactLaw(const ContactLawParams& p, const Eigen::VectorXd& u,
                        const Eigen::VectorXd& v, double alpha, bool with_derivatives,
                        ContactLawResult* result) {
  CheckLawInputs(u, v, alpha);
  const int n = static_cast<int>(u.size());
  ContactLawResult& r = *result;
  r.tangential.resize(n);
  r.normal.resize(n);
  r.states.resize(n);
  if (with_derivatives) {
    r.dT.resize(n);  // every sample is written below
    r.dN_dv.resize(n);
  }
  // Every sample's normal load in one (vectorised) pass, as AdvanceContact computes it.
  for (int k = 0; k < n; ++k) r.normal[k] = std::max(p.normal_preload + p.kn * v[k], 0.0);

  // The tangential force in stick is T_k = T_a + kt (u_k − u_a), where a is the last "anchor":
  // the initial instant, the last slip sample or the last lift-off sample. Tracking the anchor
  // (instead of dense sensitivity rows) makes the exact derivatives O(1) per sample.
  enum class Anchor { kInitial, kSlip, kLiftOff };
  Anchor anchor_kind = Anchor::kInitial;
  int anchor = 0;          // sample index (mod n) of the anchor
  double anchor_dv = 0.0;  // dT_a/dv_a
  double anchor_dalpha = 0.0;

  const double n0 = r.normal[0];
  double t_prev = alpha * p.mu * n0;
  if (n0 > 0.0) {
    anchor_dv = alpha * p.mu * p.kn;
    anchor_dalpha = p.mu * n0;
  } else {
    anchor_kind = Anchor::kLiftOff;
  }

  // Samples 1..2n−1: the first period settles the initial condition, the second is returned.
  // (Indices wrap by comparison: a `%` per sample, an integer division, cost 8 % of an FE bound.)
  // A slip or lift-off at step s < n erases the initial condition: what follows depends on the
  // motion only. Samples are therefore recorded from step s on, and when a second-period step
  // at sample k ≥ s slips or lifts off exactly as the first period did at k (same state, same
  // T bit for bit: the law's whole state, anchors included), the rest of the second period
  // would repeat samples k..n−1 as recorded, and the loop stops: the two-period result to the
  // bit in fewer steps. Samples not matched are overwritten by the second period as before.
  int first_event = n;  // step of the first slip or lift-off in the first period
  for (int step = 1, k = 1, km1 = 0; step < 2 * n; ++step, km1 = k, k = k + 1 == n ? 0 : k + 1) {
    const ContactStep at = AdvanceWithNormal(p, t_prev, u[k] - u[km1], r.normal[k]);
    const double nk = at.normal, tk = at.tangential;
    const ContactState state = at.state;
    if (state != ContactState::kStick) {
      if (step < n) {
        first_event = std::min(first_event, step);
      } else if (k >= first_event && state == r.states[k] && tk == r.tangential[k]) {
        break;
      }
    }
    if (state == ContactState::kLiftOff) {
      anchor_kind = Anchor::kLiftOff;
      anchor = k;
      anchor_dv = 0.0;
      anchor_dalpha = 0.0;
    } else if (state != ContactState::kStick) {
      anchor_kind = Anchor::kSlip;
      anchor = k;
      anchor_dv = (state == ContactState::kSlipPositive ? 1.0 : -1.0) * p.mu * p.kn;
      anchor_dalpha = 0.0;
    }
    if (step >= first_event) {
      r.tangential[k] = tk;
      r.states[k] = state;
      if (with_derivatives) {
        TangentialDerivative& d = r.dT[k];
        d = TangentialDerivative{};  // a sample may be written twice (see above)
        r.dN_dv[k] = nk > 0.0 ? p.kn : 0.0;
        if (state == ContactState::kStick) {
          d.u_plus = k;
          d.u_minus = anchor;
          if (anchor_kind != Anchor::kLiftOff) {
            d.v_index = anchor;
            d.dv = anchor_dv;
          }
          d.dalpha = anchor_kind == Anchor::kInitial ? anchor_dalpha : 0.0;
        } else if (state != ContactState::kLiftOff) {
          d.v_index = k;
          d.dv = anchor_dv;
        }
      }
    }
    t_prev = tk;
  }
}

}  // namespace fricrom
