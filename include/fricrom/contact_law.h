// 1D friction contact law with varying normal load (paper Eq. 3-4), evaluated on one period of
// time samples, with exact derivatives carried through the two-period predictor-corrector.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace fricrom {

enum class ContactState : unsigned char { kStick, kSlipPositive, kSlipNegative, kLiftOff };

// Classification of one contact over a whole period.
enum class ContactRegime {
  kFullStick,         // every sample sticks: T⁰ not unique, set by α
  kStickSlip,         // stick and slip, always in contact
  kFullSlip,          // slips at every sample
  kStickSlipLiftOff,  // some separation and some contact
  kFullLiftOff,       // separated over the whole period
};
std::string ToString(ContactRegime regime);
ContactRegime ClassifyRegime(const std::vector<ContactState>& states);

struct ContactLawParams {
  double kn = 0.0;
  double kt = 0.0;
  double mu = 0.0;
  double normal_preload = 0.0;  // N0: N = max(N0 + kn v, 0)
};

// One sample of the law: N = max(N0 + kn v, 0); in contact the elastic predictor
// T_prev + kt Δu sticks while |T| ≤ μN (a relative 1e-12 keeps round-off from deciding when the
// force just touches the limit) and slips at ±μN otherwise. The AFT (EvaluateContactLaw) and the
// time integrator both advance contacts through this one function, so they cannot drift apart.
struct ContactStep {
  double normal = 0.0;      // N [N]
  double tangential = 0.0;  // T [N]
  ContactState state = ContactState::kStick;
};
ContactStep AdvanceContact(const ContactLawParams& params, double tangential_prev,
                           double tangential_increment, double normal_gap);

// Sparse exact derivatives of one sample of T: T_k depends on u at two samples (k and its stick
// anchor), on v at one sample (the anchor's or k's own) and on α.
struct TangentialDerivative {
  int u_plus = -1;   // index with dT/du = +kt (stick), −1 if none
  int u_minus = -1;  // index with dT/du = −kt (stick anchor)
  int v_index = -1;  // index of the v sample T depends on
  double dv = 0.0;   // dT/dv at v_index
  double dalpha = 0.0;
};

struct ContactLawResult {
  Eigen::VectorXd tangential;  // T(t_k) over the second period [N]
  Eigen::VectorXd normal;      // N(t_k) [N]
  std::vector<ContactState> states;
  std::vector<TangentialDerivative> dT;  // filled when derivatives are requested
  Eigen::VectorXd dN_dv;                 // dN_k/dv_k (diagonal)
};

// Evaluates the law for relative displacements u, v sampled at N equidistant instants of one
// period. The first period starts from T(0) = α μ N(0); the second is returned (periodic when the
// contact sticks at least once or lifts off). Throws std::invalid_argument on size mismatch or
// |α| > 1.
void EvaluateContactLaw(const ContactLawParams& params, const Eigen::VectorXd& u,
                        const Eigen::VectorXd& v, double alpha, bool with_derivatives,
                        ContactLawResult* result);

// The same law where the contact sticks from the initial instant over the whole period: then
// T_k = α μ N(0) + kt (u_k − u_0) with no history to follow. Returns true and fills `result` as
// EvaluateContactLaw does (T to round-off, states, derivatives) when N > 0 at every sample and
// every T_k lies inside the friction limit by a margin that the sequential law's accumulated
// round-off cannot cross (so both classify every sample alike); false otherwise, with `result`
// partly written — the caller then evaluates the full law into it. Throws as EvaluateContactLaw.
bool EvaluateStuckContactLaw(const ContactLawParams& params, const Eigen::VectorXd& u,
                             const Eigen::VectorXd& v, double alpha, bool with_derivatives,
                             ContactLawResult* result);

}  // namespace fricrom
