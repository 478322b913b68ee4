#include "linear/dense_lapack.h"

#include <dlfcn.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "fricrom/blas_threads.h"

// Fortran BLAS/LAPACK entry points: every argument by pointer, then gfortran's hidden lengths of
// the character arguments (size_t since gfortran 8; passing them keeps tail calls inside LAPACK
// from reading stale stack slots).
extern "C" {
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy, std::size_t);
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a,
            const int* lda, const float* x, const int* incx, const float* beta, float* y,
            const int* incy, std::size_t);
void zgemv_(const char* trans, const int* m, const int* n, const std::complex<double>* alpha,
            const std::complex<double>* a, const int* lda, const std::complex<double>* x,
            const int* incx, const std::complex<double>* beta, std::complex<double>* y,
            const int* incy, std::size_t);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc,
            std::size_t, std::size_t);
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t);
void dgecon_(const char* norm, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info, std::size_t);
void sgetrf_(const int* m, const int* n, float* a, const int* lda, int* ipiv, int* info);
void sgetrs_(const char* trans, const int* n, const int* nrhs, const float* a, const int* lda,
             const int* ipiv, float* b, const int* ldb, int* info, std::size_t);
void sgecon_(const char* norm, const int* n, const float* a, const int* lda, const float* anorm,
             float* rcond, float* work, int* iwork, int* info, std::size_t);
void dsygvd_(const int* itype, const char* jobz, const char* uplo, const int* n, double* a,
             const int* lda, double* b, const int* ldb, double* w, double* work, const int* lwork,
             int* iwork, const int* liwork, int* info, std::size_t, std::size_t);
}

