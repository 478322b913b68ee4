// The linear part of a condensed harmonic balance: per harmonic h the dynamic stiffness
//   Z_h(ω) = K − (hω)² M + i hω C   (real block form [[kd, hωC], [−hωC, kd]] on [cos; sin]),
// factorised once per ω, and its receptance onto the relative-displacement rows B of the
// contacts, G_h = B_h Z_h⁻¹ B_hᵀ (B_h = B for h = 0, diag(B, B) for h ≥ 1). Dense: suited to
// lumped and reduced (Craig-Bampton) models of up to a few thousand DOFs.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace fricrom {

class HarmonicReceptance {
 public:
  // k must make Z_0 = k nonsingular (callers regularise free bodies with the stick stiffness).
  HarmonicReceptance(Eigen::MatrixXd k, Eigen::MatrixXd m, Eigen::MatrixXd c, Eigen::MatrixXd b,
                     int harmonics);

  // Factorises Z_h(ω), h = 0..H, and forms P_h = Z_h⁻¹ B_hᵀ and G_h = B_h P_h; no-op if ω is
  // unchanged.
  void SetFrequency(double omega);
  double omega() const { return omega_; }
  int num_dofs() const { return static_cast<int>(k_.rows()); }
  int num_relative() const { return static_cast<int>(b_.rows()); }

  // Z_h⁻¹ rhs; rhs has n entries for h = 0 and 2n ([cos; sin]) for h ≥ 1.
  Eigen::VectorXd Solve(int h, const Eigen::VectorXd& rhs) const;
  // (∂Z_h/∂ω) x for h ≥ 1 (zero for h = 0).
  Eigen::VectorXd DzDomegaTimes(int h, const Eigen::VectorXd& x) const;
  const Eigen::MatrixXd& P(int h) const { return p_[h]; }
  const Eigen::MatrixXd& G(int h) const { return g_[h]; }
  // B_h x (relative displacements of a harmonic block).
  Eigen::VectorXd Relative(int h, const Eigen::VectorXd& x) const;

 private:
  Eigen::MatrixXd k_, m_, c_, b_;
  int harmonics_;
  double omega_ = -1.0;
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXd>> lu_;
  std::vector<Eigen::MatrixXd> p_, g_;
};

}  // namespace fricrom
