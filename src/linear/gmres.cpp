#include "linear/gmres.h"

#include <cmath>
#include <stdexcept>

namespace fricrom::dense {

GmresResult PreconditionedGmres(const Eigen::MatrixXd& a, bool transpose_a, const Lu& m,
                                bool transpose_m, const Eigen::VectorXd& b, double tolerance,
                                int max_iterations, Eigen::VectorXd* x) {
  if (a.rows() != a.cols() || a.rows() != b.size()) {
    throw std::invalid_argument("PreconditionedGmres: inconsistent sizes or arguments");
  }
  const LinearMap apply = [&a, transpose_a](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
    if (transpose_a) {
      out->noalias() = a.transpose() * v;
    } else {
      out->noalias() = a * v;
    }
  };
  return PreconditionedGmres(apply, m, transpose_m, b, tolerance, max_iterations, x);
}

GmresResult PreconditionedGmres(const LinearMap& apply, const Lu& m, bool transpose_m,
                                const Eigen::VectorXd& b, double tolerance, int max_iterations,
                                Eigen::VectorXd* x) {
  const Eigen::Index n = b.size();
  if (m.rows() != n || x == nullptr || max_iterations < 1) {
    throw std::invalid_argument("PreconditionedGmres: inconsistent sizes or arguments");
  }
  GmresResult result;
  x->setZero(n);
  const double beta = b.norm();
  if (!std::isfinite(beta)) return result;
  if (beta == 0.0) {
    result.converged = true;
    result.relative_residual = 0.0;
    return result;
  }
  const int k_max = static_cast<int>(std::min<Eigen::Index>(max_iterations, n));
  Eigen::MatrixXd v(n, k_max + 1), z(n, k_max);  // Arnoldi basis; M⁻¹ of its columns
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(k_max + 1, k_max);
  Eigen::VectorXd cs(k_max), sn(k_max), g = Eigen::VectorXd::Zero(k_max + 1);
  v.col(0) = b / beta;
  g[0] = beta;
  int k = 0;
  Eigen::VectorXd w(n);
  while (k < k_max) {
    z.col(k) = m.Solve(Eigen::VectorXd(v.col(k)), transpose_m);
    apply(z.col(k), &w);
    if (w.size() != n) throw std::invalid_argument("PreconditionedGmres: product of wrong size");
    for (int i = 0; i <= k; ++i) {  // modified Gram-Schmidt
      h(i, k) = v.col(i).dot(w);
      w -= h(i, k) * v.col(i);
    }
    h(k + 1, k) = w.norm();
    const bool breakdown = !(h(k + 1, k) > 1e-14 * beta);
    if (!breakdown) v.col(k + 1) = w / h(k + 1, k);
    for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
      const double t = cs[i] * h(i, k) + sn[i] * h(i + 1, k);
      h(i + 1, k) = -sn[i] * h(i, k) + cs[i] * h(i + 1, k);
      h(i, k) = t;
    }
    const double r = std::hypot(h(k, k), h(k + 1, k));
    if (!(r > 0.0) || !std::isfinite(r)) break;  // singular preconditioned operator
    cs[k] = h(k, k) / r;
    sn[k] = h(k + 1, k) / r;
    h(k, k) = r;
    h(k + 1, k) = 0.0;
    g[k + 1] = -sn[k] * g[k];
    g[k] *= cs[k];
    ++k;
    result.relative_residual = std::abs(g[k]) / beta;
    if (result.relative_residual <= tolerance || breakdown) break;
  }
  result.iterations = k;
  if (k == 0) return result;
  const Eigen::VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  *x = z.leftCols(k) * y;
  result.converged = result.relative_residual <= tolerance && x->allFinite();
  return result;
}

}  // namespace fricrom::dense
