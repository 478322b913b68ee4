// Craig-Bampton reduction: partition, constraint modes (CHOLMOD multi-RHS solve), fixed-interface
// modes (ARPACK on the Cholesky-transformed operator, or dense), reduced matrices and their checks.

// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's SelfAdjointEigenSolver when Eigen
// is not a system include (CMake's Eigen3::Eigen target is; a hand -I is not).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "cholmod_factor.h"
#include "fricrom/reduction.h"
#include "fricrom/units.h"
#include "interior_modes.h"
#include "linear/dense_lapack.h"

namespace fricrom {
namespace {

using reduction_detail::CholmodFactor;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double MaxAbs(const Eigen::MatrixXd& a) { return a.size() ? a.cwiseAbs().maxCoeff() : 0.0; }

double MaxAbs(const Eigen::SparseMatrix<double>& a) {
  double m = 0.0;
  for (int k = 0; k < a.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it)
      m = std::max(m, std::abs(it.value()));
  return m;
}

// Symmetric (relative 1e-8) and finite: a NaN or Inf in K or M is bad input, not a result.
void CheckSymmetricFinite(const Eigen::SparseMatrix<double>& a, const char* name) {
  for (int k = 0; k < a.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw std::invalid_argument(
            std::string("ReduceCraigBampton: ") + name + " holds a non-finite value at row " +
            std::to_string(it.row() + 1) + ", column " + std::to_string(it.col() + 1));
      }
    }
  }
  const Eigen::SparseMatrix<double> at = a.transpose();
  const Eigen::SparseMatrix<double> d = a - at;
  const double scale = MaxAbs(a);
  if (MaxAbs(d) > 1e-8 * scale) {
    throw std::invalid_argument(std::string("ReduceCraigBampton: ") + name +
                                " is not symmetric (store both triangles)");
  }
}

// Blocks of a symmetric matrix in the [boundary | interior] partition.
struct Blocks {
  Eigen::SparseMatrix<double> ii;  // n_i x n_i
  Eigen::SparseMatrix<double> ib;  // n_i x n_b
  Eigen::MatrixXd bb;              // n_b x n_b
};

Blocks Partition(const Eigen::SparseMatrix<double>& a, const std::vector<int>& new_index,
                 const std::vector<bool>& is_boundary, int nb, int ni) {
  std::vector<Eigen::Triplet<double>> tii, tib;
  Blocks out;
  out.bb = Eigen::MatrixXd::Zero(nb, nb);
  for (int col = 0; col < a.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, col); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      const int nr = new_index[r], nc = new_index[c];
      if (is_boundary[r] && is_boundary[c]) {
        out.bb(nr, nc) += it.value();
      } else if (!is_boundary[r] && !is_boundary[c]) {
        tii.emplace_back(nr, nc, it.value());
      } else if (!is_boundary[r]) {
        tib.emplace_back(nr, nc, it.value());
      }
    }
  }
  out.ii.resize(ni, ni);
  out.ii.setFromTriplets(tii.begin(), tii.end());
  out.ib.resize(ni, nb);
  out.ib.setFromTriplets(tib.begin(), tib.end());
  return out;
}

// A * B for sparse A and a dense B with many columns, row by row: each sparse entry scales a
// contiguous row of B (Eigen's column-major path walks A once per column of B: ~4x slower here).
Eigen::MatrixXd SparseTimesDense(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixXd& b) {
  using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  using RowDense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  if (b.cols() == 0) return Eigen::MatrixXd::Zero(a.rows(), 0);
  const RowSparse ar = a;
  const RowDense br = b;
  const RowDense cr = ar * br;
  return Eigen::MatrixXd(cr);
}

}  // namespace

