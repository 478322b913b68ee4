// Private: dense kernels through the system BLAS/LAPACK (OpenBLAS at run time in our setup).
// Why: Eigen's portable kernels are built for the baseline x86-64 ISA (no -march), while
// OpenBLAS dispatches to the CPU's vector units and threads, several times faster on the
// condensed Jacobians and the modal decomposition (docs/decisions/0008-modal-receptance.md,
// benchmarks/README.md "dense LU"). Small systems (the lumped model) keep Eigen's routines
// bit for bit, so their results do not move.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

namespace fricrom::dense {

// Below this size the Eigen routines are used (call overhead, and unchanged lumped results).
inline constexpr Eigen::Index kLapackMinSize = 96;

// True when the sizes fit LAPACK's int arguments.
inline bool FitsInt(Eigen::Index a, Eigen::Index b = 0, Eigen::Index c = 0) {
  constexpr Eigen::Index kIntMax = std::numeric_limits<int>::max();
  return a <= kIntMax && b <= kIntMax && c <= kIntMax;
}

// op(a) op(b) with op = transpose where asked, through dgemm for large operands.
Eigen::MatrixXd Product(const Eigen::MatrixXd& a, bool transpose_a, const Eigen::MatrixXd& b,
                        bool transpose_b);

// w diag(d) wᵀ (symmetric), for large operands as P Pᵀ − N Nᵀ by two dsyrk (P, N: the columns of
// w with d > 0 and d < 0 scaled by sqrt|d|): half the flops of the general product. Below the
// size, Eigen's product as before.
Eigen::MatrixXd WeightedGram(const Eigen::MatrixXd& w, const Eigen::VectorXd& d);

// y = op(a) x through dgemv (zgemv for complex a; op(a) = aᴴ then) for large operands: OpenBLAS'
// kernels use the CPU's vector units, Eigen's only the baseline ISA (products of GMRES steps).
void MatVec(const Eigen::MatrixXd& a, bool transpose, const Eigen::VectorXd& x, Eigen::VectorXd* y);
void MatVec(const Eigen::MatrixXcd& a, bool adjoint, const Eigen::VectorXcd& x,
            Eigen::VectorXcd* y);

// y = a x for a symmetric a of which only the upper triangle is read (dsymv for large a, Eigen
// below the size): half the memory traffic of MatVec, which bounds these products.
void SymmetricMatVec(const Eigen::MatrixXd& a, const Eigen::VectorXd& x, Eigen::VectorXd* y);

// LU with partial pivoting of a square matrix: dgetrf/dgetrs, or Eigen below the size.
// Columns that are unit outside a few rows (a(:, s) = d_s e_s + entries in rows M, with no s in
// M — e.g. the harmonic unknowns of fully stuck contacts in the condensed balance, which couple
// only into the mean rows through the static tangential force) are eliminated exactly first:
// with S their set and R the rest, a(S, S) = diag(d), and a x = b becomes
//   (a(R, R) − a(R, S) diag(d)⁻¹ a(S, R)) x_R = b_R − a(R, S) diag(d)⁻¹ b_S,
//   x_S = diag(d)⁻¹ (b_S − a(S, R) x_R),
// where a(R, S) is non-zero only in the rows M, so the Schur complement differs from a(R, R) in
// those rows only. The factorisation then costs that of the |R| block (plus a rank-|S| update of
// |M| rows); exactly unit columns (M empty) are the special case with no update.
// Single precision (LAPACK route only; Eigen's below the size stays double) halves the time and
// memory of the factorisation and of each solve. Its solves are accurate to ~1e-7 · cond, so it
// serves as a preconditioner (GMRES restores double accuracy), never as an exact solver.
enum class LuPrecision { kDouble, kSingle };

class Lu {
 public:
  Lu() = default;
  explicit Lu(const Eigen::MatrixXd& a, LuPrecision precision = LuPrecision::kDouble) {
    Compute(a, precision);
  }
  void Compute(const Eigen::MatrixXd& a, LuPrecision precision = LuPrecision::kDouble);
  // Factorises aᵀ (without forming it where the LAPACK route can solve with a instead).
  void ComputeTransposed(const Eigen::MatrixXd& a, LuPrecision precision = LuPrecision::kDouble);
  // True when Solve is exact to double round-off (not a single-precision factorisation).
  bool exact() const { return !single_; }
  // Estimate of the reciprocal condition number in the 1-norm (0 when exactly singular): dgecon's
  // of the factors, or with eliminated columns LAPACK's estimator (dlacn2) over the whole solve.
  double rcond() const { return rcond_; }
  Eigen::Index rows() const { return n_; }
  // Eliminated columns S (LAPACK route), and the rows M their off-diagonal entries occupy.
  Eigen::Index num_unit_columns() const { return static_cast<Eigen::Index>(unit_.size()); }
  Eigen::Index num_fill_rows() const { return static_cast<Eigen::Index>(fill_rows_.size()); }
  // True once the solves go through the explicit inverse (LazyInverse below).
  bool solves_by_inverse() const { return inverse_ && inverse_->ready.load(); }
  // A⁻¹ b, or A⁻ᵀ b when `transposed` (A: the matrix factorised, aᵀ after ComputeTransposed).
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b, bool transposed = false) const;
  Eigen::VectorXd Solve(const Eigen::VectorXd& b, bool transposed = false) const;

