// Hill stability of a harmonic-balance solution: the Floquet exponents of the periodic motion
// from the quadratic eigenvalue problem of the linearised balance. A perturbation p(t) e^{λt} with
// p periodic (the same harmonics) of a solution of M q̈ + C q̇ + K q + f(q) = F(t) satisfies
//   (J + λ Δ1 + λ² Δ2) p̂ = 0,   Δ1 = 2 (∇ ⊗ M) + I ⊗ C,   Δ2 = I ⊗ M,
// with J the balance's Jacobian ∂R/∂x and ∇ the derivative operator on the coefficients (block
// h: (a, b) → (hω b, −hω a)). Its 2n(2H+1) eigenvalues are the 2n Floquet exponents, each repeated
// shifted by i h ω; the 2n whose eigenvectors' weight over e^{ikωt}, k = −H..H, is centred on
// k = 0 are kept (Lazarus & Thomas' symmetry criterion; ties by the smallest |Im λ|, the
// imaginary-part criterion, which alone fails where H is too small for a copy within ±ω/2). The
// solution is stable when every kept exponent has a negative real part. For contact laws that are
// not smooth (stick/slip switches, lift-off) the AFT Jacobian linearises along the sampled path:
// the method is then an approximation (docs/theory.md); time integration from the solution is the
// independent check (verify).
#pragma once

#include <Eigen/Dense>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/hbm_system.h"

namespace fricrom {

class CondensedSystem;

struct HillOptions {
  // A kept exponent with Re λ above this fraction of ω counts as growing: the solution is unstable.
  // (Round-off of the eigen-solve puts neutral exponents at |Re λ| ~ 1e-10 ω.)
  double growth_tolerance = 1e-7;
  // Condensed balance: full-stick modes below this multiple of the excitation frequency are
  // dynamic, the contact rows' residual flexibility above them quasi-static — the model of the
  // implicit modal time integration (TimeIntegrationOptions::modal_cutoff_factor), which checks it.
  double modal_cutoff_factor = 20.0;
  bool IsValid(std::string* error) const;
};

struct HillResult {
  Eigen::VectorXcd exponents;  // the 2n kept Floquet exponents [1/s], by decreasing real part
  double max_real = 0.0;       // the largest Re λ [1/s]
  bool stable = false;
  // Contacts that switch between stick and slip within the period: the AFT linearises a
  // non-smooth law along its samples there, and the verdict is an approximation that time
  // integration from the solution decides (Hill may report growing exponents at solutions a
  // time integration stays on; docs/stability.md).
  int switching_contacts = 0;
  bool approximate() const { return switching_contacts > 0; }
  std::string message;  // why, in a line
  std::string BriefReport() const;
};

// The Floquet exponents at a solution with Jacobian `jacobian` of a balance whose unknowns are the
// hbm_system.h layout [q̂0 | a1 | b1 | … | aH | bH] over n DOFs, with mass M (positive definite) and
// damping C. Throws std::invalid_argument on inconsistent sizes or a mass that is not definite.
HillResult HillStability(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& mass,
                         const Eigen::MatrixXd& damping, int harmonics, double omega,
                         const HillOptions& options = {});

// The same at a solution x of `system` (full balance: every DOF) at (ω, α), with the static
// tangential stiffness kt of the contacts stuck over the whole period added to the Jacobian's
// static block: the balance prescribes their static tangential force by α (so ∂R/∂q̂0 lacks it),
// while a perturbation of a stuck contact is held by kt.
HillResult HillStability(const HbmSystem& system, const Eigen::VectorXd& x, double omega,
                         const Eigen::VectorXd& alpha, const HillOptions& options = {});

// The same at a solution x of the condensed balance `system`: the linear part reduced to the
// full-stick modes below options.modal_cutoff_factor × f (dynamic) and the contact rows' residual
// flexibility (quasi-static, eliminated), ∂F̃/∂r from the AFT with the same kt restored for
// contacts stuck over the whole period; the 2m exponents of the m modes are returned. Exact where
// every mode is kept (then no residual is left). Throws std::domain_error where a residual
// direction has no stiffness (a body held only by sliding friction), which needs its mass.
HillResult HillStability(const CondensedSystem& system, const Eigen::VectorXd& x, double omega,
                         const Eigen::VectorXd& alpha, const HillOptions& options = {});

// The condensed Hill analysis of one balance for many solutions (an FRF's points, both bounds):
// the full-stick modes and K_s⁻¹ Bᵀ are computed once, at construction (throws
// std::domain_error if the full-stick stiffness is not positive definite).
class CondensedHill {
 public:
  explicit CondensedHill(const CondensedSystem& system);
  ~CondensedHill();
  CondensedHill(const CondensedHill&) = delete;
  CondensedHill& operator=(const CondensedHill&) = delete;
  HillResult At(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HillOptions& options = {}) const;

