// The linear part of a condensed harmonic balance: per harmonic h the dynamic stiffness
//   Z_h(ω) = K − (hω)² M + i hω C   (real block form [[kd, hωC], [−hωC, kd]] on [cos; sin]),
// and its receptance onto the relative-displacement rows B of the contacts,
// G_h = B_h Z_h⁻¹ B_hᵀ (B_h = B for h = 0, diag(B, B) for h ≥ 1).
// Two routes (ReceptanceMethod): dense LU per harmonic and ω (exact for any C, O(n³) per ω), or
// modal synthesis from one generalised eigen-decomposition K Φ = M Φ Λ (O(n_r² n) per ω) with the
// damping taken as the diagonal of Φᵀ C Φ — exact for proportional damping, an approximation
// whose size DampingCoupling() reports otherwise. The modal route needs M positive definite.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "fricrom/harmonic_balance.h"
#include "linear/dense_lapack.h"

namespace fricrom {

class HarmonicReceptance {
 public:
  // k must make Z_0 = k nonsingular (callers regularise free bodies with the stick stiffness).
  // Throws std::invalid_argument for inconsistent sizes, or for kModal when M is not positive
  // definite or k not positive definite on M's modes.
  HarmonicReceptance(Eigen::MatrixXd k, Eigen::MatrixXd m, Eigen::MatrixXd c, Eigen::MatrixXd b,
                     int harmonics, ReceptanceMethod method = ReceptanceMethod::kDense);

  // Forms G_h (and, dense, the factorisations and P_h = Z_h⁻¹ B_hᵀ) and the responses to the
  // fixed loads for h ≤ `harmonics` (all when negative); harmonics already formed at ω, and h = 0
  // (independent of ω) once formed, are kept. A system with fewer harmonics sharing this
  // receptance (the harmonic ladder's H = 1 search on an H = 3 case) forms only its own: 2 of
  // 6 symmetric products per ω there. Until formed at the current ω, a harmonic's accessors throw
  // std::logic_error.
  void SetFrequency(double omega, int harmonics = -1);
  // Cyclic symmetry (dense route, before any SetFrequency): the rows' terms on the next
  // sector's DOFs (`next`, n_r × n, part of B), which harmonic h ≥ 1 reads delayed by
  // h·phase[r] (Contact::phase_b), and the stick stiffness per row (K_s) that regularises k:
  // B_h and Z_h's stick springs become those of nodal diameter h·EO. Throws for the modal route.
  void SetCyclicRows(Eigen::MatrixXd next, Eigen::VectorXd phase, Eigen::VectorXd stick);
  // Fixed loads f_h (n entries for h = 0, 2n for h ≥ 1; empty = none) and one DOF of interest:
  // their responses Z_h⁻¹ f_h, its relative part B_h Z_h⁻¹ f_h and P_h's rows of the DOF are
  // kept per ω, so a Newton step at fixed ω needs only G_h products (n_r² instead of n n_r).
  void SetFixedLoads(std::vector<Eigen::VectorXd> loads, int dof);
  // The whole response (modal route: formed when first asked for at an ω).
  const Eigen::VectorXd& LoadResponse(int h) const;
  const Eigen::VectorXd& LoadRelative(int h) const { return load_relative_[Formed(h)]; }
  // The response's entries at the DOF of interest (1 for h = 0; cos and sin rows for h ≥ 1).
  const Eigen::VectorXd& LoadResponseAtDof(int h) const { return load_at_dof_[Formed(h)]; }
  const Eigen::MatrixXd& DofPRows(int h) const { return dof_p_rows_[Formed(h)]; }
  // ∂x̃_h/∂ω of x̃_h = Z_h⁻¹ (f_h − B_hᵀ fs) (fixed load f_h, fs stacked like G_h's columns):
  // its relative part B_h ∂x̃_h/∂ω and its entries at the DOF of interest (zero for h = 0). The
  // modal route works in modal coordinates, ∂q/∂ω = −d_h ∘ (∂(1/d_h)/∂ω) ∘ q, for n n_r
  // operations instead of the n² of solving with Z_h (a continuation in frequency asks at every
  // corrector step).
  void OmegaDerivative(int h, const Eigen::VectorXd& fs, Eigen::VectorXd* relative,
                       Eigen::VectorXd* at_dof) const;
  double omega() const { return omega_; }
  int num_dofs() const { return static_cast<int>(k_.rows()); }
  int num_relative() const { return static_cast<int>(b_.rows()); }
  ReceptanceMethod method() const { return method_; }
  // Modal route: max over mode pairs of |c_jk| / sqrt(c_jj c_kk) in Φᵀ C Φ (0 if proportional).
  double DampingCoupling() const { return coupling_; }

