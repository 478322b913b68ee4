// α groups: several contacts sharing one initial-tangential-force coefficient α. The physical
// non-uniqueness is one α per contact (per node pair of an FE interface); one α per interface is
// the cheaper, coarser model (fewer optimisation variables, a smaller and possibly tighter range).
// AlphaGroupedBalance presents any harmonic balance with grouped α: the solvers see num_alpha() =
// the number of groups, α_contact = α_group(contact), and ∂R/∂α_group = Σ over the group's
// contacts of ∂R/∂α_contact (chain rule). Contact-level outputs (histories, energies) stay per
// contact.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "fricrom/harmonic_balance.h"

namespace fricrom {

class AlphaGroupedBalance final : public HarmonicBalance {
 public:
  // group_of_contact[c] in [0, G) for every contact of `inner`; every group non-empty.
  // Throws std::invalid_argument otherwise.
  AlphaGroupedBalance(std::unique_ptr<HarmonicBalance> inner, std::vector<int> group_of_contact);

  int num_unknowns() const override { return inner_->num_unknowns(); }
  int num_contacts() const override { return inner_->num_contacts(); }
  int num_alpha() const override { return num_groups_; }
  int harmonics() const override { return inner_->harmonics(); }
  std::unique_ptr<HarmonicBalance> WithFewerHarmonics(int harmonics) const override;

  void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                const HbmRequest& request, HbmEvaluation* out) const override;
  double ResidualScale() const override { return inner_->ResidualScale(); }
  JacobianPattern StructuralPattern() const override;
  Eigen::VectorXd FromDofCoefficients(const Eigen::VectorXd& x) const override {
    return inner_->FromDofCoefficients(x);
  }
  Eigen::VectorXd ToDofCoefficients(const Eigen::VectorXd& x, double omega,
                                    const Eigen::VectorXd& alpha) const override {
    return inner_->ToDofCoefficients(x, omega, Expand(alpha));
  }
  Eigen::VectorXd StickLinearSolution(double omega) const override {
    return inner_->StickLinearSolution(omega);
  }
  double Amplitude(const Eigen::VectorXd& x) const override { return inner_->Amplitude(x); }
  Eigen::VectorXd AmplitudeSquaredGradient(const Eigen::VectorXd& x) const override {
    return inner_->AmplitudeSquaredGradient(x);
  }
  std::array<int, 2> ResponseCoefficients() const override {
    return inner_->ResponseCoefficients();
  }
  double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                    const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                    Eigen::VectorXd* grad_alpha) const override;
  std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                               const Eigen::VectorXd& alpha) const override {
    return inner_->ContactHistories(x, omega, Expand(alpha));
  }
  CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                       const Eigen::VectorXd& alpha) const override {
    return inner_->Energies(x, omega, Expand(alpha));
  }
  std::vector<ContactRegime> ContactRegimes(const Eigen::VectorXd& x, double omega,
                                            const Eigen::VectorXd& alpha) const override {
    return inner_->ContactRegimes(x, omega, Expand(alpha));
  }
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double omega,
                                              const Eigen::VectorXd& alpha) const override {
    return inner_->Linearize(x, omega, Expand(alpha));
  }

  // α per contact from α per group (throws on a wrong size).
  Eigen::VectorXd Expand(const Eigen::VectorXd& alpha) const;
  // Σ over each group's columns / entries: per-contact derivatives to per-group ones.
  Eigen::MatrixXd SumColumns(const Eigen::MatrixXd& per_contact) const;

 private:
  std::unique_ptr<HarmonicBalance> inner_;
  std::vector<int> group_;
  int num_groups_ = 0;
};

}  // namespace fricrom
