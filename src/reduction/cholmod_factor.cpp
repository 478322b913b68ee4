#include "cholmod_factor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#if __has_include(<suitesparse/cholmod.h>)
#include <suitesparse/cholmod.h>
#else
#include <cholmod.h>
#endif

namespace fricrom::reduction_detail {

struct CholmodFactor::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  cholmod_dense* x = nullptr;  // solve output and workspaces, reused between solves
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  cholmod_dense* h1 = nullptr;  // outputs of the two-step half solves
  cholmod_dense* h2 = nullptr;

  // One CHOLMOD solve of system `sys` for a single vector; the result is in *out.
  const double* Sys(int sys, const double* b, int n, cholmod_dense** out) {
    cholmod_dense view{};
    view.nrow = view.d = view.nzmax = static_cast<size_t>(n);
    view.ncol = 1;
    view.x = const_cast<double*>(b);  // read only
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    cholmod_solve2(sys, factor, &view, nullptr, out, nullptr, &y, &e, &common);
    return static_cast<const double*>((*out)->x);
  }

  Impl() {
    cholmod_start(&common);
    common.print = 0;  // the library is silent
    common.error_handler = nullptr;
    common.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Impl() {
    FreeWork();
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  void FreeWork() {
    if (x) cholmod_free_dense(&x, &common);
    if (y) cholmod_free_dense(&y, &common);
    if (e) cholmod_free_dense(&e, &common);
    if (h1) cholmod_free_dense(&h1, &common);
    if (h2) cholmod_free_dense(&h2, &common);
  }
};

CholmodFactor::CholmodFactor() : impl_(std::make_unique<Impl>()) {}
CholmodFactor::~CholmodFactor() = default;

bool CholmodFactor::Factorize(const Eigen::SparseMatrix<double>& a, std::string* error) {
  ok_ = false;
  n_ = static_cast<int>(a.rows());
  Impl& im = *impl_;
  if (im.factor) cholmod_free_factor(&im.factor, &im.common);
  im.FreeWork();

  Eigen::SparseMatrix<double> lower = a.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  cholmod_sparse view{};
  view.nrow = static_cast<size_t>(lower.rows());
  view.ncol = static_cast<size_t>(lower.cols());
  view.nzmax = static_cast<size_t>(lower.nonZeros());
  view.p = lower.outerIndexPtr();
  view.i = lower.innerIndexPtr();
  view.nz = nullptr;
  view.x = lower.valuePtr();
  view.z = nullptr;
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;

  if (n_ == 0) {
    ok_ = true;
    return true;
  }
  im.factor = cholmod_analyze(&view, &im.common);
  if (!im.factor || im.common.status < CHOLMOD_OK) {
    if (error) *error = "CHOLMOD analyse failed (status " + std::to_string(im.common.status) + ")";
    return false;
  }
  const int ok = cholmod_factorize(&view, im.factor, &im.common);
  if (!ok || im.common.status == CHOLMOD_NOT_POSDEF || im.factor->minor < im.factor->n) {
    if (error) {
      if (im.common.status == CHOLMOD_NOT_POSDEF || im.factor->minor < im.factor->n) {
        *error = "matrix not positive definite (CHOLMOD stopped at column " +
                 std::to_string(im.factor->minor) + " of " + std::to_string(n_) + ")";
      } else {
        *error = "CHOLMOD factorise failed (status " + std::to_string(im.common.status) + ")";
      }
    }
    return false;
  }
  // A singular positive semi-definite matrix (free-free body) often factorises with a roundoff
  // pivot instead of failing: reject a condition estimate (max/min diag L)^2 beyond 1 / (10 eps).
  const double rcond = cholmod_rcond(im.factor, &im.common);
  rcond_ = rcond;
  if (!(rcond * rcond > 10.0 * std::numeric_limits<double>::epsilon())) {
    if (error) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "matrix numerically singular, not positive definite (CHOLMOD rcond %.2e, "
                    "condition estimate %.2e)",
                    rcond, rcond > 0 ? 1.0 / (rcond * rcond) : HUGE_VAL);
      *error = buf;
    }
    return false;
  }
  ok_ = true;
  return true;
}

