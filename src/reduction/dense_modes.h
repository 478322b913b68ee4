// Private to src/reduction: all (or the lowest) eigenpairs of a small K phi = lambda M phi,
// densely, through the Cholesky factor of K - sigma M.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>

namespace fricrom::reduction_detail {

// The lowest min(max_count, finite) eigenpairs, ascending; phi M-orthonormal. K - sigma M = L L^T,
// eigen-decomposition of L^-1 M L^-T: nu, lambda = sigma + 1/nu, phi = L^-T y / sqrt(nu).
// Directions with nu ~ 0 (massless DOFs: infinite lambda) are dropped. False (with a message) if
// K - sigma M is not positive definite or the eigensolver fails.
bool DenseLowestModes(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m,
                      double sigma, int max_count, Eigen::VectorXd* lambda, Eigen::MatrixXd* phi,
                      std::string* error);

}  // namespace fricrom::reduction_detail
