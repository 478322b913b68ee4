// Private to src/reduction: RAII wrapper of a supernodal CHOLMOD Cholesky factor of a symmetric
// positive definite sparse matrix, and a Spectra-style shift-invert operator built on it.
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

// Spectra-style operator y = (K - sigma M)^-1 M x for generalised shift-invert eigenproblems.
// References K and M, which must outlive it. perform_op_bx takes B x = M x already computed (as
// ARPACK mode 3 provides it).
class SymShiftInvertCholmodOp {
 public:
  SymShiftInvertCholmodOp(const Eigen::SparseMatrix<double>& k,
                          const Eigen::SparseMatrix<double>& m)
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
  void perform_op(const double* x, double* y);      // y = (K - sigma M)^-1 M x
  void perform_op_bx(const double* bx, double* y);  // y = (K - sigma M)^-1 bx
  void apply_b(const double* x, double* y) const;   // y = M x
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
  Eigen::VectorXd scratch_;
};

}  // namespace fricrom::reduction_detail