void CholmodFactor::Solve(const Eigen::Ref<const Eigen::MatrixXd>& b,
                          Eigen::Ref<Eigen::MatrixXd> x) {
  if (n_ == 0 || b.cols() == 0) return;
  Impl& im = *impl_;
  // Blocks of columns keep CHOLMOD's copies bounded for many right-hand sides.
  constexpr Eigen::Index kBlock = 64;
  Eigen::MatrixXd rhs;
  for (Eigen::Index c0 = 0; c0 < b.cols(); c0 += kBlock) {
    const Eigen::Index nc = std::min(kBlock, b.cols() - c0);
    rhs = b.middleCols(c0, nc);
    cholmod_dense bview{};
    bview.nrow = static_cast<size_t>(n_);
    bview.ncol = static_cast<size_t>(nc);
    bview.nzmax = static_cast<size_t>(n_) * static_cast<size_t>(nc);
    bview.d = static_cast<size_t>(n_);
    bview.x = rhs.data();
    bview.z = nullptr;
    bview.xtype = CHOLMOD_REAL;
    bview.dtype = CHOLMOD_DOUBLE;
    cholmod_solve2(CHOLMOD_A, im.factor, &bview, nullptr, &im.x, nullptr, &im.y, &im.e, &im.common);
    const double* xs = static_cast<const double*>(im.x->x);
    const size_t ld = im.x->d;
    for (Eigen::Index j = 0; j < nc; ++j) {
      x.col(c0 + j) = Eigen::Map<const Eigen::VectorXd>(xs + ld * static_cast<size_t>(j), n_);
    }
  }
}

void CholmodFactor::ForwardHalf(const double* b, double* y) {
  Impl& im = *impl_;
  const double* pb = im.Sys(CHOLMOD_P, b, n_, &im.h1);
  const double* r = im.Sys(CHOLMOD_L, pb, n_, &im.h2);
  std::copy(r, r + n_, y);
}

void CholmodFactor::BackwardHalf(const double* b, double* y) {
  Impl& im = *impl_;
  const double* lb = im.Sys(CHOLMOD_Lt, b, n_, &im.h1);
  const double* r = im.Sys(CHOLMOD_Pt, lb, n_, &im.h2);
  std::copy(r, r + n_, y);
}

bool CountEigenvaluesBelow(const Eigen::SparseMatrix<double>& k,
                           const Eigen::SparseMatrix<double>& m, double lambda, int* count,
                           std::string* error) {
  Eigen::SparseMatrix<double> lower =
      Eigen::SparseMatrix<double>(k - lambda * m).triangularView<Eigen::Lower>();
  lower.makeCompressed();
  if (lower.rows() == 0) {
    *count = 0;
    return true;
  }
  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<size_t>(lower.rows());
  view.nzmax = static_cast<size_t>(lower.nonZeros());
  view.p = lower.outerIndexPtr();
  view.i = lower.innerIndexPtr();
  view.x = lower.valuePtr();
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.error_handler = nullptr;
  common.supernodal = CHOLMOD_SIMPLICIAL;  // LDL^T: indefinite matrices factorise
  common.final_ll = 0;
  cholmod_factor* f = cholmod_analyze(&view, &common);
  bool ok = f != nullptr && common.status >= CHOLMOD_OK && cholmod_factorize(&view, f, &common) &&
            f->minor == f->n && !f->is_ll;
  if (ok) {
    // Simplicial LDL^T: the first entry of column j of L holds D(j, j).
    const int* colp = static_cast<const int*>(f->p);
    const double* x = static_cast<const double*>(f->x);
    int negative = 0;
    for (size_t j = 0; j < f->n; ++j) {
      const double d = x[colp[j]];
      if (!std::isfinite(d) || d == 0.0) ok = false;
      negative += d < 0.0 ? 1 : 0;
    }
    *count = negative;
  }
  if (!ok && error) {
    *error =
        "LDL^T of K - lambda M failed (zero pivot: lambda at an eigenvalue, or CHOLMOD status " +
        std::to_string(common.status) + ")";
  }
  if (f) cholmod_free_factor(&f, &common);
  cholmod_finish(&common);
  return ok;
}

bool CholeskyTransformOp::set_shift(double sigma, std::string* error) {
  sigma_ = sigma;
  external_ = nullptr;
  Eigen::SparseMatrix<double> a = k_ - sigma * m_;
  return own_.Factorize(a, error);
}

void CholeskyTransformOp::perform_op(const double* x, double* y) {
  ++applications_;
  const int n = rows();
  w_.resize(n);
  v_.resize(n);
  factor().BackwardHalf(x, w_.data());
  v_.noalias() = m_lower_.selfadjointView<Eigen::Lower>() * w_;
  factor().ForwardHalf(v_.data(), y);
}

Eigen::MatrixXd CholeskyTransformOp::ToModes(const Eigen::MatrixXd& y) {
  Eigen::MatrixXd phi(y.rows(), y.cols());
  for (Eigen::Index j = 0; j < y.cols(); ++j)
    factor().BackwardHalf(y.col(j).data(), phi.col(j).data());
  return phi;
}

}  // namespace fricrom::reduction_detail
