// What the nonlinear solvers (Newton, continuation, bounds, sweeps, NOA, certification) see of a
// harmonic-balance problem R(x; ω, α) = 0: unknowns x, one α per contact direction, the residual
// with its exact derivatives, and the few response quantities they rank and report. The full
// lumped/FE system (HbmSystem) and the system condensed onto the contact DOFs (CondensedSystem)
// both implement it, so one code path serves both (Spectra's operator idea).
// Units: SI; ω in rad/s.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/contact_law.h"
#include "fricrom/formulation.h"
#include "fricrom/solve.h"

namespace fricrom {

struct HbmOptions {
  int harmonics = 1;                                       // H >= 1: harmonics 0..H are balanced
  int samples_per_period = 128;                            // AFT time samples N (must exceed 2H)
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

// Entries of [∂R/∂x | ∂R/∂α] that can be nonzero at some (x, ω, α): the fixed structure handed to
// sparse solvers (Ipopt). Column c < num_unknowns() is x_c, column num_unknowns() + g is α_g.
struct JacobianPattern {
  std::vector<int> rows, cols;  // one entry per structural nonzero, no duplicates
  int nnz() const { return static_cast<int>(rows.size()); }
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
  // Where in x the response's first-harmonic cosine and sine coefficients are (Amplitude is
  // their hypot): every balance carries them as unknowns.
  virtual std::array<int, 2> ResponseCoefficients() const = 0;
  // Loss factor η (CycleEnergy::loss_factor) and, when the gradients are requested, its exact
  // gradient; `e` must hold R at (x, α), and the Jacobians too when gradients are requested.
  virtual double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                            const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                            Eigen::VectorXd* grad_alpha) const = 0;

  virtual std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                                       const Eigen::VectorXd& alpha) const = 0;
  virtual CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                               const Eigen::VectorXd& alpha) const = 0;
  // Each contact's regime over the period (ContactHistories' `regime`). A balance may classify
  // from its own unknowns for less: the condensed one from its relative displacements, without
  // recovering every DOF (equal to the histories' regimes at solutions, up to samples on a
  // state boundary).
  virtual std::vector<ContactRegime> ContactRegimes(const Eigen::VectorXd& x, double omega,
                                                    const Eigen::VectorXd& alpha) const;

  // ∂R/∂x at (x, ω, α) as a matrix-free operator (nullptr, the default, where forming the
  // Jacobian is as cheap). It keeps its own copy of the contact derivatives and reads this
  // balance's linear part: use it on the thread that owns the balance, while the balance lives.
  virtual std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double omega,
                                                      const Eigen::VectorXd& alpha) const;

  // Structural nonzeros of the Jacobians (dense unless a balance knows better; the condensed
  // balance is dense through the receptance, the full one is as sparse as K, M, C and the
  // contacts' DOFs).
  virtual JacobianPattern StructuralPattern() const;

  // This balance's unknowns from the harmonic coefficients of every DOF (hbm.h layout, e.g.
  // LastPeriodCoefficients of a time integration): the full balance takes them as they are, the
  // condensed one the contacts' relative displacements and the response DOF. Throws
  // std::invalid_argument on a size mismatch.
  virtual Eigen::VectorXd FromDofCoefficients(const Eigen::VectorXd& dof_coefficients) const;
  // The harmonic coefficients of every DOF (hbm.h layout) of this balance's solution x at
  // (ω, α): x itself for the full balance, the recovered DOFs for the condensed one.
  virtual Eigen::VectorXd ToDofCoefficients(const Eigen::VectorXd& x, double omega,
                                            const Eigen::VectorXd& alpha) const;

  // Harmonic continuation: the same problem with fewer harmonics (1 ≤ harmonics < harmonics()),
  // cheap to build (it may share this one's linear part). From the stick start, Newton at H = 3
  // crawls through dozens of damped steps while contacts switch; started from the H = 1 solution
  // it converges in a few. nullptr where not available (e.g. loads at the dropped harmonics).
  virtual std::unique_ptr<HarmonicBalance> WithFewerHarmonics(int harmonics) const;
  // WithFewerHarmonics(1), built on first use and kept (nullptr for H = 1 or where unavailable).
  const HarmonicBalance* FirstHarmonicBalance() const;
  // This system's x from x_low of one with fewer harmonics: its coefficients, the higher harmonics
  // zero (every balance here orders x harmonic-major in equal blocks). Throws on a size mismatch.
  Eigen::VectorXd EmbedLowerHarmonics(const Eigen::VectorXd& x_low, int low_harmonics) const;

 private:
  mutable std::unique_ptr<HarmonicBalance> first_harmonic_;
  mutable bool first_harmonic_tried_ = false;
};

}  // namespace fricrom