const char* ToString(CraigBamptonStatus status) {
  switch (status) {
    case CraigBamptonStatus::kSuccess:
      return "SUCCESS";
    case CraigBamptonStatus::kFactorizationFailed:
      return "FACTORIZATION_FAILED";
    case CraigBamptonStatus::kEigenNotConverged:
      return "EIGEN_NOT_CONVERGED";
    case CraigBamptonStatus::kChecksFailed:
      return "CHECKS_FAILED";
  }
  return "UNKNOWN";
}

bool CraigBamptonOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (num_modes < 1) return fail("num_modes must be >= 1, got " + std::to_string(num_modes));
  if (!(std::isfinite(cutoff_hz) && cutoff_hz >= 0.0))
    return fail("cutoff_hz must be finite and >= 0 (0: use num_modes)");
  if (!(std::isfinite(shift) && shift <= 0.0))
    return fail("shift must be finite and <= 0 (the lowest modes are computed)");
  if (!(std::isfinite(eigen_tolerance) && eigen_tolerance >= 0.0))
    return fail("eigen_tolerance must be finite and >= 0 (0: machine precision)");
  if (max_eigen_iterations < 1) return fail("max_eigen_iterations must be >= 1");
  if (dense_eigen_max_size < 0) return fail("dense_eigen_max_size must be >= 0");
  if (!(std::isfinite(check_tolerance) && check_tolerance > 0.0))
    return fail("check_tolerance must be finite and > 0");
  return true;
}

double CraigBamptonChecks::Max() const {
  // NaN-propagating: std::max drops a NaN, and a check that produced NaN must fail the run.
  double worst = 0.0;
  for (double v : {stiffness_symmetry, mass_symmetry, stiffness_coupling, modal_mass,
                   modal_stiffness, eigen_residual}) {
    worst = NanMax(worst, v);
  }
  return worst;
}

std::string CraigBamptonSummary::BriefReport() const {
  char buf[512];
  const double f0 = frequencies_hz.empty() ? 0.0 : frequencies_hz.front();
  const double f1 = frequencies_hz.empty() ? 0.0 : frequencies_hz.back();
  std::snprintf(buf, sizeof buf,
                "Craig-Bampton %s: n=%d (boundary %d, interior %d), %d modes %.4g-%.4g Hz, %s "
                "(%d batches, %d restarts, %d solves), checks max %.2e, %.3f s (factor %.3f, "
                "psi %.3f, eig %.3f, assembly %.3f)",
                ToString(status), num_dofs, num_boundary, num_interior, modes, f0, f1,
                dense_eigensolver ? "dense" : "ARPACK", eigen_batches, eigen_restarts,
                operator_applications, checks.Max(), wall_s, factor_s, constraint_modes_s, eigen_s,
                assembly_s);
  std::string s = buf;
  if (!message.empty()) s += ": " + message;
  return s;
}

