// Hill stability of a condensed-balance solution (stability.h): the linear part reduced to the
// full-stick modes below a cutoff (dynamic) and the residual flexibility of the contact rows
// (quasi-static), the implicit modal time integration's model, so that both checks judge the
// same dynamics; then the dense Hill analysis on the modes alone.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/condensed_system.h"
#include "fricrom/linear.h"
#include "fricrom/stability.h"
#include "fricrom/units.h"

namespace fricrom {
namespace {

// The reduced basis at one cutoff: full-stick modes below it (mass-normalised, at least one) and
// the residual attachments of the contact rows, Ψ = (K_s⁻¹ − Φ Λ⁻¹ Φᵀ) Bᵀ made K-orthonormal
// (rank-deficient directions dropped). Both are K- and M-orthogonal to each other.
struct HillBasis {
  Eigen::MatrixXd phi, psi;
  Eigen::VectorXd lambda;  // ω_j² of phi's modes
};

// The reduced balance's linear blocks (hbm_system.h layout over q = m + p coordinates): the modes
// with Λ, I and Φᵀ C Φ, the residual coordinates with their unit stiffness only (massless).
Eigen::MatrixXd ReducedLinearJacobian(const HillBasis& basis, const Eigen::MatrixXd& modal_damping,
                                      int harmonics, double omega) {
  const Eigen::Index m = basis.phi.cols(), q = m + basis.psi.cols(), nh = 2 * harmonics + 1;
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(nh * q, nh * q);
  for (Eigen::Index c = 0; c < nh; ++c) {
    const int h = static_cast<int>((c + 1) / 2);
    const double w2 = (h * omega) * (h * omega);
    for (Eigen::Index i = 0; i < q; ++i) {
      j(c * q + i, c * q + i) = i < m ? basis.lambda[i] - w2 : 1.0;
    }
    if (h == 0) continue;
    const Eigen::Index a = (2 * h - 1) * q, s = 2 * h * q;
    if (c == 2 * h - 1) {
      j.block(a, s, m, m) = h * omega * modal_damping;   // cosine row: C times hω b
      j.block(s, a, m, m) = -h * omega * modal_damping;  // sine row: C times −hω a
    }
  }
  return j;
}

}  // namespace

struct CondensedHill::Modal {
  ModalResult modes;        // full-stick modes of the whole model
  Eigen::MatrixXd k_s;      // K + Bᵀ K_s B
  Eigen::MatrixXd flex;     // K_s⁻¹ Bᵀ
  double flex_floor = 0.0;  // rank threshold of the residual attachments
};

CondensedHill::CondensedHill(const CondensedSystem& system)
    : system_(system), modal_(std::make_unique<Modal>()) {
  if (HasCyclicContacts(system.model())) {
    // A sector's Floquet exponents would judge only perturbations of its own nodal diameters.
    throw std::domain_error(
        "a cyclic sector's Floquet exponents would judge its own nodal diameters only");
  }
  const Model& model = system.model();
  modal_->k_s = model.stiffness + ContactStickStiffness(model);
  try {
    modal_->modes = ComputeModes(modal_->k_s, model.mass);
  } catch (const std::invalid_argument& e) {
    throw std::domain_error(e.what());  // a mass the modes cannot use: not computed, said why
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(modal_->k_s);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    throw std::domain_error("the full-stick stiffness is not positive definite");
  }
  const Eigen::MatrixXd bt = system.relative_operator().transpose();
  modal_->flex = ldlt.solve(bt);
  // Relative to the whole flexibility B K_s⁻¹ Bᵀ: with every mode kept the residual is round-off.
  modal_->flex_floor = 1e-10 * (bt.transpose() * modal_->flex).diagonal().maxCoeff();
}

CondensedHill::~CondensedHill() = default;

HillResult CondensedHill::At(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                             const HillOptions& options) const {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const CondensedSystem& system = system_;
  const Model& model = system.model();
  const int nh = 2 * system.harmonics() + 1, nr = system.num_relative();
  const ModalResult& modes = modal_->modes;
  HillBasis basis;
  Eigen::Index kept = 0;
  while (kept < modes.frequencies_hz.size() &&
         modes.frequencies_hz[kept] < options.modal_cutoff_factor * Hz(omega)) {
    ++kept;
  }
  kept = std::max<Eigen::Index>(kept, 1);
  basis.phi = modes.shapes.leftCols(kept);
  basis.lambda = modes.frequencies_hz.head(kept).unaryExpr(&EigenvalueFromHz);
  const Eigen::MatrixXd bt = system.relative_operator().transpose();
  const Eigen::MatrixXd psi = modal_->flex - basis.phi * (basis.lambda.cwiseInverse().asDiagonal() *
                                                          (basis.phi.transpose() * bt));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(psi.transpose() * modal_->k_s * psi);
  const Eigen::VectorXd ev = gram.eigenvalues();
  std::vector<int> keep;
  for (int i = 0; i < ev.size(); ++i) {
    if (ev[i] > modal_->flex_floor && ev[i] > 0.0) keep.push_back(i);
  }
  basis.psi.resize(model.num_dofs(), static_cast<Eigen::Index>(keep.size()));
  for (size_t i = 0; i < keep.size(); ++i) {
    basis.psi.col(static_cast<Eigen::Index>(i)) =
        psi * gram.eigenvectors().col(keep[i]) / std::sqrt(ev[keep[i]]);
  }
  const Eigen::Index m = basis.phi.cols(), p = basis.psi.cols(), q = m + p;
  // As for the full balance: a contact stuck over the whole period holds a perturbation with its
  // stick springs in every harmonic — F̃ = F_c − K_s r adds nothing for it.
  const std::vector<ContactRegime> regimes = system.ContactRegimes(x, omega, alpha);
  std::vector<bool> as_springs(regimes.size());
  for (size_t c = 0; c < regimes.size(); ++c)
    as_springs[c] = regimes[c] == ContactRegime::kFullStick;
  const Eigen::MatrixXd d = system.ContactForceJacobian(x, alpha, as_springs);
  Eigen::MatrixXd br(nr, q);
  br << system.relative_operator() * basis.phi, system.relative_operator() * basis.psi;
  Eigen::MatrixXd j = ReducedLinearJacobian(
      basis, basis.phi.transpose() * model.damping * basis.phi, system.harmonics(), omega);
  Eigen::MatrixXd db(nh * nr, nh * q);  // D (I ⊗ B_r)
  for (int l = 0; l < nh; ++l) db.middleCols(l * q, q) = d.middleCols(l * nr, nr) * br;
  for (int c = 0; c < nh; ++c) j.middleRows(c * q, q) += br.transpose() * db.middleRows(c * nr, nr);
  // Eliminate the massless residual coordinates: J_eff = J_dd − J_ds J_ss⁻¹ J_sd.
  std::vector<Eigen::Index> dyn, sta;
  for (Eigen::Index c = 0; c < nh; ++c) {
    for (Eigen::Index i = 0; i < q; ++i) (i < m ? dyn : sta).push_back(c * q + i);
  }
  const auto pick = [&](const std::vector<Eigen::Index>& r, const std::vector<Eigen::Index>& s) {
    Eigen::MatrixXd out(static_cast<Eigen::Index>(r.size()), static_cast<Eigen::Index>(s.size()));
    for (size_t a = 0; a < r.size(); ++a) {
      for (size_t b = 0; b < s.size(); ++b) out(a, b) = j(r[a], s[b]);
    }
    return out;
  };
  Eigen::MatrixXd j_eff = pick(dyn, dyn);
  if (p > 0) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(pick(sta, sta));
    if (!(lu.rcond() > 1e-13)) {
      throw std::domain_error(
          "a residual (quasi-static) direction has no stiffness at this solution (a body the "
          "contacts hold only by sliding friction): its Floquet exponents need its mass");
    }
    j_eff -= pick(dyn, sta) * lu.solve(pick(sta, dyn));
  }
  HillResult r = HillStability(j_eff, Eigen::MatrixXd::Identity(m, m),
                               basis.phi.transpose() * model.damping * basis.phi,
                               system.harmonics(), omega, options);
  r.message +=
      " (" + std::to_string(m) + " full-stick modes below " +
      std::to_string(static_cast<int>(std::lround(options.modal_cutoff_factor * Hz(omega)))) +
      " Hz, " + std::to_string(p) + " residual directions quasi-static)";
  NoteSwitchingContacts(regimes, &r);
  return r;
}

HillResult HillStability(const CondensedSystem& system, const Eigen::VectorXd& x, double omega,
                         const Eigen::VectorXd& alpha, const HillOptions& options) {
  return CondensedHill(system).At(x, omega, alpha, options);
}

}  // namespace fricrom
