// Harmonic balance condensed onto the contact DOFs (issue 10): the nonlinear unknowns are the
// harmonics of the relative displacements of the contacts (u along the tangent, v along the
// normal; a row two contacts share, e.g. the normal gap of a pair with two tangential
// directions, is one unknown) and of the response DOF; the linear remainder is solved per harmonic
// through the receptance of the linear part. With B the relative-displacement operator,
// K_s = diag(kt, kn) the stick stiffness of the contacts and Z̃_h = Z_h + Bᵀ K_s B (the
// full-stick dynamic stiffness, nonsingular even when a damper is held only by its contacts):
//   x̃_h(r) = Z̃_h⁻¹ (f_h − Bᵀ F̃_h(r)),   F̃(r) = F_c(r) − K_s r   (exact, no approximation),
//   R_r = W (r − B x̃(r)) = 0,   R_y = s_y (y − e_respᵀ x̃(r)) = 0,
// with W = diag(max(kn, kt)) per row (so R is in newtons, like the full balance). The
// solution equals the full HbmSystem solution (tests compare both to 1e-10). Unknowns are
// harmonic-major: 2H+1 blocks of [r (num_relative() rows) | y (1)].
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

class HarmonicReceptance;
class AftContactForces;
class HbmSystem;
struct ContactForceBlocks;
struct AftDerivatives;
struct EffectiveForceBlocks;

class CondensedSystem : public HarmonicBalance {
 public:
  CondensedSystem(Model model, const HbmOptions& options);  // throws std::invalid_argument
  ~CondensedSystem() override;
  CondensedSystem(const CondensedSystem&) = delete;
  CondensedSystem& operator=(const CondensedSystem&) = delete;

  const Model& model() const { return model_; }
  // Distinct relative-displacement rows (≤ 2 per contact).
  int num_relative() const { return static_cast<int>(b_.rows()); }
  int block_size() const { return num_relative() + 1; }
  int num_unknowns() const override;
  int num_contacts() const override { return static_cast<int>(model_.contacts.size()); }
  int harmonics() const override { return options_.harmonics; }
  // Shares this system's receptance (its G_0, G_1, ... are the lower system's).
  std::unique_ptr<HarmonicBalance> WithFewerHarmonics(int harmonics) const override;