  // Z_h⁻¹ rhs; rhs has n entries for h = 0 and 2n ([cos; sin]) for h ≥ 1.
  Eigen::VectorXd Solve(int h, const Eigen::VectorXd& rhs) const;
  // P_h v = Z_h⁻¹ B_hᵀ v and P_hᵀ g = B_h Z_h⁻ᵀ g.
  Eigen::VectorXd TimesP(int h, const Eigen::VectorXd& v) const;
  Eigen::VectorXd TransposeTimesP(int h, const Eigen::VectorXd& g) const;
  // The rows of P_h belonging to one DOF (1 × n_r for h = 0, 2 × 2n_r: cos and sin rows).
  Eigen::MatrixXd PRows(int h, int dof) const;
  // (∂Z_h/∂ω) x for h ≥ 1 (zero for h = 0).
  Eigen::VectorXd DzDomegaTimes(int h, const Eigen::VectorXd& x) const;
  const Eigen::MatrixXd& G(int h) const {
    FormG(Formed(h));
    return g_[h];
  }
  // Whether G_h is formed at the current ω. The modal route forms G_h (h ≥ 1) only when G,
  // GComplexColumns or more than a few GTimes at one ω ask for it; until then GTimes goes through
  // the modes (W diag(d_h) Wᵀ v), equal to the formed product up to round-off.
  bool GFormed(int h) const;
  // G_h v, or G_hᵀ v when `transposed`, v stacked like G_h's columns. For h ≥ 1 through the
  // complex form Ĝ_h = A + iB of G_h = [[A, B], [−B, A]] on v̂ = v_cos − i v_sin: half the memory
  // traffic of the real product (GMRES steps are bound by it).
  void GTimes(int h, const Eigen::VectorXd& v, bool transposed, Eigen::VectorXd* out) const;
  // The columns `cols` of Ĝ_h (h ≥ 1), for products restricted to the entries of v that can be
  // non-zero (GTimes' convention: Ĝ_h v̂, and Ĝ_hᴴ ŵ for the transposed product's rows `cols`).
  Eigen::MatrixXcd GComplexColumns(int h, const std::vector<int>& cols) const;
  // B_h x (relative displacements of a harmonic block).
  Eigen::VectorXd Relative(int h, const Eigen::VectorXd& x) const;

 private:
  // Forms harmonic h at ω: G_h, its complex form, the fixed loads' responses.
  void FormHarmonic(int h, double omega);
  void FormDense(int h, double omega);
  // The modal route's G_h and Ĝ_h at the current ω, unless formed already (harmonic h formed).
  void FormG(int h) const;
  void ComplexForm(int h) const;  // Ĝ_h from G_h
  // Ĝ_h v̂ (or Ĝ_hᴴ v̂) through the modes, in GTimes' convention.
  void ModalProduct(int h, const Eigen::VectorXd& v, bool transposed, Eigen::VectorXd* out) const;
  void UpdateFixedLoads(int h);
  // h, after checking that harmonic h is formed at the current ω (std::logic_error if not).
  int Formed(int h) const;
  // C x, or in the modal route the damping it models, M Φ diag(c) Φᵀ M x.
  Eigen::VectorXd DampingTimes(const Eigen::VectorXd& x) const;

  // B_h in the real block form on [cos; sin] (2n_r × 2n) for h ≥ 1: diag(B, B), or the cyclic
  // rows' delayed next-sector terms.
  Eigen::MatrixXd BlockB(int h) const;
  bool cyclic() const { return next_.size() > 0; }

  Eigen::MatrixXd k_, m_, c_, b_;
  Eigen::MatrixXd next_;           // cyclic rows' next-sector terms (empty: no cyclic rows)
  Eigen::VectorXd phase_, stick_;  // per row: delay per harmonic [rad], stick stiffness
  int harmonics_;
  ReceptanceMethod method_;
  double omega_ = -1.0;
  std::vector<double> formed_at_;  // ω at which each harmonic was formed (NaN: not formed)
  // dense route
  std::vector<dense::Lu> lu_;
  std::vector<Eigen::MatrixXd> p_;
  // modal route
  Eigen::MatrixXd phi_, mphi_, w_;  // mass-normalised modes Φ (n × n), M Φ and W = B Φ
  Eigen::VectorXd lambda_, modal_c_;
  double coupling_ = 0.0;
  std::vector<Eigen::VectorXcd> d_;  // Z_h⁻¹ ≅ Φ diag(d_h) Φᵀ in complex form
  mutable std::vector<Eigen::MatrixXd> g_;
  mutable std::vector<Eigen::MatrixXcd> g_complex_;  // Ĝ_h (h ≥ 1)
  mutable std::vector<double> g_formed_at_;          // ω at which G_h was formed (NaN: never)
  mutable std::vector<int> products_before_g_;       // GTimes through W at the current ω
  // fixed loads and their per-ω responses
  std::vector<Eigen::VectorXd> loads_, load_relative_, load_at_dof_;
  mutable std::vector<Eigen::VectorXd> load_response_;
  mutable std::vector<double> load_response_at_;  // ω of load_response_[h] (NaN: none)
  std::vector<Eigen::VectorXcd> modal_load_;      // modal route: Φᵀ f̂_h (complex form)
  std::vector<Eigen::VectorXcd> modal_load_q_;    // d_h ∘ Φᵀ f̂_h at the current ω
  std::vector<Eigen::MatrixXd> dof_p_rows_;
  int dof_ = -1;
};

}  // namespace fricrom
