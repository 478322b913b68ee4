// Independent verification route for the harmonic balance: direct time integration of
//   M q̈ + C q̇ + K q + F_C(q, history) = F_exc(t)                    (paper Eq. 1)
// with the same 1D contact law as the AFT (contact.h: N = max(N0 + kn v, 0); stick predictor
// T_k = T_{k−1} + kt (u_k − u_{k−1}) kept while |T| ≤ μN, else slip T = ±μN; lift-off T = 0),
// applied incrementally: the tangential force is carried from step to step, so the steady state
// reached depends on the history, which is how the α non-uniqueness (paper §2.2) shows up here.
//
// Procedure:
//  1. Static state at t = 0: the static (h = 0) loads are fully applied and the static problem
//     K q + F_C = F0 is solved with every contact's tangential force prescribed as T = α μ N
//     (an admissible static equilibrium of a contact seated with that friction state; contacts
//     with N ≤ 0 are open). This is paper Eq. 4, T(0) = α μ N(0), taken literally.
//  2. From that state at rest, the harmonic loads (h ≥ 1 at ω = 2π freq_hz) are switched on with
//     a smooth ramp over ramp_periods periods; then integration continues until the first-harmonic
//     amplitude of the response DOF stops changing (steady_tolerance) or max_periods is reached.
// The excitation phase is that of the HBM: period p covers t ∈ [pT, (p+1)T) and the loads are
// cos/sin(hωt), so sample k of the last period is the HBM time sample θ_k = 2πk/N.
//
// Two schemes (TimeIntegrationOptions::scheme):
//  - central differences (explicit, every DOF, exact law per step): lumped models, where the
//    step set by the sampling is far inside the stability limit;
//  - implicit modal (reduced FE models, whose stiff contact springs put ω_max in the MHz: the
//    explicit step would need ~10⁴ steps per period): Newmark's average acceleration on the
//    full-stick modes below modal_cutoff_factor × the excitation frequency, the modes above taken
//    quasi-statically (residual flexibility, exact at ω = 0), and per step the contact law solved
//    exactly on the contacts' relative displacements by a semismooth Newton method
//    (modal_time_integration.cpp says how).
#pragma once

#include <Eigen/Dense>
#include <limits>
#include <string>
#include <vector>

#include "fricrom/contact_law.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

struct TimeIntegrationOptions {
  enum class Scheme {
    kAuto,               // central differences if stable at steps_per_period, else implicit modal
    kCentralDifference,  // explicit; kUnstable (nothing integrated) beyond its stability limit
    kImplicitModal,      // unconditionally stable; modes above the cutoff quasi-static
  };
  Scheme scheme = Scheme::kAuto;
  double freq_hz = 0.0;        // excitation frequency [Hz] (required)
  int steps_per_period = 256;  // time steps per excitation period (also the output sampling)
  int max_periods = 3000;      // gives up (kNotSettled) after this many periods
  int min_periods = 50;        // never declares steady state earlier
  // Periods over which the harmonic loads are ramped in; −1: automatic (central differences 20,
  // half-cosine ramp; implicit modal 300, infinitely smooth ramp: it leaves next to nothing in
  // lightly damped free modes near the excitation).
  int ramp_periods = -1;
  int block_periods = 10;  // central differences: steady state is tested every block_periods
  // Central differences: steady when |A_j − A_{j−1}| ≤ steady_tolerance · A_j, A_j the
  // first-harmonic amplitude of the response DOF over the last period of block j.
  // Implicit modal: A_j is the Hann-windowed first harmonic over window j of window_periods
  // periods. A free mode that friction does not damp (all contacts stuck, modal damping ~1e-5)
  // rings on for thousands of periods beside the forced response; the window separates the two
  // (the forced part is exact, a mode detuned by Δf leaks ~(Δf·window)⁻³), so "steady" means the
  // forced periodic response has settled. 0: automatic (1e-6 central, 1e-4 implicit modal).
  double steady_tolerance = 0.0;
  int window_periods = 200;
  // dt must satisfy ω_max dt ≤ stability_fraction · 2 (central-difference limit), ω_max from the
  // full-stick system (the stiffest state the contacts can take).
  double stability_fraction = 0.9;
  // Implicit modal scheme: full-stick modes up to modal_cutoff_factor × freq_hz are integrated
  // (the contact law's higher harmonics reach them; above, the response is quasi-static), at
  // least one. A per-step contact solve that has not converged after max_contact_iterations
  // Newton steps stops the run (kContactFailed).
  double modal_cutoff_factor = 20.0;
  int max_contact_iterations = 50;
  bool IsValid(std::string* error) const;
};