  void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HbmRequest& request, HbmEvaluation* out) const override;
  // W (I + G_h ∂F̃/∂r) applied per harmonic: G_h is block-diagonal over the harmonics, so a
  // product costs Σ_h (m_h n_r)² against the dense Jacobian's ((2H+1)(n_r+1))² (5/9 at H = 1,
  // 13/49 at H = 3), with no Jacobian to assemble.
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double omega,
                                              const Eigen::VectorXd& alpha) const override;
  double ResidualScale() const override;
  Eigen::VectorXd StickLinearSolution(double omega) const override;
  double Amplitude(const Eigen::VectorXd& x) const override;
  Eigen::VectorXd AmplitudeSquaredGradient(const Eigen::VectorXd& x) const override;
  std::array<int, 2> ResponseCoefficients() const override {
    return {Idx(1, num_relative()), Idx(2, num_relative())};
  }
  double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                    const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                    Eigen::VectorXd* grad_alpha) const override;
  std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                               const Eigen::VectorXd& alpha) const override;
  CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                       const Eigen::VectorXd& alpha) const override;
  // From the AFT of the relative-displacement unknowns (no recovery of the DOFs).
  std::vector<ContactRegime> ContactRegimes(const Eigen::VectorXd& x, double omega,
                                            const Eigen::VectorXd& alpha) const override;

  // The relative-displacement operator B (num_relative() × DOFs; harmonic 0's on a cyclic
  // sector, whose harmonics h ≥ 1 read the next sector delayed), the stick stiffness per row
  // (K_s = diag) and contact c's tangential row: the linear part a Hill analysis reduces.
  const Eigen::MatrixXd& relative_operator() const { return b_; }
  const Eigen::VectorXd& stick_stiffness() const { return ks_; }
  int tangential_row(int c) const { return row_t_[c]; }
  // ∂F̃/∂r at (x, α), F̃ = F_c − K_s r, coefficient-major ((2H+1)·num_relative() square: entry
  // (j·n_r + i, l·n_r + k) is ∂F̃_i(coefficient j)/∂r_k(coefficient l)). Contacts flagged in
  // `as_springs` (empty: none) count as their linear stick springs, which add nothing to F̃.
  Eigen::MatrixXd ContactForceJacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& alpha,
                                       const std::vector<bool>& as_springs = {}) const;

  // All DOF coefficients (hbm.h layout) of condensed unknowns x at (ω, α): x̃(r).
  Eigen::VectorXd Recover(const Eigen::VectorXd& x, double omega,
                          const Eigen::VectorXd& alpha) const;
  // Condensed unknowns of full DOF coefficients (r = B x, y = response DOF).
  Eigen::VectorXd Condense(const Eigen::VectorXd& x_full) const;
  Eigen::VectorXd FromDofCoefficients(const Eigen::VectorXd& x_full) const override {
    return Condense(x_full);
  }
  Eigen::VectorXd ToDofCoefficients(const Eigen::VectorXd& x, double omega,
                                    const Eigen::VectorXd& alpha) const override {
    return Recover(x, omega, alpha);
  }

 private:
  // The sibling with fewer harmonics (WithFewerHarmonics).
  CondensedSystem(const CondensedSystem& higher, int harmonics);
  int Idx(int coefficient, int row) const { return coefficient * block_size() + row; }
  // b_, ks_, w_ and each contact's rows (row_t_, row_n_), identical rows merged.
  void BuildRelativeRows();
  void CheckInputs(const Eigen::VectorXd& x, const Eigen::VectorXd& alpha) const;
  // Contact forces F̃ (coefficient-major, per relative row) at x; blocks_ keep derivatives.
  Eigen::VectorXd ContactForces(const Eigen::VectorXd& x, const Eigen::VectorXd& alpha,
                                AftDerivatives derivatives) const;
  // Stacked F̃ (or r) of harmonic h: [coef 2h−1 rows; coef 2h rows], or coef 0.
  Eigen::VectorXd Stack(int h, const Eigen::VectorXd& coefficient_major) const;
  // A (rows × m·nr, m = coefficients of harmonic h) times ∂F̃_h/∂r -> rows × nh·nr.
  Eigen::MatrixXd TimesForceJacobian(int h, const Eigen::MatrixXd& a) const;
  // Contact c's ∂F̃/∂r blocks from blocks_ (after ContactForces with derivatives).
  void EffectiveBlocks(int c, EffectiveForceBlocks* out) const;
  Eigen::VectorXd Excitation(int h) const;

  Model model_;
  HbmOptions options_;
  Eigen::MatrixXd b_;  // relative-displacement operator, one row per distinct (u or v) row
  // Cyclic symmetry: each row's terms on the next sector's DOFs (part of b_, which is harmonic
  // 0's operator) and the delay per harmonic of its contact; empty without cyclic contacts.
  Eigen::MatrixXd next_;
  Eigen::VectorXd phase_;
  std::vector<int> row_t_, row_n_;  // each contact's tangential and normal row of b_
  Eigen::VectorXd ks_;              // stick stiffness per row (sum of the contacts' kt or kn on it)
  Eigen::VectorXd w_;               // row weights of R_r
  double sy_ = 1.0;                 // weight of R_y
  std::shared_ptr<HarmonicReceptance> receptance_;
  std::unique_ptr<AftContactForces> aft_;
  std::unique_ptr<HbmSystem> full_;  // the uncondensed balance: energies, histories, η
  mutable std::vector<ContactForceBlocks> blocks_;
  // The (x, α) that blocks_ belong to, their forces F̃ and the derivatives computed
  // (ContactForces).
  struct ForceMemo {
    bool valid = false;
    Eigen::VectorXd x, alpha, ft;
    bool displacement = false, alpha_derivative = false;
  };
  mutable ForceMemo memo_;
};

}  // namespace fricrom
