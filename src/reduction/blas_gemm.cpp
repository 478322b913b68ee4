#include "blas_gemm.h"

#include <limits>
#include <stdexcept>

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n,
                       const int* k, const double* alpha, const double* a, const int* lda,
                       const double* b, const int* ldb, const double* beta, double* c,
                       const int* ldc);

namespace fricrom::reduction_detail {

Eigen::MatrixXd TransposeTimes(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows()) throw std::invalid_argument("TransposeTimes: row counts differ");
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(a.cols(), b.cols());
  constexpr Eigen::Index kIntMax = std::numeric_limits<int>::max();
  if (a.size() == 0 || b.size() == 0) return c;
  if (a.rows() > kIntMax || a.cols() > kIntMax || b.cols() > kIntMax) {
    c.noalias() = a.transpose() * b;  // beyond 32-bit BLAS indices
    return c;
  }
  const int m = static_cast<int>(a.cols()), n = static_cast<int>(b.cols());
  const int k = static_cast<int>(a.rows());
  const double one = 1.0, zero = 0.0;
  dgemm_("T", "N", &m, &n, &k, &one, a.data(), &k, b.data(), &k, &zero, c.data(), &m);
  return c;
}

}  // namespace fricrom::reduction_detail
