// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's SelfAdjointEigenSolver.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "dense_modes.h"

#include <algorithm>
#include <cmath>

namespace fricrom::reduction_detail {

bool DenseLowestModes(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m,
                      double sigma, int max_count, Eigen::VectorXd* lambda, Eigen::MatrixXd* phi,
                      std::string* error) {
  const Eigen::MatrixXd kd = Eigen::MatrixXd(k), md = Eigen::MatrixXd(m);
  Eigen::LLT<Eigen::MatrixXd> llt(kd - sigma * md);
  if (llt.info() != Eigen::Success) {
    if (error) *error = "K - shift * M not positive definite (dense Cholesky)";
    return false;
  }
  const auto l = llt.matrixL();
  Eigen::MatrixXd c = l.solve(md);
  c = l.solve(c.transpose()).eval();
  c = 0.5 * (c + c.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(c);
  if (es.info() != Eigen::Success) {
    if (error) *error = "dense symmetric eigensolver failed";
    return false;
  }
  const Eigen::VectorXd nu = es.eigenvalues();  // ascending nu = descending lambda
  const Eigen::Index n = nu.size();
  const double nu_max = n ? nu.maxCoeff() : 0.0;
  int finite = 0;
  for (Eigen::Index j = 0; j < n; ++j) finite += nu(j) > 1e-13 * nu_max ? 1 : 0;
  const int count = std::min(finite, max_count);
  lambda->resize(count);
  phi->resize(k.rows(), count);
  for (int j = 0; j < count; ++j) {
    const Eigen::Index src = n - 1 - j;
    (*lambda)(j) = sigma + 1.0 / nu(src);
    phi->col(j) = l.transpose().solve(es.eigenvectors().col(src)) / std::sqrt(nu(src));
  }
  return true;
}

}  // namespace fricrom::reduction_detail
