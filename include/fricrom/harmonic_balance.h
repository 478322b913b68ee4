// What the nonlinear solvers (Newton, continuation, bounds, sweeps, NOA, certification) see of a
// harmonic-balance problem R(x; ω, α) = 0: unknowns x, one α per contact direction, the residual
// with its exact derivatives, and the few response quantities they rank and report. The full
// lumped/FE system (HbmSystem) and the system condensed onto the contact DOFs (CondensedSystem)
// both implement it, so one code path serves both (Spectra's operator idea).
// Units: SI; ω in rad/s.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "fricrom/contact.h"

namespace fricrom {

// How the condensed balance forms the receptance Z_h(ω)⁻¹ of the linear part.
enum class ReceptanceMethod {
  kDense,  // LU of the real block form per harmonic and ω: exact for any damping, O(n³) per ω
  kModal,  // one generalised eigen-decomposition of (K + K_stick, M), then O(n_r² n) per ω; the
           // damping enters through the diagonal of Φᵀ C Φ (exact for proportional damping)
};

struct HbmOptions {
  int harmonics = 1;             // H >= 1: harmonics 0..H are balanced
  int samples_per_period = 128;  // AFT time samples N (must exceed 2H)
  ReceptanceMethod receptance = ReceptanceMethod::kDense;  // condensed balance only
  bool IsValid(std::string* error) const;
};

// What an evaluation computes; the residual is always computed.
struct HbmRequest {
  bool jacobian = false;        // ∂R/∂x
  bool alpha_jacobian = false;  // ∂R/∂α (one column per contact)
  bool omega_derivative = false;
};

struct HbmEvaluation {
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd alpha_jacobian;
  Eigen::VectorXd omega_derivative;
};

// Time histories of one contact over a period at a solution.
struct ContactHistory {
  Eigen::VectorXd time_s;
  Eigen::VectorXd u, v;        // relative tangential / normal displacement [m]
  Eigen::VectorXd tangential;  // T [N]
  Eigen::VectorXd normal;      // N [N]
  std::vector<ContactState> states;
  ContactRegime regime = ContactRegime::kFullStick;
};

// Energies per cycle [J] of a periodic state; at a solution, excitation = viscous + friction.
struct CycleEnergy {
  double excitation_work = 0.0;
  double viscous_dissipation = 0.0;
  std::vector<double> contact_dissipation;  // per contact, from the contact's own forces
  // Peak potential energy of the harmonics h ≥ 1 (paper Eq. 8, made exact):
  // ½ Σ_h (a_hᵀK a_h + b_hᵀK b_h) + ½ Σ_contacts Σ_h (T̂a·ûa + T̂b·ûb + N̂a·v̂a + N̂b·v̂b).
  double potential_energy = 0.0;
  double friction_dissipation() const;
  // η = (viscous + friction dissipation) / (2π U_pot) (paper Eq. 6); cω/k for a linear oscillator.
  double loss_factor() const;
};

class HarmonicBalance {
 public:
  virtual ~HarmonicBalance() = default;

  virtual int num_unknowns() const = 0;
  virtual int num_contacts() const = 0;  // contacts (directions) of the model
  // Initial-tangential-force coefficients α the solvers vary: one per contact unless contacts
  // share α (AlphaGroupedBalance). Every α argument below has this size.
  virtual int num_alpha() const { return num_contacts(); }
  virtual int harmonics() const = 0;

  // Throws std::invalid_argument on wrong sizes or |α_c| > 1.
  virtual void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                        const HbmRequest& request, HbmEvaluation* out) const = 0;
  // Norm of the load vector, the scale residual tolerances are relative to.
  virtual double ResidualScale() const = 0;
  // Solution of the full-stick linear system (contacts as kn/kt springs): a Newton start.
  virtual Eigen::VectorXd StickLinearSolution(double omega) const = 0;

  // First-harmonic amplitude of the response [m], and the gradient of its square w.r.t. x.
  virtual double Amplitude(const Eigen::VectorXd& x) const = 0;
  virtual Eigen::VectorXd AmplitudeSquaredGradient(const Eigen::VectorXd& x) const = 0;
  // Loss factor η (CycleEnergy::loss_factor) and, when the gradients are requested, its exact
  // gradient; `e` must hold R at (x, α), and the Jacobians too when gradients are requested.
  virtual double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                            const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                            Eigen::VectorXd* grad_alpha) const = 0;

  virtual std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                                       const Eigen::VectorXd& alpha) const = 0;
  virtual CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                               const Eigen::VectorXd& alpha) const = 0;
};

}  // namespace fricrom
