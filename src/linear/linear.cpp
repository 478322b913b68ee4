#include "fricrom/linear.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

#include "fricrom/units.h"
#include "linear/dense_lapack.h"

namespace fricrom {
namespace {

std::vector<int> AllDofs(const Model& model) {
  std::vector<int> all(model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) all[i] = i;
  return all;
}

}  // namespace

namespace {

// Off-diagonal modal damping below this fraction of the largest entry is round-off: the modal
// receptance, which keeps the diagonal of Φᵀ C Φ, is then exact.
constexpr double kDiagonalDamping = 1e-8;

// Eigenvalues of M relative to its largest below this are massless directions (round-off of an
// exporter's semi-definite mass: the EXTSEOUT superelement's smallest is -7e-12 of 1).
constexpr double kMassless = 1e-9;

// Modes of (K, M) with M positive semi-definite: M φ = μ (K + σM) φ, whose μ are bounded, and
// λ = 1/μ − σ; the directions with μ ≈ 0 have no mass and no finite frequency. σ > 0 always: a
// free body's K passes a Cholesky test on round-off, and its rigid modes' μ = 1/round-off would
// swamp the massless threshold.
bool SemiDefiniteModes(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m, ModalResult* out) {
  const double m_scale = m.cwiseAbs().maxCoeff(), k_scale = k.cwiseAbs().maxCoeff();
  if (!(m_scale > 0)) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> mass_eigen(m, Eigen::EigenvaluesOnly);
  if (mass_eigen.eigenvalues().minCoeff() < -kMassless * mass_eigen.eigenvalues().maxCoeff()) {
    return false;  // indefinite: not a mass
  }
  for (double sigma : {1e-3 * k_scale / m_scale, k_scale / m_scale}) {
    const Eigen::MatrixXd shifted = k + sigma * m;
    if (Eigen::LLT<Eigen::MatrixXd>(shifted).info() != Eigen::Success) continue;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(m, shifted);
    if (solver.info() != Eigen::Success) continue;
    const Eigen::VectorXd& mu = solver.eigenvalues();  // ascending: the largest μ is the lowest λ
    const double mu_max = mu.maxCoeff();
    std::vector<int> kept;
    for (int i = static_cast<int>(mu.size()) - 1; i >= 0; --i) {
      if (mu[i] > kMassless * mu_max) kept.push_back(i);
    }
    out->massless = static_cast<int>(mu.size() - kept.size());
    out->frequencies_hz.resize(static_cast<Eigen::Index>(kept.size()));
    out->shapes.resize(m.rows(), static_cast<Eigen::Index>(kept.size()));
    for (size_t j = 0; j < kept.size(); ++j) {
      const Eigen::Index c = static_cast<Eigen::Index>(j);
      out->frequencies_hz[c] = HzFromEigenvalue(1.0 / mu[kept[j]] - sigma);
      // (K + σM)-normalised φ has φᵀMφ = μ: mass-normalise.
      out->shapes.col(c) = solver.eigenvectors().col(kept[j]) / std::sqrt(mu[kept[j]]);
    }
    return true;
  }
  return false;
}

}  // namespace

ModalResult ComputeModes(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass) {
  if (stiffness.rows() != mass.rows() || stiffness.cols() != mass.cols() ||
      stiffness.rows() != stiffness.cols()) {
    throw std::invalid_argument("ComputeModes: K and M must be square and of equal size");
  }
  ModalResult result;
  if (Eigen::LLT<Eigen::MatrixXd>(mass).info() != Eigen::Success) {
    if (SemiDefiniteModes(stiffness, mass, &result)) return result;
    throw std::invalid_argument(
        "ComputeModes: the mass matrix is not positive semi-definite (a negative eigenvalue "
        "beyond round-off)");
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, mass);
  if (solver.info() != Eigen::Success) {
    throw std::invalid_argument("ComputeModes: the generalized eigenproblem (K, M) failed");
  }
  result.frequencies_hz = solver.eigenvalues().unaryExpr(&HzFromEigenvalue);
  result.shapes = solver.eigenvectors();
  return result;
}

ReceptanceMethod ChooseReceptance(const Model& model, int min_dofs) {
  if (HasCyclicContacts(model)) return ReceptanceMethod::kDense;  // stuck modes per harmonic
  if (model.num_dofs() < min_dofs) return ReceptanceMethod::kDense;
  const Eigen::MatrixXd k = model.stiffness + ContactStickStiffness(model);
  Eigen::VectorXd lambda;
  Eigen::MatrixXd phi;
  if (!dense::SymmetricGeneralizedEigen(k, model.mass, &lambda, &phi)) {
    return ReceptanceMethod::kDense;  // a semi-definite mass: the modal route needs a definite one
  }
  const Eigen::MatrixXd c = phi.transpose() * model.damping * phi;
  const double largest = c.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd off = c - Eigen::MatrixXd(c.diagonal().asDiagonal());
  return off.cwiseAbs().maxCoeff() <= kDiagonalDamping * largest ? ReceptanceMethod::kModal
                                                                 : ReceptanceMethod::kDense;
}

ModalResult FreeSystemModes(const Model& model) {
  return ComputeModes(model.stiffness(model.free_dofs, model.free_dofs),
                      model.mass(model.free_dofs, model.free_dofs));
}

ModalResult StickSystemModes(const Model& model) {
  RequireNoCyclicContacts(model,
                          "the full-stick modes (per nodal diameter: CyclicNaturalFrequencies)");
  return ComputeModes(model.stiffness + ContactStickStiffness(model), model.mass);
}

namespace {

// Modal synthesis of one response entry: |Σ_k φ_rk (φ_kᵀ f) / (λ_k − ω² + iω c_k)|.
std::vector<double> ModalAmplitude(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                                   const Eigen::MatrixXd& c, const Eigen::VectorXcd& f,
                                   int response, const std::vector<double>& freqs_hz) {
  // LAPACK (dsygvd, dgemm) on FE-sized systems: the references of an FE bound curve took 13 % of
  // a bound's time with Eigen's solver; small (lumped) systems keep Eigen's, bit for bit.
  Eigen::VectorXd lambda;
  Eigen::MatrixXd phi;
  if (!dense::SymmetricGeneralizedEigen(k, m, &lambda, &phi)) {
    throw std::invalid_argument(
        "LinearResponseAmplitude: modal route needs a positive definite mass matrix");
  }
  const Eigen::VectorXd cm =
      k.rows() < dense::kLapackMinSize
          ? Eigen::VectorXd((phi.transpose() * c * phi).diagonal())
          : Eigen::VectorXd(
                phi.cwiseProduct(dense::Product(c, false, phi, false)).colwise().sum().transpose());
  const Eigen::VectorXcd weight =
      phi.row(response).transpose().cast<std::complex<double>>().cwiseProduct(phi.transpose() * f);
  std::vector<double> amp;
  for (double fhz : freqs_hz) {
    const double w = RadPerS(fhz);
    std::complex<double> q = 0.0;
    for (Eigen::Index i = 0; i < weight.size(); ++i) {
      q += weight[i] / std::complex<double>(lambda[i] - w * w, w * cm[i]);
    }
    amp.push_back(std::abs(q));
  }
  return amp;
}

}  // namespace

std::vector<double> LinearResponseAmplitude(const Model& model, LinearSystemKind kind,
                                            const std::vector<double>& freqs_hz,
                                            ReceptanceMethod method) {
  std::vector<int> dofs = kind == LinearSystemKind::kFree ? model.free_dofs : AllDofs(model);
  Eigen::MatrixXd k = model.stiffness;
  // A cyclic sector's stuck contacts couple it to the next sector at harmonic 1's phase: the
  // Hermitian stick stiffness X + iY of the real block form [[X, Y], [−Y, X]].
  Eigen::MatrixXd k_imag;
  const bool cyclic = kind == LinearSystemKind::kStick && HasCyclicContacts(model);
  if (cyclic) {
    const Eigen::MatrixXd ks1 = ContactStickStiffness(model, 1);
    const int nd = model.num_dofs();
    k += ks1.topLeftCorner(nd, nd);
    k_imag = ks1.topRightCorner(nd, nd);
  } else if (kind == LinearSystemKind::kStick) {
    k += ContactStickStiffness(model);
  }
  int response = -1;
  for (size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i] == model.response_dof) response = static_cast<int>(i);
  }
  if (response < 0) {
    throw std::invalid_argument("LinearResponseAmplitude: response DOF not in the system");
  }
  const Eigen::MatrixXd ks = k(dofs, dofs), ms = model.mass(dofs, dofs),
                        cs = model.damping(dofs, dofs);
  const int n = static_cast<int>(dofs.size());
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  for (const HarmonicLoad& l : model.loads) {
    if (l.harmonic != 1) continue;
    for (int i = 0; i < n; ++i) f[i] += std::complex<double>(l.cos[dofs[i]], -l.sin[dofs[i]]);
  }
  if (method == ReceptanceMethod::kModal && !cyclic) {
    return ModalAmplitude(ks, ms, cs, f, response, freqs_hz);
  }
  std::vector<double> amp;
  amp.reserve(freqs_hz.size());
  for (double fhz : freqs_hz) {
    const double w = RadPerS(fhz);
    Eigen::MatrixXcd z = (ks - w * w * ms).cast<std::complex<double>>();
    z += std::complex<double>(0.0, w) * cs.cast<std::complex<double>>();
    if (cyclic) z.imag() += k_imag(dofs, dofs);
    const Eigen::VectorXcd q = z.partialPivLu().solve(f);
    amp.push_back(std::abs(q[response]));
  }
  return amp;
}

}  // namespace fricrom