namespace {

// Caller contract; returns the boundary flags. Throws std::invalid_argument.
std::vector<bool> CheckContract(const Eigen::SparseMatrix<double>& stiffness,
                                const Eigen::SparseMatrix<double>& mass,
                                const std::vector<int>& boundary,
                                const CraigBamptonOptions& options,
                                const CraigBamptonSummary* summary) {
  if (summary == nullptr) throw std::invalid_argument("ReduceCraigBampton: summary is null");
  std::string err;
  if (!options.IsValid(&err)) throw std::invalid_argument("CraigBamptonOptions: " + err);
  const Eigen::Index n_full = stiffness.rows();
  if (stiffness.cols() != n_full || mass.rows() != n_full || mass.cols() != n_full) {
    throw std::invalid_argument("ReduceCraigBampton: K and M must be square and of equal size");
  }
  if (n_full == 0) throw std::invalid_argument("ReduceCraigBampton: empty model");
  const int n = static_cast<int>(n_full);
  std::vector<bool> is_boundary(static_cast<size_t>(n), false);
  for (int b : boundary) {
    if (b < 0 || b >= n) {
      throw std::invalid_argument("ReduceCraigBampton: boundary index " + std::to_string(b) +
                                  " out of range [0, " + std::to_string(n) + ")");
    }
    if (is_boundary[b]) {
      throw std::invalid_argument("ReduceCraigBampton: duplicate boundary index " +
                                  std::to_string(b));
    }
    is_boundary[b] = true;
  }
  CheckSymmetricFinite(stiffness, "K");
  CheckSymmetricFinite(mass, "M");
  return is_boundary;
}

// T^T K T and T^T M T with T = [[I, 0], [Psi, Phi]], block by block: K_ib and M_ib stay sparse
// (a few boundary columns); the dense work is M_ii Psi and Psi^T (M_ii Psi) (lower triangle).
// Fills the structural checks except the eigen residual.
void Assemble(const Blocks& kb, const Blocks& mb, const Eigen::VectorXd& lambda,
              const Eigen::MatrixXd& kii_phi, const Eigen::MatrixXd& mii_phi, double k_max,
              ReducedModel* out, CraigBamptonChecks* ch) {
  // aᵀ b through BLAS dgemm: ~10x Eigen's portable kernels on the tall products (123k rows).
  const auto TransposeTimes = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return dense::Product(a, true, b, false);
  };
  const Eigen::MatrixXd& psi = out->constraint_modes;
  const Eigen::MatrixXd& phi = out->normal_modes;
  const int nb = static_cast<int>(psi.cols()), ni = static_cast<int>(psi.rows());
  const int nq = static_cast<int>(phi.cols());
  // K: K_ii Psi = -K_ib, so K_bb + K_ib^T Psi + Psi^T (K_ib + K_ii Psi) = K_bb + K_ib^T Psi.
  Eigen::MatrixXd& k = out->stiffness;
  k.resize(nb + nq, nb + nq);
  k.topLeftCorner(nb, nb) = kb.bb + kb.ib.transpose() * psi;
  const Eigen::MatrixXd kbq = kb.ib.transpose() * phi + TransposeTimes(psi, kii_phi);
  k.topRightCorner(nb, nq) = kbq;
  k.bottomLeftCorner(nq, nb) = kbq.transpose();
  k.bottomRightCorner(nq, nq) = TransposeTimes(phi, kii_phi);
  const Eigen::MatrixXd mii_psi = SparseTimesDense(mb.ii, psi);
  const Eigen::MatrixXd mib_t_psi = mb.ib.transpose() * psi;
  Eigen::MatrixXd& m = out->mass;
  m.resize(nb + nq, nb + nq);
  m.topLeftCorner(nb, nb) =
      mb.bb + mib_t_psi + mib_t_psi.transpose() +
      (nb > 0 && ni > 0 ? TransposeTimes(psi, mii_psi) : Eigen::MatrixXd::Zero(nb, nb));
  const Eigen::MatrixXd mbq = mb.ib.transpose() * phi + TransposeTimes(psi, mii_phi);
  m.topRightCorner(nb, nq) = mbq;
  m.bottomLeftCorner(nq, nb) = mbq.transpose();
  m.bottomRightCorner(nq, nq) = TransposeTimes(phi, mii_phi);

  const double kmax = MaxAbs(k), mmax = MaxAbs(m);
  ch->stiffness_symmetry = kmax > 0 ? MaxAbs(Eigen::MatrixXd(k - k.transpose())) / kmax : 0.0;
  ch->mass_symmetry = mmax > 0 ? MaxAbs(Eigen::MatrixXd(m - m.transpose())) / mmax : 0.0;
  const double coupling_scale = k_max * MaxAbs(phi) * (1.0 + MaxAbs(psi));
  ch->stiffness_coupling = coupling_scale > 0 ? MaxAbs(kbq) / coupling_scale : 0.0;
  if (nq > 0) {
    const auto qq = Eigen::seqN(nb, nq);
    ch->modal_mass = MaxAbs(Eigen::MatrixXd(m(qq, qq) - Eigen::MatrixXd::Identity(nq, nq)));
    ch->modal_stiffness = MaxAbs(Eigen::MatrixXd(k(qq, qq) - Eigen::MatrixXd(lambda.asDiagonal())));
  }
  k = 0.5 * (k + k.transpose()).eval();
  m = 0.5 * (m + m.transpose()).eval();
}

