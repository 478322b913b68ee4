// dense::Lu (dense_lapack.h): LAPACK's LU of what remains after columns that are unit outside a
// few rows are eliminated exactly.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "linear/dense_lapack.h"

// Fortran LAPACK/BLAS entry points: every argument by pointer, then gfortran's hidden lengths of
// the character arguments.
extern "C" {
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a,
            const int* lda, const float* x, const int* incx, const float* beta, float* y,
            const int* incy, std::size_t);
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t);
void dgecon_(const char* norm, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info, std::size_t);
void sgetrf_(const int* m, const int* n, float* a, const int* lda, int* ipiv, int* info);
void sgetrs_(const char* trans, const int* n, const int* nrhs, const float* a, const int* lda,
             const int* ipiv, float* b, const int* ldb, int* info, std::size_t);
void sgetri_(const int* n, float* a, const int* lda, const int* ipiv, float* work, const int* lwork,
             int* info);
void sgecon_(const char* norm, const int* n, const float* a, const int* lda, const float* anorm,
             float* rcond, float* work, int* iwork, int* info, std::size_t);
void dlacn2_(const int* n, double* v, double* x, int* isgn, double* est, int* kase, int* isave);
}

namespace fricrom::dense {
namespace {

// Lu::LazyInverse: the solves after which a single-precision factorisation is inverted, and the
// smallest active part worth it. At 525 unknowns sgetri costs 1.6 sgetrf and a solve by sgemv
// is 2-4x faster than sgetrs (AMD EPYC, OpenBLAS 0.3.21): the inversion pays back after a few
// hundred solves, which a GMRES preconditioner of the bound runs serves (48: not tuned).
constexpr int kInverseAfter = 48;
constexpr int kInverseMinSize = 256;

}  // namespace

void Lu::Compute(const Eigen::MatrixXd& a, LuPrecision precision) { Factor(a, false, precision); }

void Lu::ComputeTransposed(const Eigen::MatrixXd& a, LuPrecision precision) {
  Factor(a, true, precision);
}

void Lu::Factor(const Eigen::MatrixXd& a, bool transposed, LuPrecision precision) {
  if (a.rows() != a.cols()) throw std::invalid_argument("dense::Lu: matrix is not square");
  n_ = a.rows();
  lapack_ = n_ >= kLapackMinSize && FitsInt(n_);
  transposed_ = false;
  single_ = false;
  inverse_.reset();
  if (!lapack_) {
    if (transposed) {
      eigen_.compute(a.transpose());
    } else {
      eigen_.compute(a);
    }
    rcond_ = n_ == 0 ? 0.0 : eigen_.rcond();
    if (!(rcond_ >= 0.0)) rcond_ = 0.0;  // NaN from an exactly zero pivot
    return;
  }
  transposed_ = transposed;  // a itself is factorised; solves swap the transposition
  SplitColumns(a);
  const double anorm = a.cwiseAbs().colwise().sum().maxCoeff();
  rcond_ = 0.0;
  if (!std::isfinite(anorm)) return;
  Gather(a);
  constexpr float kFloatMax = std::numeric_limits<float>::max();
  const auto fits_float = [](const Eigen::MatrixXd& m) {
    return m.size() == 0 || m.cwiseAbs().maxCoeff() < 0.5 * kFloatMax;
  };
  single_ = precision == LuPrecision::kSingle && !active_.empty() && fits_float(factors_) &&
            fits_float(coupling_) && fits_float(fill_);
  if (single_) {
    coupling_single_ = coupling_.cast<float>();
    fill_single_ = fill_.cast<float>();
    coupling_.resize(0, 0);
    fill_.resize(0, 0);
  } else {
    coupling_single_.resize(0, 0);
    fill_single_.resize(0, 0);
  }
  double rcond_active = 1.0;
  if (!active_.empty() && !FactorActive(unit_.empty(), &rcond_active)) return;
  // With eliminated columns the factors' estimate is not the whole matrix's: LAPACK's estimator
  // runs over the whole solve instead (about as many solves as getcon's).
  rcond_ = unit_.empty() ? rcond_active : EstimateRcond(anorm);
}

void Lu::SplitColumns(const Eigen::MatrixXd& a) {
  active_.clear();
  unit_.clear();
  fill_rows_.clear();
  fill_pos_.clear();
  // Candidates: a finite non-zero pivot and at most half of the rest of the column non-zero.
  const Eigen::Index limit = n_ / 2;
  std::vector<char> candidate(static_cast<std::size_t>(n_), 0);
  std::vector<char> touched(static_cast<std::size_t>(n_), 0);
  std::vector<char> unit_only(static_cast<std::size_t>(n_), 0);
  // The candidates' off-diagonal non-zero rows, column after column (one scan of the matrix).
  std::vector<Eigen::Index> nz;
  std::vector<std::size_t> nz_begin(static_cast<std::size_t>(n_) + 1, 0);
  for (Eigen::Index c = 0; c < n_; ++c) {
    nz_begin[c] = nz.size();
    const double d = a(c, c);
    if (!(d != 0.0 && std::isfinite(d))) continue;
    const double* col = a.col(c).data();
    bool sparse = true;
    for (Eigen::Index r = 0; r < n_ && sparse; ++r) {
      if (r == c || col[r] == 0.0) continue;
      nz.push_back(r);
      sparse = static_cast<Eigen::Index>(nz.size() - nz_begin[c]) <= limit;
    }
    if (!sparse) nz.resize(nz_begin[c]);
    candidate[c] = sparse;
    unit_only[c] = sparse && nz.size() == nz_begin[c];
  }
  nz_begin[n_] = nz.size();
  const auto rows_of = [&](Eigen::Index c) {
    return std::pair(nz.begin() + static_cast<std::ptrdiff_t>(nz_begin[c]),
                     nz.begin() + static_cast<std::ptrdiff_t>(nz_begin[c + 1]));
  };
  const auto count = [&](Eigen::Index c) {
    return static_cast<Eigen::Index>(nz_begin[c + 1] - nz_begin[c]);
  };
  // S: the candidates with at most `most` entries that no such candidate touches, so a(S, S) is
  // diagonal. Where the other columns are sparse too (banded models) they touch the sparsest
  // ones, so the bound halves from n/2 while that splits off more columns.
  const auto split_at = [&](Eigen::Index most) {
    std::fill(touched.begin(), touched.end(), 0);
    for (Eigen::Index c = 0; c < n_; ++c) {
      if (count(c) > most) continue;
      const auto [first, last] = rows_of(c);
      for (auto r = first; r != last; ++r) touched[*r] = 1;
    }
    Eigen::Index ns = 0;
    for (Eigen::Index c = 0; c < n_; ++c) ns += candidate[c] && count(c) <= most && !touched[c];
    return ns;
  };
  Eigen::Index best = limit, ns = split_at(limit);
  for (Eigen::Index most = limit / 2; most >= 1; most /= 2) {
    const Eigen::Index tried = split_at(most);
    if (tried > ns) {
      best = most;
      ns = tried;
    }
  }
  split_at(best);
  for (Eigen::Index c = 0; c < n_; ++c) candidate[c] = candidate[c] && count(c) <= best;
  // The update S needs (2|M||S||R| flops) must cost less than the LU it saves ((2/3)(n³ − |R|³));
  // else only exactly unit columns are split off.
  Eigen::Index ns_unit = 0;
  for (Eigen::Index c = 0; c < n_; ++c) ns_unit += unit_only[c];
  std::vector<char> fill(static_cast<std::size_t>(n_), 0);
  Eigen::Index nm = 0;
  for (Eigen::Index c = 0; c < n_; ++c) {
    if (!candidate[c] || touched[c]) continue;
    const auto [first, last] = rows_of(c);
    for (auto r = first; r != last; ++r) fill[*r] = 1;
  }
  for (Eigen::Index r = 0; r < n_; ++r) nm += fill[r];
  const double dn = static_cast<double>(n_), ds = static_cast<double>(ns);
  const double dr = dn - ds;
  const bool schur = ns > ns_unit && 2.0 * static_cast<double>(nm) * ds * dr <
                                         (2.0 / 3.0) * (dn * dn * dn - dr * dr * dr);
  for (Eigen::Index c = 0; c < n_; ++c) {
    const bool in_s = schur ? candidate[c] && !touched[c] : unit_only[c] != 0;
    if (in_s) {
      unit_.push_back(c);
      continue;
    }
    if (schur && fill[c]) {
      fill_rows_.push_back(c);
      fill_pos_.push_back(static_cast<Eigen::Index>(active_.size()));
    }
    active_.push_back(c);
  }
}

void Lu::Gather(const Eigen::MatrixXd& a) {
  const auto na = static_cast<Eigen::Index>(active_.size());
  const auto ns = static_cast<Eigen::Index>(unit_.size());
  const auto nm = static_cast<Eigen::Index>(fill_rows_.size());
  unit_diag_.resize(ns);
  for (Eigen::Index k = 0; k < ns; ++k) unit_diag_[k] = a(unit_[k], unit_[k]);
  fill_.resize(nm, ns);
  if (unit_.empty()) {
    factors_ = a;
    coupling_.resize(0, 0);
    coupling_cols_.clear();
    return;
  }
  // a(S, R) keeps its non-zero columns only (with the condensed balance, the mean unknowns of the
  // stuck contacts leave ~40 % of them exactly zero: its products move less memory).
  coupling_cols_.clear();
  for (Eigen::Index k = 0; k < na; ++k) {
    const auto col = a.col(active_[k]);
    for (Eigen::Index i = 0; i < ns; ++i) {
      if (col[unit_[i]] != 0.0) {
        coupling_cols_.push_back(k);
        break;
      }
    }
  }
  const auto nk = static_cast<Eigen::Index>(coupling_cols_.size());
  factors_.resize(na, na);
  coupling_.resize(ns, nk);
  for (Eigen::Index k = 0; k < na; ++k) {  // column by column: contiguous reads
    const auto col = a.col(active_[k]);
    for (Eigen::Index i = 0; i < na; ++i) factors_(i, k) = col[active_[i]];
  }
  for (Eigen::Index k = 0; k < nk; ++k) {
    const auto col = a.col(active_[coupling_cols_[k]]);
    for (Eigen::Index i = 0; i < ns; ++i) coupling_(i, k) = col[unit_[i]];
  }
  if (nm == 0) return;
  for (Eigen::Index k = 0; k < ns; ++k) {
    const auto col = a.col(unit_[k]);
    for (Eigen::Index i = 0; i < nm; ++i) fill_(i, k) = col[fill_rows_[i]] / unit_diag_[k];
  }
  // The Schur complement differs from a(R, R) in the rows M only.
  const Eigen::MatrixXd update = Product(fill_, false, coupling_, false);
  for (Eigen::Index k = 0; k < nk; ++k) {
    for (Eigen::Index i = 0; i < nm; ++i) factors_(fill_pos_[i], coupling_cols_[k]) -= update(i, k);
  }
}

bool Lu::FactorActive(bool estimate, double* rcond_active) {
  const int n = static_cast<int>(factors_.rows());
  pivots_.assign(static_cast<std::size_t>(n), 0);
  int info = 0;
  const double active_norm = estimate ? factors_.cwiseAbs().colwise().sum().maxCoeff() : 0.0;
  std::vector<int> iwork(estimate ? static_cast<std::size_t>(n) : 0);
  if (single_) {
    factors_single_ = factors_.cast<float>();
    factors_.resize(0, 0);
    sgetrf_(&n, &n, factors_single_.data(), &n, pivots_.data(), &info);
    if (info < 0) throw std::logic_error("dense::Lu: sgetrf rejected an argument");
    if (info > 0) return false;  // exactly singular: rcond 0
    if (n >= kInverseMinSize) inverse_ = std::make_shared<LazyInverse>();
    if (!estimate) return true;
    std::vector<float> work(4 * static_cast<std::size_t>(n));
    const auto norm = static_cast<float>(active_norm);
    float rcond = 0.0F;
    sgecon_("1", &n, factors_single_.data(), &n, &norm, &rcond, work.data(), iwork.data(), &info,
            1);
    *rcond_active = rcond;
    return info == 0 && std::isfinite(rcond);
  }
  factors_single_.resize(0, 0);
  dgetrf_(&n, &n, factors_.data(), &n, pivots_.data(), &info);
  if (info < 0) throw std::logic_error("dense::Lu: dgetrf rejected an argument");
  if (info > 0) return false;
  if (!estimate) return true;
  std::vector<double> work(4 * static_cast<std::size_t>(n));
  dgecon_("1", &n, factors_.data(), &n, &active_norm, rcond_active, work.data(), iwork.data(),
          &info, 1);
  return info == 0 && std::isfinite(*rcond_active);
}

// 1 / (‖A‖₁ ‖A⁻¹‖₁) with ‖A⁻¹‖₁ from dlacn2 (Higham's estimator, what getcon uses), by solves.
double Lu::EstimateRcond(double anorm) const {
  if (n_ == 0 || !(anorm > 0.0)) return 0.0;
  const int n = static_cast<int>(n_);
  Eigen::VectorXd v(n_), x(n_);
  std::vector<int> isgn(static_cast<std::size_t>(n_));
  std::array<int, 3> isave{};
  double est = 0.0;
  int kase = 0;
  do {
    dlacn2_(&n, v.data(), x.data(), isgn.data(), &est, &kase, isave.data());
    if (kase != 0) x = SolveFactored(x, kase == 2);
  } while (kase != 0);
  const double rcond = 1.0 / (anorm * est);
  return std::isfinite(rcond) && rcond >= 0.0 ? rcond : 0.0;
}

const Eigen::MatrixXf* Lu::ActiveInverse() const {
  if (!inverse_) return nullptr;
  LazyInverse& lazy = *inverse_;
  if (lazy.ready.load(std::memory_order_acquire)) return &lazy.inverse;
  if (lazy.solves.fetch_add(1, std::memory_order_relaxed) + 1 < kInverseAfter) return nullptr;
  const std::lock_guard<std::mutex> lock(lazy.mutex);
  if (lazy.ready.load(std::memory_order_acquire)) return &lazy.inverse;
  if (lazy.failed) return nullptr;
  const int n = static_cast<int>(factors_single_.rows());
  Eigen::MatrixXf inverse = factors_single_;
  int info = 0, lwork = -1;
  float query = 0.0F;
  sgetri_(&n, inverse.data(), &n, pivots_.data(), &query, &lwork, &info);
  lwork = std::max(n, static_cast<int>(query));
  std::vector<float> work(static_cast<std::size_t>(lwork));
  if (info == 0) sgetri_(&n, inverse.data(), &n, pivots_.data(), work.data(), &lwork, &info);
  if (info != 0 || !inverse.allFinite()) {
    lazy.failed = true;
    return nullptr;
  }
  lazy.inverse = std::move(inverse);
  lazy.ready.store(true, std::memory_order_release);
  return &lazy.inverse;
}

Eigen::MatrixXd Lu::SolveActive(Eigen::MatrixXd b, bool transposed) const {
  if (b.rows() == 0 || b.cols() == 0) return b;
  if (!FitsInt(b.cols())) throw std::invalid_argument("dense::Lu::Solve: too many columns");
  const int n = static_cast<int>(b.rows()), nrhs = static_cast<int>(b.cols());
  int info = 0;
  if (single_) {
    if (const Eigen::MatrixXf* inverse = ActiveInverse(); inverse != nullptr) {
      Eigen::MatrixXf out(n, nrhs);
      const Eigen::MatrixXf bf = b.cast<float>();
      if (nrhs == 1) {
        const int one = 1;
        const float unit = 1.0F, zero = 0.0F;
        sgemv_(transposed ? "T" : "N", &n, &n, &unit, inverse->data(), &n, bf.data(), &one, &zero,
               out.data(), &one, 1);
      } else if (transposed) {
        out.noalias() = inverse->transpose() * bf;
      } else {
        out.noalias() = *inverse * bf;
      }
      return out.cast<double>();
    }
    Eigen::MatrixXf bs = b.cast<float>();
    sgetrs_(transposed ? "T" : "N", &n, &nrhs, factors_single_.data(), &n, pivots_.data(),
            bs.data(), &n, &info, 1);
    if (info != 0) throw std::logic_error("dense::Lu: sgetrs rejected an argument");
    return bs.cast<double>();
  }
  dgetrs_(transposed ? "T" : "N", &n, &nrhs, factors_.data(), &n, pivots_.data(), b.data(), &n,
          &info, 1);
  if (info != 0) throw std::logic_error("dense::Lu: dgetrs rejected an argument");
  return b;
}

Eigen::MatrixXd Lu::BlockTimes(bool fill, const Eigen::MatrixXd& v, bool transposed) const {
  if (!single_) return Product(fill ? fill_ : coupling_, transposed, v, false);
  const Eigen::MatrixXf& block = fill ? fill_single_ : coupling_single_;
  if (v.cols() != 1) {
    const Eigen::MatrixXf vs = v.cast<float>();
    if (transposed) return (block.transpose() * vs).cast<double>();
    return (block * vs).cast<double>();
  }
  const int m = static_cast<int>(block.rows());
  const int n = static_cast<int>(block.cols()), one_i = 1;
  const Eigen::VectorXf vs = v.col(0).cast<float>();
  Eigen::VectorXf out(transposed ? n : m);
  const float one = 1.0F, zero = 0.0F;
  if (m > 0 && n > 0) {
    sgemv_(transposed ? "T" : "N", &m, &n, &one, block.data(), &m, vs.data(), &one_i, &zero,
           out.data(), &one_i, 1);
  } else {
    out.setZero();
  }
  return out.cast<double>();
}

Eigen::MatrixXd Lu::SolveFactored(const Eigen::MatrixXd& b, bool t) const {
  if (unit_.empty()) return SolveActive(b, t);
  const Eigen::VectorXd inverse = unit_diag_.cwiseInverse();
  Eigen::MatrixXd x(n_, b.cols());
  if (!t) {  // x_R from the Schur complement, then x_S = (b_S − a_SR x_R) / d
    Eigen::MatrixXd br = b(active_, Eigen::all);
    const Eigen::MatrixXd bs = b(unit_, Eigen::all);
    if (!fill_rows_.empty()) {
      br(fill_pos_, Eigen::all) -= BlockTimes(true, bs, false);  // a_MS d⁻¹ b_S
    }
    const Eigen::MatrixXd xa = SolveActive(std::move(br), false);
    x(active_, Eigen::all) = xa;
    x(unit_, Eigen::all) =
        inverse.asDiagonal() * (bs - BlockTimes(false, xa(coupling_cols_, Eigen::all), false));
  } else {  // u = c_S / d, y_R = Schur⁻ᵀ (c_R − a_SRᵀ u), y_S = u − (a_MS / d)ᵀ y_M
    const Eigen::MatrixXd u = inverse.asDiagonal() * b(unit_, Eigen::all);
    Eigen::MatrixXd ca = b(active_, Eigen::all);
    ca(coupling_cols_, Eigen::all) -= BlockTimes(false, u, true);
    const Eigen::MatrixXd ya = SolveActive(std::move(ca), true);
    x(active_, Eigen::all) = ya;
    x(unit_, Eigen::all) = u;
    if (!fill_rows_.empty()) {
      x(unit_, Eigen::all) -= BlockTimes(true, ya(fill_pos_, Eigen::all), true);
    }
  }
  return x;
}

Eigen::MatrixXd Lu::Solve(const Eigen::MatrixXd& b, bool transposed) const {
  if (b.rows() != n_) throw std::invalid_argument("dense::Lu::Solve: right-hand side size");
  if (!lapack_) {
    if (transposed) return eigen_.transpose().solve(b);
    return eigen_.solve(b);
  }
  return SolveFactored(b, transposed != transposed_);  // with respect to the factorised matrix
}

Eigen::VectorXd Lu::Solve(const Eigen::VectorXd& b, bool transposed) const {
  if (!lapack_ && b.size() == n_) {  // Eigen's vector kernels: bit-identical to before
    if (transposed) return eigen_.transpose().solve(b);
    return eigen_.solve(b);
  }
  return Solve(Eigen::MatrixXd(b), transposed);
}

}  // namespace fricrom::dense