struct TimeIntegrationResult {
  enum class Status {
    kSteadyState,    // settled within steady_tolerance
    kNotSettled,     // max_periods reached (still drifting, or not periodic)
    kUnstable,       // dt beyond the stability limit, or the solution blew up
    kStaticFailed,   // no static equilibrium found for the prescribed α (singular / cycling)
    kContactFailed,  // implicit scheme: a step's contact solve did not converge
  };
  Status status = Status::kNotSettled;
  std::string message;
  // First harmonic of the response DOF over the last period [m]; NaN when no period was
  // integrated (unstable step, failed static state): a failed run is never a number.
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  int periods = 0;  // periods integrated (ramp included)
  int steps = 0;
  double relative_change = 0.0;  // last block-to-block amplitude change / amplitude
  // Implicit modal: spread (max − min)/max of the one-period amplitudes over the last window: the
  // free vibration riding on the forced response (0 when the motion is periodic).
  double free_vibration = 0.0;
  double stability_ratio = 0.0;          // ω_max dt / 2 (< 1 for a stable scheme)
  std::string scheme;                    // "central-difference" or "implicit-modal"
  int modes_integrated = 0;              // implicit modal: modes below the cutoff
  double cutoff_hz = 0.0;                // implicit modal: the cutoff [Hz]
  long long contact_iterations = 0;      // implicit modal: Newton steps over all time steps
  int max_step_iterations = 0;           // implicit modal: the most Newton steps of one step
  Eigen::VectorXd static_displacement;   // q at t = 0 [m]
  Eigen::VectorXd last_period_response;  // response DOF at the N samples of the last period [m]
  Eigen::MatrixXd last_period_displacements;  // all DOFs (rows) × N samples [m]
  Eigen::MatrixXd last_period_tangential;     // contacts (rows) × N samples, T [N]
  Eigen::MatrixXd last_period_normal;         // contacts (rows) × N samples, N [N]
  std::vector<ContactRegime> regimes;         // per contact, over the last period
  // T/(μN) at the first sample of the last period (0 where the contact is open): the α with which
  // the HBM's AFT (which starts at that same instant) reproduces this periodic contact state.
  Eigen::VectorXd equivalent_alpha;
  bool IsSteady() const { return status == Status::kSteadyState; }
};
std::string ToString(TimeIntegrationResult::Status status);

// Integrates the model to a periodic steady state from the static state set by initial_alpha (one
// value in [−1, 1] per α: per contact, or per group of Model::alpha_group). Throws
// std::invalid_argument on invalid options, an invalid model (Model::Validate), a non positive
// definite mass matrix or a bad initial_alpha; numerical outcomes are reported in the result's
// status. No output is printed.
TimeIntegrationResult IntegrateToSteadyState(const Model& model,
                                             const Eigen::VectorXd& initial_alpha,
                                             const TimeIntegrationOptions& options);

// The state at t = 0 of a periodic solution, to integrate from (IntegrateFromPeriodicState).
struct PeriodicStart {
  Eigen::VectorXd displacement;   // q(0) [m]
  Eigen::VectorXd velocity;       // q̇(0) [m/s]
  Eigen::VectorXd contact_alpha;  // T/(μN) per contact at t = 0 (0 where open)
};

// The state at t = 0 of the harmonic-balance solution x of `system` (a balance of `model`) at
// (ω, α): q and q̇ from its DOF coefficients, each contact's T/(μN) from its AFT history (the
// law's state at θ = 0, which the time integrator continues from). Throws std::invalid_argument
// where the balance's contacts are not the model's.
PeriodicStart PeriodicStartOf(const Model& model, const HarmonicBalance& system,
                              const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha);

// Integrates from a periodic state with the harmonic loads fully on (no ramp; options'
// ramp_periods ignored) by the implicit modal scheme, to see whether the state holds: a solution
// that is a stable periodic response stays (steady after two windows, its amplitude the
// state's), an unstable one leaves it. Throws as IntegrateToSteadyState, and on a start whose
// sizes do not fit the model or whose contact_alpha lies outside [−1, 1].
TimeIntegrationResult IntegrateFromPeriodicState(const Model& model, const PeriodicStart& start,
                                                 const TimeIntegrationOptions& options);

// Real Fourier coefficients of the last period in the HBM layout of hbm.h (harmonic-major,
// [q̂0 | a1 | b1 | ... | aH | bH]), e.g. to start or compare an HBM solution. Throws
// std::invalid_argument if the result holds no period or H is negative or ≥ N/2.
Eigen::VectorXd LastPeriodCoefficients(const TimeIntegrationResult& result, int harmonics);

}  // namespace fricrom