// max_j ||K_ii phi_j - lambda_j M_ii phi_j|| / ((max|K_ii| + |lambda_j| max|M_ii|) ||phi_j||),
// NaN-propagating.
double EigenResidual(const Blocks& kb, const Blocks& mb, const Eigen::VectorXd& lambda,
                     const Eigen::MatrixXd& phi, const Eigen::MatrixXd& kii_phi,
                     const Eigen::MatrixXd& mii_phi) {
  const double kii_max = MaxAbs(kb.ii), mii_max = MaxAbs(mb.ii);
  double worst = 0.0;
  for (Eigen::Index j = 0; j < lambda.size(); ++j) {
    const double den = (kii_max + std::abs(lambda(j)) * mii_max) * phi.col(j).norm();
    const double r = (kii_phi.col(j) - lambda(j) * mii_phi.col(j)).norm();
    worst = NanMax(worst, den > 0 ? r / den : r);
  }
  return worst;
}

// Row of each DOF in [boundary in the given order | interior ascending]; fills the interior list.
std::vector<int> NewIndex(const std::vector<int>& boundary, const std::vector<bool>& is_boundary,
                          std::vector<int>* interior) {
  std::vector<int> new_index(is_boundary.size());
  for (size_t j = 0; j < boundary.size(); ++j) new_index[boundary[j]] = static_cast<int>(j);
  for (int i = 0, c = 0; i < static_cast<int>(is_boundary.size()); ++i) {
    if (!is_boundary[i]) {
      new_index[i] = c++;
      interior->push_back(i);
    }
  }
  return new_index;
}

// Scales each column to phi^T M_ii phi = 1 (exact per column); returns M_ii Phi, kept for the
// reduced mass matrix and the residual check.
Eigen::MatrixXd MassNormalise(const Eigen::SparseMatrix<double>& mii, Eigen::MatrixXd* phi) {
  Eigen::MatrixXd mii_phi = SparseTimesDense(mii, *phi);
  for (Eigen::Index j = 0; j < phi->cols(); ++j) {
    const double scale = 1.0 / std::sqrt(phi->col(j).dot(mii_phi.col(j)));
    phi->col(j) *= scale;
    mii_phi.col(j) *= scale;
  }
  return mii_phi;
}

}  // namespace

