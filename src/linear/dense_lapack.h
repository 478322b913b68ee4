// Private: dense kernels through the system BLAS/LAPACK (OpenBLAS at run time in our setup).
// Why: Eigen's portable kernels are built for the baseline x86-64 ISA (no -march), while
// OpenBLAS dispatches to the CPU's vector units and threads: on the 2-core CI machine dgetrf is
// 2.2x Eigen's PartialPivLU at n = 603 and 4x at 1407, dsygvd 3.7-7.5x the generalised
// eigensolver (benchmarks/README.md). Small systems (the lumped model) keep Eigen's routines
// bit for bit, so their results do not move.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace fricrom::dense {

// Below this size the Eigen routines are used (call overhead, and unchanged lumped results).
inline constexpr Eigen::Index kLapackMinSize = 96;

// op(a) op(b) with op = transpose where asked, through dgemm for large operands.
Eigen::MatrixXd Product(const Eigen::MatrixXd& a, bool transpose_a, const Eigen::MatrixXd& b,
                        bool transpose_b);

// LU with partial pivoting of a square matrix: dgetrf/dgecon/dgetrs, or Eigen below the size.
class Lu {
 public:
  Lu() = default;
  explicit Lu(const Eigen::MatrixXd& a) { Compute(a); }
  void Compute(const Eigen::MatrixXd& a);
  // Estimate of the reciprocal condition number in the 1-norm (0 when exactly singular).
  double rcond() const { return rcond_; }
  Eigen::Index rows() const { return n_; }
  // A⁻¹ b, or A⁻ᵀ b when `transposed`.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b, bool transposed = false) const;
  Eigen::VectorXd Solve(const Eigen::VectorXd& b, bool transposed = false) const;

 private:
  Eigen::Index n_ = 0;
  bool lapack_ = false;
  Eigen::MatrixXd factors_;
  std::vector<int> pivots_;
  Eigen::PartialPivLU<Eigen::MatrixXd> eigen_;
  double rcond_ = 0.0;
};

// K Φ = M Φ Λ for symmetric K and symmetric positive definite M (lower triangles read):
// eigenvalues ascending, Φ M-orthonormal. False if M is not positive definite or the solver fails.
bool SymmetricGeneralizedEigen(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                               Eigen::VectorXd* values, Eigen::MatrixXd* vectors);

}  // namespace fricrom::dense
