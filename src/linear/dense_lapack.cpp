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
void dsymv_(const char* uplo, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy,
            std::size_t);
void zgemv_(const char* trans, const int* m, const int* n, const std::complex<double>* alpha,
            const std::complex<double>* a, const int* lda, const std::complex<double>* x,
            const int* incx, const std::complex<double>* beta, std::complex<double>* y,
            const int* incy, std::size_t);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc,
            std::size_t, std::size_t);
void dsygvd_(const int* itype, const char* jobz, const char* uplo, const int* n, double* a,
             const int* lda, double* b, const int* ldb, double* w, double* work, const int* lwork,
             int* iwork, const int* liwork, int* info, std::size_t, std::size_t);
}

namespace fricrom::dense {

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

void SymmetricMatVec(const Eigen::MatrixXd& a, const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  if (a.rows() != a.cols() || a.cols() != x.size()) {
    throw std::invalid_argument("dense::SymmetricMatVec: sizes differ");
  }
  y->resize(a.rows());
  if (a.rows() < kLapackMinSize || !FitsInt(a.rows())) {
    y->noalias() = a.selfadjointView<Eigen::Upper>() * x;
    return;
  }
  const int n = static_cast<int>(a.rows()), one_i = 1;
  const double one = 1.0, zero = 0.0;
  dsymv_("U", &n, &one, a.data(), &n, x.data(), &one_i, &zero, y->data(), &one_i, 1);
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
  if (n <= 2 && !transpose_b) {
    // One or two columns: a dgemv per column streams a, where dgemm would first pack it (the
    // Schur-complement blocks of a double LU's solves, 3 % of an FE bound curve, and the modal
    // receptance's products through W: 1.6x faster at 324 x 862 with two columns).
    const int ar = static_cast<int>(a.rows()), ac = static_cast<int>(a.cols()), one_i = 1;
    const double one = 1.0, zero = 0.0;
    for (Eigen::Index j = 0; j < n; ++j) {
      dgemv_(transpose_a ? "T" : "N", &ar, &ac, &one, a.data(), &ar, b.col(j).data(), &one_i, &zero,
             c.col(j).data(), &one_i, 1);
    }
    return c;
  }
  const int im = static_cast<int>(m), in = static_cast<int>(n), ik = static_cast<int>(k);
  const int lda = static_cast<int>(a.rows()), ldb = static_cast<int>(b.rows());
  const double one = 1.0, zero = 0.0;
  dgemm_(transpose_a ? "T" : "N", transpose_b ? "T" : "N", &im, &in, &ik, &one, a.data(), &lda,
         b.data(), &ldb, &zero, c.data(), &im, 1, 1);
  return c;
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
