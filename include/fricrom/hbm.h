// Harmonic balance (paper Eq. 2/9) with the alternating frequency/time scheme on FFTW.
// Unknowns x are real Fourier coefficients ordered harmonic-major,
//   x = [q̂0 (n) | a1 (n) | b1 (n) | ... | aH (n) | bH (n)],  q(t) = q̂0 + Σ a_h cos hωt + b_h sin
//   hωt,
// so the linear part is block-diagonal per harmonic (what condensation onto contact DOFs needs).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/contact.h"
#include "fricrom/model.h"

namespace fricrom {

struct HbmOptions {
  int harmonics = 1;             // H >= 1: harmonics 0..H are balanced
  int samples_per_period = 128;  // AFT time samples N (must exceed 2H)
  bool IsValid(std::string* error) const;
};

// False (with a message) when a load of `model` sits at a harmonic outside 0..harmonics: such a
// load cannot be represented and is an input error, never silently dropped.
bool LoadsRepresentable(const Model& model, int harmonics, std::string* error);

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

// The harmonic-balance residual of one model: R(x; ω, α) = Z(ω) x + F̂c(x, α) − F̂exc.
// Owns a copy of the model and its FFTW plans/workspace; Evaluate is therefore not re-entrant:
// use one HbmSystem per thread.
class HbmSystem {
 public:
  HbmSystem(Model model, const HbmOptions& options);  // throws std::invalid_argument
  ~HbmSystem();
  HbmSystem(const HbmSystem&) = delete;
  HbmSystem& operator=(const HbmSystem&) = delete;

  const Model& model() const { return model_; }
  const HbmOptions& options() const { return options_; }
  int num_dofs() const { return model_.num_dofs(); }
  int num_coefficients() const { return 2 * options_.harmonics + 1; }
  int num_unknowns() const { return num_dofs() * num_coefficients(); }
  int num_contacts() const { return static_cast<int>(model_.contacts.size()); }
  // Index in x of coefficient j (0: static, 2h−1: cos h, 2h: sin h) of DOF d.
  int Index(int dof, int coefficient) const { return coefficient * num_dofs() + dof; }

  // Throws std::invalid_argument on wrong sizes or |α_c| > 1.
  void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HbmRequest& request, HbmEvaluation* out) const;

  // Norm of the load vector, the scale residual tolerances are relative to.
  double ResidualScale() const;
  // Solution of the full-stick linear system (contacts as kn/kt springs): a Newton start.
  Eigen::VectorXd StickLinearSolution(double omega) const;
  // First-harmonic amplitude of a DOF (default: the response DOF) [m].
  double Amplitude(const Eigen::VectorXd& x, int dof = -1) const;

  std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                               const Eigen::VectorXd& alpha) const;
  CycleEnergy Energies(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha) const;

 private:
  struct Workspace;
  Model model_;
  HbmOptions options_;
  std::unique_ptr<Workspace> work_;
};

}  // namespace fricrom
