// Craig-Bampton reduction of a sparse FE model (K, M) onto a set of boundary DOFs, which stay
// physical; the interior is represented by static constraint modes and mass-normalised
// fixed-interface normal modes. CHOLMOD and ARPACK are used inside src/reduction only.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace fricrom {

struct CraigBamptonOptions {
  // Number of fixed-interface modes kept (used when cutoff_hz == 0); clamped to the number of
  // interior DOFs with finite eigenvalues.
  int num_modes = 20;
  // > 0: keep every fixed-interface mode with frequency <= cutoff_hz [Hz] (num_modes is then only
  // the first batch size of the search); 0: keep num_modes modes.
  double cutoff_hz = 0.0;
  // Spectral shift sigma [rad^2/s^2] of the shift-invert operator (K_ii - sigma M_ii)^-1 M_ii.
  // Must be <= 0 (the lowest modes are wanted). Use sigma < 0 when K_ii is singular (free-free
  // interior, e.g. an empty boundary set), e.g. -(2 pi * 1 Hz)^2 times a model scale.
  double shift = 0.0;
  // ARPACK relative accuracy of the Ritz values; 0 means machine precision.
  double eigen_tolerance = 0.0;
  // ARPACK restart limit (iparam[2]).
  int max_eigen_iterations = 1000;
  // Interior problems with at most this many DOFs are solved densely (LAPACK-style, all modes)
  // instead of with ARPACK.
  int dense_eigen_max_size = 200;
  // The structural checks of the summary (all relative, see CraigBamptonChecks) must stay below
  // this value, otherwise the status is kChecksFailed.
  double check_tolerance = 1e-8;

  // False with a message naming the field and the rule if an option is out of range.
  bool IsValid(std::string* error) const;
};

enum class CraigBamptonStatus {
  kSuccess,
  kFactorizationFailed,  // K_ii or K_ii - sigma M_ii not positive definite (CHOLMOD / LLT)
  kEigenNotConverged,    // ARPACK reached max_eigen_iterations or returned an error
  kChecksFailed,         // reduced matrices computed, but a structural check exceeds tolerance
};
const char* ToString(CraigBamptonStatus status);

// Structural checks on the reduced matrices, each a max-abs error divided by a scale (given).
struct CraigBamptonChecks {
  double stiffness_symmetry = 0.0;  // max|K_r - K_r^T| / max|K_r|
  double mass_symmetry = 0.0;       // max|M_r - M_r^T| / max|M_r|
  double stiffness_coupling = 0.0;  // max|K_bq| / (max|K| * max|Phi| * (1 + max|Psi|))
  double modal_mass = 0.0;          // max|M_qq - I|
  double modal_stiffness = 0.0;     // max|K_qq - diag(omega^2)| / max(omega^2, |sigma|, 1)
  // max_j ||K_ii phi_j - lambda_j M_ii phi_j|| / ((max|K_ii| + |lambda_j| max|M_ii|) ||phi_j||)
  double eigen_residual = 0.0;
  double Max() const;
};

struct CraigBamptonSummary {
  CraigBamptonStatus status = CraigBamptonStatus::kSuccess;
  std::string message;
  int num_dofs = 0;
  int num_boundary = 0;
  int num_interior = 0;
  int modes = 0;                        // fixed-interface modes kept
  std::vector<double> frequencies_hz;   // of the kept modes, ascending
  bool dense_eigensolver = false;       // interior small enough for the dense path
  int eigen_batches = 0;                // ARPACK runs (several when searching up to cutoff_hz)
  int eigen_restarts = 0;               // ARPACK iterations summed over the batches
  int operator_applications = 0;        // shift-invert solves summed over the batches
  CraigBamptonChecks checks;
  double factor_s = 0.0;                // CHOLMOD analyse + factorise (all factors)
  double constraint_modes_s = 0.0;      // multi-RHS solve for Psi
  double eigen_s = 0.0;                 // fixed-interface modes
  double assembly_s = 0.0;              // T^T K T, T^T M T and checks
  double wall_s = 0.0;                  // total

  bool IsSolutionUsable() const { return status == CraigBamptonStatus::kSuccess; }
  std::string BriefReport() const;
};

struct ReducedModel {
  // Dense (nb + nq) x (nb + nq): rows/cols [boundary DOFs in the given order | modal coordinates].
  Eigen::MatrixXd stiffness;
  Eigen::MatrixXd mass;
  std::vector<int> boundary_dofs;         // indices in the full model, order of the rows above
  Eigen::VectorXd modal_frequencies_hz;   // fixed-interface frequencies of the modal coordinates
  // Interior recovery: u_interior = constraint_modes * u_b + normal_modes * q, interior DOFs in
  // ascending full-model order (interior_dofs).
  std::vector<int> interior_dofs;
  Eigen::MatrixXd constraint_modes;       // Psi, n_i x n_b
  Eigen::MatrixXd normal_modes;           // Phi, n_i x n_q, mass-normalised
};

// Craig-Bampton reduction. K and M: symmetric (both triangles stored), same square size.
// boundary: distinct indices in [0, n), may be empty (pure fixed-interface modal reduction, then
// K must be factorable with the shift, i.e. shift < 0 for a free-free body).
// Throws std::invalid_argument on wrong sizes, non-symmetric input, out-of-range or duplicate
// indices and invalid options; numerical failures are reported in summary->status (the returned
// model is then empty unless status == kChecksFailed). summary may not be null.
ReducedModel ReduceCraigBampton(const Eigen::SparseMatrix<double>& stiffness,
                                const Eigen::SparseMatrix<double>& mass,
                                const std::vector<int>& boundary,
                                const CraigBamptonOptions& options,
                                CraigBamptonSummary* summary);

}  // namespace fricrom
