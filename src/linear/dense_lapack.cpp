#include "linear/dense_lapack.h"

#include <dlfcn.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
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
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t);
void dgecon_(const char* norm, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info, std::size_t);
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

void Lu::Compute(const Eigen::MatrixXd& a) { Factor(a, false); }

void Lu::ComputeTransposed(const Eigen::MatrixXd& a) { Factor(a, true); }

void Lu::Factor(const Eigen::MatrixXd& a, bool transposed) {
  if (a.rows() != a.cols()) throw std::invalid_argument("dense::Lu: matrix is not square");
  n_ = a.rows();
  lapack_ = n_ >= kLapackMinSize && FitsInt(n_);
  transposed_ = false;
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
  } else {
    factors_.resize(na, na);
    coupling_.resize(static_cast<Eigen::Index>(unit_.size()), na);
    for (Eigen::Index k = 0; k < na; ++k) {  // column by column: contiguous reads
      const auto col = a.col(active_[k]);
      for (Eigen::Index i = 0; i < na; ++i) factors_(i, k) = col[active_[i]];
      for (std::size_t i = 0; i < unit_.size(); ++i) coupling_(i, k) = col[unit_[i]];
    }
  }
  double rcond_active = 1.0;
  if (na > 0) {
    pivots_.assign(static_cast<std::size_t>(na), 0);
    const int n = static_cast<int>(na);
    int info = 0;
    const double active_norm = factors_.cwiseAbs().colwise().sum().maxCoeff();
    dgetrf_(&n, &n, factors_.data(), &n, pivots_.data(), &info);
    if (info < 0) throw std::logic_error("dense::Lu: dgetrf rejected an argument");
    if (info > 0) return;  // exactly singular: rcond 0
    std::vector<double> work(4 * static_cast<std::size_t>(n));
    std::vector<int> iwork(static_cast<std::size_t>(n));
    dgecon_("1", &n, factors_.data(), &n, &active_norm, &rcond_active, work.data(), iwork.data(),
            &info, 1);
    if (info != 0 || !std::isfinite(rcond_active)) return;
  }
  // An estimate for the block-triangular whole: the worse of the active block and the unit
  // pivots relative to the matrix norm (a singularity guard, as the estimate of dgecon is).
  rcond_ = rcond_active;
  if (!unit_.empty()) rcond_ = std::min(rcond_, unit_diag_.cwiseAbs().minCoeff() / anorm);
}

Eigen::MatrixXd Lu::SolveActive(Eigen::MatrixXd b, bool transposed) const {
  if (b.rows() == 0 || b.cols() == 0) return b;
  if (!FitsInt(b.cols())) throw std::invalid_argument("dense::Lu::Solve: too many columns");
  const int n = static_cast<int>(b.rows()), nrhs = static_cast<int>(b.cols());
  int info = 0;
  dgetrs_(transposed ? "T" : "N", &n, &nrhs, factors_.data(), &n, pivots_.data(), b.data(), &n,
          &info, 1);
  if (info != 0) throw std::logic_error("dense::Lu: dgetrs rejected an argument");
  return b;
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
        unit_diag_.cwiseInverse().asDiagonal() * (b(unit_, Eigen::all) - coupling_ * xa);
  } else {  // y_T = c_T / d, y_A = a_AA⁻ᵀ (c_A − a_TAᵀ y_T)
    const Eigen::MatrixXd yt = unit_diag_.cwiseInverse().asDiagonal() * b(unit_, Eigen::all);
    x(unit_, Eigen::all) = yt;
    x(active_, Eigen::all) = SolveActive(b(active_, Eigen::all) - coupling_.transpose() * yt, true);
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
  return true;
}

}  // namespace fricrom