namespace fricrom::dense {
namespace {

constexpr Eigen::Index kIntMax = std::numeric_limits<int>::max();

bool FitsInt(Eigen::Index a, Eigen::Index b = 0, Eigen::Index c = 0) {
  return a <= kIntMax && b <= kIntMax && c <= kIntMax;
}

}  // namespace

Eigen::MatrixXd WeightedGram(const Eigen::MatrixXd& w, const Eigen::VectorXd& d) {
  if (w.cols() != d.size()) throw std::invalid_argument("dense::WeightedGram: sizes differ");
  const Eigen::Index n = w.rows();
  if (std::max(n, w.cols()) < kLapackMinSize || !FitsInt(n, w.cols())) {
    return Product(w * d.asDiagonal(), false, w, true);
  }
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  const int in = static_cast<int>(n);
  for (const double sign : {1.0, -1.0}) {
    std::vector<Eigen::Index> cols;
    for (Eigen::Index k = 0; k < d.size(); ++k) {
      if (sign * d[k] > 0.0) cols.push_back(k);
    }
    if (cols.empty()) continue;
    Eigen::MatrixXd p(n, static_cast<Eigen::Index>(cols.size()));
    for (size_t c = 0; c < cols.size(); ++c) {
      p.col(static_cast<Eigen::Index>(c)) = w.col(cols[c]) * std::sqrt(sign * d[cols[c]]);
    }
    const int k = static_cast<int>(p.cols());
    const double beta = 1.0;
    dsyrk_("L", "N", &in, &k, &sign, p.data(), &in, &beta, g.data(), &in, 1, 1);
  }
  g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
  return g;
}

namespace {

// y = op(a)·x, op = identity or the adjoint (the transpose for real a); BLAS gemv (`gemv`, dgemv_
// or zgemv_) on matrices large enough to gain from it, Eigen below that.
template <typename Scalar, typename Gemv>
void GemvOrEigen(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& a, bool adjoint,
                 const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x,
                 Eigen::Matrix<Scalar, Eigen::Dynamic, 1>* y, Gemv gemv) {
  if ((adjoint ? a.rows() : a.cols()) != x.size()) {
    throw std::invalid_argument("dense::MatVec: sizes differ");
  }
  y->resize(adjoint ? a.cols() : a.rows());
  if (std::max(a.rows(), a.cols()) < kLapackMinSize || !FitsInt(a.rows(), a.cols()) ||
      a.size() == 0) {
    if (adjoint) {
      y->noalias() = a.adjoint() * x;
    } else {
      y->noalias() = a * x;
    }
    return;
  }
  const int m = static_cast<int>(a.rows()), n = static_cast<int>(a.cols()), one_i = 1;
  const Scalar one = 1.0, zero = 0.0;
  gemv(adjoint ? "C" : "N", &m, &n, &one, a.data(), &m, x.data(), &one_i, &zero, y->data(), &one_i,
       1);
}

}  // namespace

void MatVec(const Eigen::MatrixXd& a, bool transpose, const Eigen::VectorXd& x,
            Eigen::VectorXd* y) {
  GemvOrEigen(a, transpose, x, y, dgemv_);  // "C" is the transpose for real BLAS
}

void MatVec(const Eigen::MatrixXcd& a, bool adjoint, const Eigen::VectorXcd& x,
            Eigen::VectorXcd* y) {
  GemvOrEigen(a, adjoint, x, y, zgemv_);
}

Eigen::MatrixXd Product(const Eigen::MatrixXd& a, bool transpose_a, const Eigen::MatrixXd& b,
                        bool transpose_b) {
  const Eigen::Index m = transpose_a ? a.cols() : a.rows(), k = transpose_a ? a.rows() : a.cols();
  const Eigen::Index kb = transpose_b ? b.cols() : b.rows(), n = transpose_b ? b.rows() : b.cols();
  if (k != kb) throw std::invalid_argument("dense::Product: inner dimensions differ");
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m, n);
  if (m == 0 || n == 0 || k == 0) return c;
  if (std::max({m, n, k}) < kLapackMinSize || !FitsInt(m, n, k) || !FitsInt(a.rows(), b.rows())) {
    if (transpose_a && transpose_b)
      c.noalias() = a.transpose() * b.transpose();
    else if (transpose_a)
      c.noalias() = a.transpose() * b;
    else if (transpose_b)
      c.noalias() = a * b.transpose();
    else
      c.noalias() = a * b;
    return c;
  }
  const int im = static_cast<int>(m), in = static_cast<int>(n), ik = static_cast<int>(k);
  const int lda = static_cast<int>(a.rows()), ldb = static_cast<int>(b.rows());
  const double one = 1.0, zero = 0.0;
  dgemm_(transpose_a ? "T" : "N", transpose_b ? "T" : "N", &im, &in, &ik, &one, a.data(), &lda,
         b.data(), &ldb, &zero, c.data(), &im, 1, 1);
  return c;
}

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
  // Unit columns: a(:, t) = d_t e_t. With T their set and A the rest, a(A, T) = 0, so
  // a x = b splits into a(A, A) x_A = b_A and x_T = (b_T − a(T, A) x_A) / d.
  active_.clear();
  unit_.clear();
  for (Eigen::Index c = 0; c < n_; ++c) {
    const double d = a(c, c);
    bool unit = d != 0.0 && std::isfinite(d);
    for (Eigen::Index r = 0; unit && r < n_; ++r) unit = r == c || a(r, c) == 0.0;  // early exit
    (unit ? unit_ : active_).push_back(c);
  }
  const double anorm = a.cwiseAbs().colwise().sum().maxCoeff();
  rcond_ = 0.0;
  if (!std::isfinite(anorm)) return;
  const auto na = static_cast<Eigen::Index>(active_.size());
  unit_diag_.resize(static_cast<Eigen::Index>(unit_.size()));
  for (std::size_t k = 0; k < unit_.size(); ++k) unit_diag_[k] = a(unit_[k], unit_[k]);
  if (unit_.empty()) {
    factors_ = a;
    coupling_.resize(0, na);
  } else {
    factors_.resize(na, na);
    coupling_.resize(static_cast<Eigen::Index>(unit_.size()), na);
    for (Eigen::Index k = 0; k < na; ++k) {  // column by column: contiguous reads
      const auto col = a.col(active_[k]);
      for (Eigen::Index i = 0; i < na; ++i) factors_(i, k) = col[active_[i]];
      for (std::size_t i = 0; i < unit_.size(); ++i) coupling_(i, k) = col[unit_[i]];
    }
  }
  single_ = precision == LuPrecision::kSingle && na > 0 &&
            factors_.cwiseAbs().maxCoeff() < 0.5 * std::numeric_limits<float>::max() &&
            (coupling_.size() == 0 ||
             coupling_.cwiseAbs().maxCoeff() < 0.5 * std::numeric_limits<float>::max());
  if (single_) {
    coupling_single_ = coupling_.cast<float>();
    coupling_.resize(0, 0);
  } else {
    coupling_single_.resize(0, 0);
  }
  double rcond_active = 1.0;
  if (na > 0 && !FactorActive(&rcond_active)) return;
  // An estimate for the block-triangular whole: the worse of the active block and the unit
  // pivots relative to the matrix norm (a singularity guard, as the estimate of dgecon is).
  rcond_ = rcond_active;
  if (!unit_.empty()) rcond_ = std::min(rcond_, unit_diag_.cwiseAbs().minCoeff() / anorm);
}