 private:
  struct Modal;
  const CondensedSystem& system_;
  std::unique_ptr<Modal> modal_;
};

// Counts the contacts of `regimes` that switch between stick and slip into r (and its message).
void NoteSwitchingContacts(const std::vector<ContactRegime>& regimes, HillResult* r);

// Hill stability of solutions of one balance of any kind (the condensed one's modal data kept
// between calls).
class SolutionStability {
 public:
  explicit SolutionStability(const HarmonicBalance& system) : system_(system) {}
  // As HillStabilityOf.
  HillResult At(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HillOptions& options = {});

 private:
  const HarmonicBalance& system_;
  std::unique_ptr<CondensedHill> condensed_;
};

// Hill stability of a solution of any balance: the full one (dense, up to a companion size of
// 3000 unknowns) or the condensed one (modal form). Throws std::domain_error, saying why, where it
// cannot be computed (another balance, a problem too large, a residual direction without
// stiffness).
HillResult HillStabilityOf(const HarmonicBalance& system, const Eigen::VectorXd& x, double omega,
                           const Eigen::VectorXd& alpha, const HillOptions& options = {});

// The independent check: time integration from the solution's own state at t = 0 (implicit
// modal scheme, loads fully on; time_integration.h) for a few windows. The solution holds when
// the run settles at its amplitude within `margin` (the harmonic truncation separates the
// time-domain amplitude from the HBM's by up to ~1e-2 next to a resonance) after its windows,
// settled or still shedding the free vibration its start excites; a run that ends farther away
// has left it.
struct HoldResult {
  bool holds = false;    // the motion stayed within the margin of the solution
  bool settled = false;  // ... and reached a steady state (a stable solution may still ring)
  std::string status;    // the run's TimeIntegrationResult status
  double amplitude = std::numeric_limits<double>::quiet_NaN();           // the run's [m]
  double solution_amplitude = std::numeric_limits<double>::quiet_NaN();  // the HBM's [m]
  int periods = 0;
  double wall_s = 0.0;
  std::string message;
};
struct HoldOptions {
  int window_periods = 50;  // the steady-state window (TimeIntegrationOptions::window_periods)
  int windows = 3;          // the run stops after this many windows at most
  double margin = 0.02;     // relative amplitude margin of "holds"
  double modal_cutoff_factor = 20.0;
  bool IsValid(std::string* error) const;
};
HoldResult HoldsUnderTimeIntegration(const Model& model, const HarmonicBalance& system,
                                     const Eigen::VectorXd& x, double omega,
                                     const Eigen::VectorXd& alpha, const HoldOptions& options = {});

// Hill stability of both bounds of `b` at ω (their x are solutions of `system`): the full balance
// (dense, up to a companion size of 3000) and the condensed one (modal form); where it cannot be
// computed each bound's stability says why.
void AssessBoundStability(const HarmonicBalance& system, double omega, BoundsResult* b,
                          const HillOptions& options = {});
// The same with the modal data of `stability` kept between calls (a bound curve's points).
void AssessBoundStability(SolutionStability* stability, double omega, BoundsResult* b,
                          const HillOptions& options = {});

// The bounds over the stable solutions among `b`'s own solutions and fixed-α solves at `samples`
// points of the α box (its two uniform corners, then uniform random α, a fixed stream), each
// started from b's solutions by Newton and judged by Hill (StableBounds says what it is and is
// not). A candidate counts as stable only where Hill computed it and found it stable, also where
// the verdict is approximate (counted). Throws std::invalid_argument for samples < 0.
StableBounds BoundsOverStableSolutions(SolutionStability* stability, const HarmonicBalance& system,
                                       const BoundsResult& b, int samples,
                                       const HillOptions& options = {});

}  // namespace fricrom