 private:
  void Factor(const Eigen::MatrixXd& a, bool transposed, LuPrecision precision);
  // Chooses S (unit_), R (active_) and M (fill_rows_, with their positions in R).
  void SplitColumns(const Eigen::MatrixXd& a);
  // Gathers a(R, R) − a(R, S) diag(d)⁻¹ a(S, R), a(S, R) (non-zero columns) and a(M, S) diag(d)⁻¹.
  void Gather(const Eigen::MatrixXd& a);
  // getrf (and getcon if `estimate`) of factors_; false if exactly singular or not finite.
  bool FactorActive(bool estimate, double* rcond_active);
  double EstimateRcond(double anorm) const;
  // Solves with the matrix factorised (t: its transpose).
  Eigen::MatrixXd SolveFactored(const Eigen::MatrixXd& b, bool t) const;
  Eigen::MatrixXd SolveActive(Eigen::MatrixXd b, bool transposed) const;
  // a(S, R) v or a(M, S) diag(d)⁻¹ v (`fill`), or their transposes, in the factors' precision.
  Eigen::MatrixXd BlockTimes(bool fill, const Eigen::MatrixXd& v, bool transposed) const;
  // The explicit inverse of a single-precision active part (of at least 256 unknowns), formed
  // once the factorisation has served 48 solves (dense_lu.cpp): a preconditioner reused for
  // hundreds of GMRES products then solves by one matrix-vector product instead of two
  // triangular solves. Shared by copies of this Lu (same factors); thread-safe, as Solve is const.
  struct LazyInverse {
    std::atomic<int> solves{0};
    std::atomic<bool> ready{false};
    std::mutex mutex;
    bool failed = false;  // getri found the factors singular: triangular solves stay
    Eigen::MatrixXf inverse;
  };
  const Eigen::MatrixXf* ActiveInverse() const;

  Eigen::Index n_ = 0;
  bool lapack_ = false;
  bool transposed_ = false;
  bool single_ = false;                                             // factors in factors_single_
  std::vector<Eigen::Index> active_, unit_, fill_rows_, fill_pos_;  // R, S, M, M's places in R
  Eigen::VectorXd unit_diag_;
  std::vector<Eigen::Index> coupling_cols_;    // places in R of a(S, R)'s non-zero columns
  Eigen::MatrixXd factors_, coupling_, fill_;  // LU of the Schur complement; a(S, R); a(M, S)/d
  Eigen::MatrixXf factors_single_, coupling_single_, fill_single_;
  std::vector<int> pivots_;
  std::shared_ptr<LazyInverse> inverse_;  // null unless single precision, large enough
  Eigen::PartialPivLU<Eigen::MatrixXd> eigen_;
  double rcond_ = 0.0;
};

// K Φ = M Φ Λ for symmetric K and symmetric positive definite M (lower triangles read):
// eigenvalues ascending, Φ M-orthonormal. False if M is not positive definite or the solver fails.
bool SymmetricGeneralizedEigen(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                               Eigen::VectorXd* values, Eigen::MatrixXd* vectors);

}  // namespace fricrom::dense
