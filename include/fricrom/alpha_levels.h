// Levels of α: coarse parameterisations of the per-pair initial tangential force coefficients of
// an FE assembly, from one α per interface and direction up to one α per node pair and direction.
// A level maps its parameters c to the fine α by α = clamp(P·c, −1, 1): every c gives an
// admissible fine α, so a level's bounds are a lower estimate of the fine ones, and a bound
// search that starts each level from the optima of the level below (and keeps them as
// candidates) gives fine bounds that contain every coarser level's (docs/theory.md, "α levels").
// AlphaLevelBalance presents a harmonic balance with a level's parameters as its α.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/harmonic_balance.h"

namespace fricrom {

struct Case;

struct AlphaLevel {
  std::string name;                 // "interface", "face", "pair"
  Eigen::MatrixXd map;              // P: fine α × parameters
  std::vector<std::string> labels;  // one per parameter, e.g. "d1L.t1.uniform"
  int num_parameters() const { return static_cast<int>(map.cols()); }
  bool IsIdentity() const;
  // The fine α of parameters c: clamp(P c, −1, 1).
  Eigen::VectorXd FineAlpha(const Eigen::VectorXd& c) const;
  // The parameters c whose fine α is `alpha` (least squares; c clamped to the box). Returns false
  // when no c of this level gives `alpha` to 1e-10.
  bool Lift(const Eigen::VectorXd& alpha, Eigen::VectorXd* c) const;
};

// The α levels of a case, coarsest first; the last is always one parameter per solver α (P = I).
// For an FE assembly whose α is per pair (no interface groups): "interface" (one α per interface
// and tangential direction), "face" (per interface and direction the shapes 1, s1, s2 over the
// face's two in-plane principal axes, s normalised to [−1, 1]) and "pair". Contacts given one by
// one, or a lumped case, have each contact its own interface: one level. A level that equals the
// next finer one is dropped.
std::vector<AlphaLevel> AlphaLevelsOf(const Case& c);

// Structured α a certificate tests beside uniform samples of the fine box (which, in hundreds of
// dimensions, all land near the box's middle): per coarse level, the corners ±1 of every
// parameter alone and of all parameters together, and every parameter at −1 with the rest at +1
// (and the opposite); on the face level every gradient shape alone (±), which tilts one face, and
// each gradient over all faces at once. Fine α, duplicates removed; none for a one-level case.
std::vector<Eigen::VectorXd> StructuredAlphaPatterns(const std::vector<AlphaLevel>& levels);

// `inner` with a level's parameters as its α (α_fine = clamp(P c)); ∂R/∂c = ∂R/∂α · D P with D the
// unsaturated entries (|P c| ≤ 1: a saturated entry's one-sided derivative is kept at the edge).
// Borrows `inner`, which must outlive it, or owns the balance it was given.
class AlphaLevelBalance final : public HarmonicBalance {
 public:
  AlphaLevelBalance(const HarmonicBalance& inner, AlphaLevel level);
  AlphaLevelBalance(std::unique_ptr<HarmonicBalance> owned, AlphaLevel level);

  const AlphaLevel& level() const { return level_; }
  int num_unknowns() const override { return inner_->num_unknowns(); }
  int num_contacts() const override { return inner_->num_contacts(); }
  int num_alpha() const override { return level_.num_parameters(); }
  int harmonics() const override { return inner_->harmonics(); }
  std::unique_ptr<HarmonicBalance> WithFewerHarmonics(int harmonics) const override;

  void Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& c,
                const HbmRequest& request, HbmEvaluation* out) const override;
  double ResidualScale() const override { return inner_->ResidualScale(); }
  Eigen::VectorXd FromDofCoefficients(const Eigen::VectorXd& x) const override {
    return inner_->FromDofCoefficients(x);
  }
  Eigen::VectorXd ToDofCoefficients(const Eigen::VectorXd& x, double omega,
                                    const Eigen::VectorXd& c) const override {
    return inner_->ToDofCoefficients(x, omega, Fine(c));
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
  double LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& c,
                    const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                    Eigen::VectorXd* grad_c) const override;
  std::vector<ContactHistory> ContactHistories(const Eigen::VectorXd& x, double omega,
                                               const Eigen::VectorXd& c) const override {
    return inner_->ContactHistories(x, omega, Fine(c));
  }
  CycleEnergy Energies(const Eigen::VectorXd& x, double omega,
                       const Eigen::VectorXd& c) const override {
    return inner_->Energies(x, omega, Fine(c));
  }
  std::vector<ContactRegime> ContactRegimes(const Eigen::VectorXd& x, double omega,
                                            const Eigen::VectorXd& c) const override {
    return inner_->ContactRegimes(x, omega, Fine(c));
  }
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double omega,
                                              const Eigen::VectorXd& c) const override {
    return inner_->Linearize(x, omega, Fine(c));
  }

  Eigen::VectorXd Fine(const Eigen::VectorXd& c) const;  // throws on a wrong size
  // Per-fine-α derivatives (columns) to per-parameter ones at c: columns · D P.
  Eigen::MatrixXd ChainColumns(const Eigen::MatrixXd& per_fine, const Eigen::VectorXd& c) const;

 private:
  std::unique_ptr<HarmonicBalance> owned_;
  const HarmonicBalance* inner_ = nullptr;
  AlphaLevel level_;
};

}  // namespace fricrom
