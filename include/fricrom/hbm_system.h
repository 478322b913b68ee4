// Harmonic balance (paper Eq. 2/9) with the alternating frequency/time scheme on FFTW.
// Unknowns x are real Fourier coefficients ordered harmonic-major,
//   x = [q̂0 (n) | a1 (n) | b1 (n) | ... | aH (n) | bH (n)],
//   q(t) = q̂0 + Σ a_h cos hωt + b_h sin hωt,
// so the linear part is block-diagonal per harmonic (what condensation onto contact DOFs needs).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/contact_law.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

// False (with a message) when a load of `model` sits at a harmonic outside 0..harmonics: such a
// load cannot be represented and is an input error, never silently dropped.
bool LoadsRepresentable(const Model& model, int harmonics, std::string* error);

// The harmonic-balance residual of one model: R(x; ω, α) = Z(ω) x + F̂c(x, α) − F̂exc.
// Owns a copy of the model and its FFTW plans/workspace; Evaluate is therefore not re-entrant:
// use one HbmSystem per thread.
class HbmSystem : public HarmonicBalance {
 public:
  HbmSystem(Model model, const HbmOptions& options);  // throws std::invalid_argument
  ~HbmSystem() override;
  HbmSystem(const HbmSystem&) = delete;
  HbmSystem& operator=(const HbmSystem&) = delete;

  const Model& model() const { return model_; }
  const HbmOptions& options() const { return options_; }
  int num_dofs() const { return model_.num_dofs(); }
  int num_coefficients() const { return 2 * options_.harmonics + 1; }
  int num_unknowns() const override { return num_dofs() * num_coefficients(); }
  int num_contacts() const override { return static_cast<int>(model_.contacts.size()); }
  int harmonics() const override { return options_.harmonics; }
  std::unique_ptr<HarmonicBalance> WithFewerHarmonics(int harmonics) const override;
  // Index in x of coefficient j (0: static, 2h−1: cos h, 2h: sin h) of DOF d.
  int Index(int dof, int coefficient) const { return coefficient * num_dofs() + dof; }

  void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HbmRequest& request, HbmEvaluation* out) const override;
  double ResidualScale() const override;
  JacobianPattern StructuralPattern() const override;
  Eigen::VectorXd StickLinearSolution(double omega) const override;
  double Amplitude(const Eigen::VectorXd& x) const override { return DofAmplitude(x, -1); }
  Eigen::VectorXd AmplitudeSquaredGradient(const Eigen::VectorXd& x) const override;
  std::array<int, 2> ResponseCoefficients() const override {
    return {Index(model_.response_dof, 1), Index(model_.response_dof, 2)};
  }
  // First-harmonic amplitude of a DOF (−1: the response DOF) [m].
  double DofAmplitude(const Eigen::VectorXd& x, int dof) const;
  double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                    const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                    Eigen::VectorXd* grad_alpha) const override;

  std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                               const Eigen::VectorXd& alpha) const override;
  CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                       const Eigen::VectorXd& alpha) const override;

 private:
  struct Workspace;
  // Residual, Jacobian and α-Jacobian terms of a cyclic contact (AFT evaluated in the workspace).
  void AddCyclicContactForces(const Contact& c, int ci, const HbmRequest& request,
                              Eigen::VectorXd* r, HbmEvaluation* out) const;
  Model model_;
  HbmOptions options_;
  std::unique_ptr<Workspace> work_;
};

}  // namespace fricrom
