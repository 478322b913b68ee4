// Private to src/reduction: C = A^T B through the system BLAS (OpenBLAS when installed: its
// vectorised, threaded dgemm is ~10x Eigen's portable kernels for the tall products of the
// Craig-Bampton assembly, e.g. Psi^T (M_ii Psi) with 123k rows).
#pragma once

#include <Eigen/Dense>

namespace fricrom::reduction_detail {

// a: k x m, b: k x n (column-major, as Eigen stores them); returns a^T b (m x n).
Eigen::MatrixXd TransposeTimes(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace fricrom::reduction_detail