ReducedModel ReduceCraigBampton(const Eigen::SparseMatrix<double>& stiffness,
                                const Eigen::SparseMatrix<double>& mass,
                                const std::vector<int>& boundary,
                                const CraigBamptonOptions& options, CraigBamptonSummary* summary) {
  const auto t_start = Clock::now();
  // ---- 1. Caller contract.
  const std::vector<bool> is_boundary = CheckContract(stiffness, mass, boundary, options, summary);
  CraigBamptonSummary& s = *summary;
  s = CraigBamptonSummary{};
  const int n = static_cast<int>(stiffness.rows()), nb = static_cast<int>(boundary.size());
  const int ni = n - nb;
  s.num_dofs = n;
  s.num_boundary = nb;
  s.num_interior = ni;
  ReducedModel out;
  out.boundary_dofs = boundary;
  auto finish = [&](CraigBamptonStatus st, const std::string& msg) {
    s.status = st;
    s.message = msg;
    s.wall_s = Seconds(t_start);
    if (st != CraigBamptonStatus::kSuccess && st != CraigBamptonStatus::kChecksFailed) {
      ReducedModel empty;
      empty.boundary_dofs = boundary;
      return empty;
    }
    return out;
  };

  // ---- 2. Partition [boundary in the given order | interior ascending].
  const std::vector<int> new_index = NewIndex(boundary, is_boundary, &out.interior_dofs);
  const Blocks kb = Partition(stiffness, new_index, is_boundary, nb, ni);
  const Blocks mb = Partition(mass, new_index, is_boundary, nb, ni);

  // ---- 3. Factor K_ii once; constraint modes Psi = -K_ii^-1 K_ib.
  CholmodFactor kfac;
  std::string err;
  auto t0 = Clock::now();
  if (ni > 0 && (nb > 0 || options.shift == 0.0) && !kfac.Factorize(kb.ii, &err)) {
    s.factor_s = Seconds(t0);
    return finish(CraigBamptonStatus::kFactorizationFailed,
                  "K_ii: " + err +
                      (nb == 0 ? ""
                               : "; the boundary DOFs must suppress every rigid-body motion "
                                 "of the interior"));
  }
  s.factor_s = Seconds(t0);
  t0 = Clock::now();
  out.constraint_modes = Eigen::MatrixXd::Zero(ni, nb);
  if (ni > 0 && nb > 0) {
    kfac.Solve(Eigen::MatrixXd(kb.ib), out.constraint_modes);
    out.constraint_modes = -out.constraint_modes;
  }
  s.constraint_modes_s = Seconds(t0);

  // ---- 4. Fixed-interface modes (M_ii may be only positive semi-definite), mass-normalised.
  t0 = Clock::now();
  reduction_detail::InteriorModes modes =
      reduction_detail::ComputeInteriorModes(kb.ii, mb.ii, &kfac, options);
  s.factor_s += modes.factor_s;
  s.dense_eigensolver = modes.dense;
  s.eigen_batches = modes.batches;
  s.eigen_restarts = modes.restarts;
  s.operator_applications = modes.applications;
  if (modes.status != CraigBamptonStatus::kSuccess) {
    s.eigen_s = Seconds(t0);
    return finish(modes.status, modes.message);
  }
  const int nq = static_cast<int>(modes.lambda.size());
  const Eigen::MatrixXd mii_phi = MassNormalise(mb.ii, &modes.phi);
  s.eigen_s = Seconds(t0);
  s.modes = nq;
  out.modal_frequencies_hz.resize(nq);
  for (int j = 0; j < nq; ++j) {
    out.modal_frequencies_hz(j) = HzFromEigenvalue(modes.lambda(j));
    s.frequencies_hz.push_back(out.modal_frequencies_hz(j));
  }
  out.normal_modes = std::move(modes.phi);

  // ---- 5. Reduced matrices and their checks; any non-finite value fails the run.
  t0 = Clock::now();
  const Eigen::MatrixXd kii_phi = SparseTimesDense(kb.ii, out.normal_modes);
  CraigBamptonChecks& ch = s.checks;
  Assemble(kb, mb, modes.lambda, kii_phi, mii_phi, MaxAbs(stiffness), &out, &ch);
  if (nq > 0) {
    ch.modal_stiffness /=
        std::max({modes.lambda.cwiseAbs().maxCoeff(), std::abs(options.shift), 1e-300});
  }
  ch.eigen_residual = EigenResidual(kb, mb, modes.lambda, out.normal_modes, kii_phi, mii_phi);
  s.assembly_s = Seconds(t0);
  const std::string& note = modes.message;
  if (!out.stiffness.allFinite() || !out.mass.allFinite()) {
    return finish(CraigBamptonStatus::kChecksFailed,
                  "the reduced K or M holds non-finite values (singular interior or mass?)");
  }
  if (!(ch.Max() <= options.check_tolerance)) {  // NaN fails too
    char buf[128];
    std::snprintf(buf, sizeof buf, "structural check %.3e exceeds check_tolerance %.1e", ch.Max(),
                  options.check_tolerance);
    return finish(CraigBamptonStatus::kChecksFailed, note.empty() ? buf : note + "; " + buf);
  }
  return finish(CraigBamptonStatus::kSuccess, note);
}

}  // namespace fricrom
