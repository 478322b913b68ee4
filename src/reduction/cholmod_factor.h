// Private to src/reduction: RAII wrapper of a supernodal CHOLMOD Cholesky factor of a symmetric
// positive definite sparse matrix, the Cholesky-transformed eigen operator built on it, and a
// Sylvester inertia count.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <memory>
#include <string>

namespace fricrom::reduction_detail {

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  // Analyse (first call only; the pattern must not change afterwards) and factorise A (both
  // triangles stored; only the lower one is read). False with a message if A is not positive
  // definite or CHOLMOD fails; the factor is then unusable.
  bool Factorize(const Eigen::SparseMatrix<double>& a, std::string* error);
  bool ok() const { return ok_; }
  int rows() const { return n_; }
  // min(diag L) / max(diag L) of the last factorisation (CHOLMOD's rough estimate).
  double rcond() const { return rcond_; }

  // X = A^-1 B, any number of columns (multi-RHS solve; reuses workspace).
  void Solve(const Eigen::Ref<const Eigen::MatrixXd>& b, Eigen::Ref<Eigen::MatrixXd> x);
  // The halves of A^-1 = P^T L^-T L^-1 P (CHOLMOD: L L^T = P A P^T), one vector of rows():
  // y = L^-1 P b and y = P^T L^-T b.
  void ForwardHalf(const double* b, double* y);
  void BackwardHalf(const double* b, double* y);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool ok_ = false;
  int n_ = 0;
  double rcond_ = 0.0;
};

// Number of eigenvalues of K x = lambda M x below `lambda` for K positive definite and M positive
// semi-definite (Sylvester's law of inertia: the negative pivots of a CHOLMOD simplicial LDL^T of
// K - lambda M, fill-reducing symmetric permutation, no pivoting). Infinite eigenvalues (massless
// DOFs) are never counted. False with a message on a zero pivot (lambda at an eigenvalue) or a
// CHOLMOD failure.
bool CountEigenvaluesBelow(const Eigen::SparseMatrix<double>& k,
                           const Eigen::SparseMatrix<double>& m, double lambda, int* count,
                           std::string* error);

// The generalized problem K phi = lambda M phi as a standard symmetric one through a Cholesky
// factor K - sigma M = P^T L L^T P (never a factor of M, which may be only positive
// semi-definite): C = L^-1 P M P^T L^-T, C y = nu y with nu = 1 / (lambda - sigma), phi = P^T L^-T
// y. C is symmetric positive semi-definite in the Euclidean inner product, so Lanczos needs no
// M-inner product (which a singular or slightly indefinite M breaks: ghost Ritz values); massless
// directions have nu = 0 and come last. References K and M, which must outlive it.
class CholeskyTransformOp {
 public:
  CholeskyTransformOp(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m)
      : k_(k), m_(m), m_lower_(m.triangularView<Eigen::Lower>()) {}
  int rows() const { return static_cast<int>(k_.rows()); }
  // Factorises K - sigma M; false (with a message) if it is not positive definite.
  bool set_shift(double sigma, std::string* error);
  // Adopt an existing factor of K (sigma = 0) instead of factorising again.
  void use_factor(CholmodFactor* factor_of_k) {
    external_ = factor_of_k;
    sigma_ = 0.0;
  }
  double shift() const { return sigma_; }
  void perform_op(const double* x, double* y);  // y = C x
  // phi = P^T L^-T y for each column.
  Eigen::MatrixXd ToModes(const Eigen::MatrixXd& y);
  int applications() const { return applications_; }

 private:
  CholmodFactor& factor() { return external_ ? *external_ : own_; }
  const Eigen::SparseMatrix<double>& k_;
  const Eigen::SparseMatrix<double>& m_;
  Eigen::SparseMatrix<double> m_lower_;  // M x through one triangle: half the memory traffic
  CholmodFactor own_;
  CholmodFactor* external_ = nullptr;
  double sigma_ = 0.0;
  int applications_ = 0;
  Eigen::VectorXd w_, v_;
};

}  // namespace fricrom::reduction_detail