bool Lu::FactorActive(double* rcond_active) {
  const int n = static_cast<int>(factors_.rows());
  pivots_.assign(static_cast<std::size_t>(n), 0);
  int info = 0;
  const double active_norm = factors_.cwiseAbs().colwise().sum().maxCoeff();
  std::vector<int> iwork(static_cast<std::size_t>(n));
  if (single_) {
    factors_single_ = factors_.cast<float>();
    factors_.resize(0, 0);
    sgetrf_(&n, &n, factors_single_.data(), &n, pivots_.data(), &info);
    if (info < 0) throw std::logic_error("dense::Lu: sgetrf rejected an argument");
    if (info > 0) return false;  // exactly singular: rcond 0
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
  std::vector<double> work(4 * static_cast<std::size_t>(n));
  dgecon_("1", &n, factors_.data(), &n, &active_norm, rcond_active, work.data(), iwork.data(),
          &info, 1);
  return info == 0 && std::isfinite(*rcond_active);
}

Eigen::MatrixXd Lu::SolveActive(Eigen::MatrixXd b, bool transposed) const {
  if (b.rows() == 0 || b.cols() == 0) return b;
  if (!FitsInt(b.cols())) throw std::invalid_argument("dense::Lu::Solve: too many columns");
  const int n = static_cast<int>(b.rows()), nrhs = static_cast<int>(b.cols());
  int info = 0;
  if (single_) {
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

// a(T, A) v, or its transpose times v, in the factorisation's precision.
Eigen::MatrixXd Lu::CouplingTimes(const Eigen::MatrixXd& v, bool transposed) const {
  if (!single_) return Product(coupling_, transposed, v, false);
  if (v.cols() != 1) {
    const Eigen::MatrixXf vs = v.cast<float>();
    if (transposed) return (coupling_single_.transpose() * vs).cast<double>();
    return (coupling_single_ * vs).cast<double>();
  }
  const int m = static_cast<int>(coupling_single_.rows());
  const int n = static_cast<int>(coupling_single_.cols()), one_i = 1;
  const Eigen::VectorXf vs = v.col(0).cast<float>();
  Eigen::VectorXf out(transposed ? n : m);
  const float one = 1.0F, zero = 0.0F;
  if (m > 0 && n > 0) {
    sgemv_(transposed ? "T" : "N", &m, &n, &one, coupling_single_.data(), &m, vs.data(), &one_i,
           &zero, out.data(), &one_i, 1);
  } else {
    out.setZero();
  }
  return out.cast<double>();
}

Eigen::MatrixXd Lu::Solve(const Eigen::MatrixXd& b, bool transposed) const {
  if (b.rows() != n_) throw std::invalid_argument("dense::Lu::Solve: right-hand side size");
  if (!lapack_) {
    if (transposed) return eigen_.transpose().solve(b);
    return eigen_.solve(b);
  }
  const bool t = transposed != transposed_;  // with respect to the factorised matrix
  if (unit_.empty()) return SolveActive(b, t);
  Eigen::MatrixXd x(n_, b.cols());
  if (!t) {  // x_A = a_AA⁻¹ b_A, x_T = (b_T − a_TA x_A) / d
    const Eigen::MatrixXd xa = SolveActive(b(active_, Eigen::all), false);
    x(active_, Eigen::all) = xa;
    x(unit_, Eigen::all) =
        unit_diag_.cwiseInverse().asDiagonal() * (b(unit_, Eigen::all) - CouplingTimes(xa, false));
  } else {  // y_T = c_T / d, y_A = a_AA⁻ᵀ (c_A − a_TAᵀ y_T)
    const Eigen::MatrixXd yt = unit_diag_.cwiseInverse().asDiagonal() * b(unit_, Eigen::all);
    x(unit_, Eigen::all) = yt;
    x(active_, Eigen::all) = SolveActive(b(active_, Eigen::all) - CouplingTimes(yt, true), true);
  }
  return x;
}

Eigen::VectorXd Lu::Solve(const Eigen::VectorXd& b, bool transposed) const {
  if (!lapack_ && b.size() == n_) {  // Eigen's vector kernels: bit-identical to before
    if (transposed) return eigen_.transpose().solve(b);
    return eigen_.solve(b);
  }
  return Solve(Eigen::MatrixXd(b), transposed);
}

bool SymmetricGeneralizedEigen(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                               Eigen::VectorXd* values, Eigen::MatrixXd* vectors) {
  const Eigen::Index n = k.rows();
  if (k.cols() != n || m.rows() != n || m.cols() != n) {
    throw std::invalid_argument("dense::SymmetricGeneralizedEigen: sizes differ");
  }
  if (n < kLapackMinSize || !FitsInt(n)) {
    if (Eigen::LLT<Eigen::MatrixXd>(m).info() != Eigen::Success) return false;
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(k, m);
    if (es.info() != Eigen::Success) return false;
    *values = es.eigenvalues();
    *vectors = es.eigenvectors();
    return true;
  }
  Eigen::MatrixXd a = k, b = m;
  values->resize(n);
  const int in = static_cast<int>(n), itype = 1;
  int info = 0, lwork = -1, liwork = -1, iwork_query = 0;
  double work_query = 0.0;
  dsygvd_(&itype, "V", "L", &in, a.data(), &in, b.data(), &in, values->data(), &work_query, &lwork,
          &iwork_query, &liwork, &info, 1, 1);
  if (info != 0) return false;
  lwork = static_cast<int>(work_query);
  liwork = iwork_query;
  std::vector<double> work(static_cast<std::size_t>(lwork));
  std::vector<int> iwork(static_cast<std::size_t>(liwork));
  dsygvd_(&itype, "V", "L", &in, a.data(), &in, b.data(), &in, values->data(), work.data(), &lwork,
          iwork.data(), &liwork, &info, 1, 1);
  if (info != 0 || !values->allFinite()) return false;  // info > n: M not positive definite
  *vectors = std::move(a);
  return vectors->allFinite();
}

}  // namespace fricrom::dense

namespace fricrom {

bool SetBlasThreads(int threads) {
  if (threads < 1) throw std::invalid_argument("SetBlasThreads: threads must be >= 1");
  // OpenBLAS's control, looked up at run time: other BLAS libraries have none (or their own).
  using SetThreads = void (*)(int);
  void* symbol = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (symbol == nullptr) return false;
  reinterpret_cast<SetThreads>(symbol)(threads);
  if (threads == 1) {
    // OpenBLAS starts its worker pool when it loads, and each idle worker spins (sched_yield) for
    // about 0.1 s before it sleeps: CPU taken from our own threads or ranks (2 threads on the
    // lumped γ sweep: 0.752 → 0.707 s without it). One thread never needs the pool, so it is
    // stopped; OpenBLAS restarts it by itself if more threads are set later.
    using Shutdown = int (*)();
    void* stop = dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
    if (stop != nullptr) reinterpret_cast<Shutdown>(stop)();
  }
  return true;
}

}  // namespace fricrom
