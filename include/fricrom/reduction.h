// Craig-Bampton reduction of a sparse FE model (K, M) onto a set of boundary DOFs, which stay
// physical; the interior is represented by static constraint modes and mass-normalised
// fixed-interface normal modes. CHOLMOD and ARPACK are used inside src/reduction only.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom {

struct CraigBamptonOptions {
  // Number of fixed-interface modes kept (used when cutoff_hz == 0); clamped to the number of
  // interior DOFs with finite eigenvalues.
  int num_modes = 20;
  // > 0: keep every fixed-interface mode with frequency <= cutoff_hz [Hz] (num_modes is then only
  // the first batch size; a Sylvester count at the cutoff then says how many more); 0: keep
  // num_modes modes.
  double cutoff_hz = 0.0;
  // Spectral shift sigma [rad^2/s^2]: the eigen operator is L^-1 P M_ii P^T L^-T with
  // K_ii - sigma M_ii = P^T L L^T P (eigenvalues 1 / (lambda - sigma); M_ii is never factorised).
  // Must be <= 0 (the lowest modes are wanted). Use sigma < 0 when K_ii is singular (free-free
  // interior, e.g. an empty boundary set), e.g. -(2 pi * 1 Hz)^2 times a model scale.
  double shift = 0.0;
  // ARPACK relative accuracy of the Ritz values; 0 means machine precision. 1e-12 halves the
  // shift-invert solves against 0 on the 123k-DOF blade with the same checks (~1e-14).
  double eigen_tolerance = 1e-12;
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

// max(a, b), but NaN when either is NaN (std::max(a, NaN) returns a: a NaN check would pass).
inline double NanMax(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::quiet_NaN();
  return a < b ? b : a;
}

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
  int modes = 0;                       // fixed-interface modes kept
  std::vector<double> frequencies_hz;  // of the kept modes, ascending
  bool dense_eigensolver = false;      // interior small enough for the dense path
  int eigen_batches = 0;               // ARPACK runs (several when searching up to cutoff_hz)
  int eigen_restarts = 0;              // ARPACK iterations summed over the batches
  int operator_applications = 0;       // operator applications (L^-T, M, L^-1) summed
  CraigBamptonChecks checks;
  double factor_s = 0.0;            // CHOLMOD analyse + factorise (all factors)
  double constraint_modes_s = 0.0;  // multi-RHS solve for Psi
  double eigen_s = 0.0;             // fixed-interface modes
  double assembly_s = 0.0;          // T^T K T, T^T M T and checks
  double wall_s = 0.0;              // total

  bool IsSolutionUsable() const { return status == CraigBamptonStatus::kSuccess; }
  std::string BriefReport() const;
};

struct ReducedModel {
  // Dense (nb + nq) x (nb + nq): rows/cols [boundary DOFs in the given order | modal coordinates].
  Eigen::MatrixXd stiffness;
  Eigen::MatrixXd mass;
  std::vector<int> boundary_dofs;        // indices in the full model, order of the rows above
  Eigen::VectorXd modal_frequencies_hz;  // fixed-interface frequencies of the modal coordinates
  // Interior recovery: u_interior = constraint_modes * u_b + normal_modes * q, interior DOFs in
  // ascending full-model order (interior_dofs).
  std::vector<int> interior_dofs;
  Eigen::MatrixXd constraint_modes;  // Psi, n_i x n_b
  Eigen::MatrixXd normal_modes;      // Phi, n_i x n_q, mass-normalised
};

// Craig-Bampton reduction. K and M: symmetric (both triangles stored), same square size.
// boundary: distinct indices in [0, n), may be empty (pure fixed-interface modal reduction, then
// K must be factorable with the shift, i.e. shift < 0 for a free-free body).
// Throws std::invalid_argument on wrong sizes, non-symmetric input, out-of-range or duplicate
// indices, non-finite entries and invalid options; M may be positive semi-definite (massless
// DOFs; their infinite eigenvalues are never kept); numerical failures are reported in
// summary->status (the returned model is then empty unless status == kChecksFailed). summary may
// not be null.
ReducedModel ReduceCraigBampton(const Eigen::SparseMatrix<double>& stiffness,
                                const Eigen::SparseMatrix<double>& mass,
                                const std::vector<int>& boundary,
                                const CraigBamptonOptions& options, CraigBamptonSummary* summary);

// ---- Boundary selection -------------------------------------------------------------------

// The rows of `matrix` (its DOF map) that belong to the nodes of the named node sets of `model`,
// restricted to `components` (e.g. {1, 2, 3}; empty = every component the matrix has for the
// node). Ordered set by set, node by node in the set's order, component ascending; a node in
// several sets is taken once. Throws std::invalid_argument naming the set/node when a set is
// unknown (the message lists the sets the model has), the matrix has no DOF map, or a node of a
// set has none of the requested components in the matrix (e.g. a constrained node).
struct BoundarySelection {
  std::vector<int> indices;    // row indices in `matrix`
  std::vector<DofId> dofs;     // the same rows as (node, component)
  std::vector<int64_t> nodes;  // distinct nodes, in order of first appearance
};
BoundarySelection SelectBoundaryDofs(const FeModel& model, const FeMatrix& matrix,
                                     const std::vector<std::string>& set_names,
                                     const std::vector<int>& components = {});

// ---- Lowest modes of a full sparse model (reference for the reduced one) -------------------

struct ModalSolveOptions {
  int num_modes = 10;
  // Shift sigma [rad^2/s^2] of (K - sigma M)^-1 M; with auto_shift and a K that is not positive
  // definite (free-free body), a negative shift is chosen from the matrices' scale instead.
  double shift = 0.0;
  bool auto_shift = true;
  double tolerance = 0.0;  // ARPACK relative accuracy; 0 = machine precision
  int max_iterations = 1000;
  int dense_max_size = 200;  // models up to this size are solved densely
  bool IsValid(std::string* error) const;
};

enum class ModalSolveStatus { kSuccess, kFactorizationFailed, kNotConverged };
const char* ToString(ModalSolveStatus status);

struct ModalSolveResult {
  ModalSolveStatus status = ModalSolveStatus::kSuccess;
  std::string message;
  Eigen::VectorXd lambda;          // eigenvalues omega^2 [rad^2/s^2], ascending
  Eigen::VectorXd frequencies_hz;  // sqrt(max(lambda, 0)) / 2 pi
  Eigen::MatrixXd modes;           // mass-normalised, one column per eigenvalue
  double shift_used = 0.0;
  int restarts = 0;
  double wall_s = 0.0;
};

// The `num_modes` lowest eigenpairs of K phi = lambda M phi (K, M symmetric, both triangles; M
// may be only positive semi-definite: infinite eigenvalues of massless DOFs are never returned, so
// fewer than num_modes may come back). ARPACK (Cholesky-transformed operator); the dense solver
// for small models, for more than a quarter of the spectrum, or when ARPACK stops (up to 6000
// DOFs). Throws std::invalid_argument on wrong sizes, non-finite entries or invalid options.
ModalSolveResult SolveLowestModes(const Eigen::SparseMatrix<double>& stiffness,
                                  const Eigen::SparseMatrix<double>& mass,
                                  const ModalSolveOptions& options);

// Finite eigenvalues (ascending, omega^2) of a dense reduced model, through a Cholesky factor of
// K - sigma M (never of M: a reduced M is only positive semi-definite when boundary DOFs carry no
// mass); infinite eigenvalues are dropped, so fewer than n may come back. Throws
// std::invalid_argument on non-finite entries or when no shift tried makes K - sigma M definite.
Eigen::VectorXd ReducedEigenvalues(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass);

// ---- Static response check -------------------------------------------------------------------

// Static response to a uniform acceleration `accel` [m/s^2] (body load f = M a, a = accel on the
// translational components 1-3 of `dofs`) at the boundary DOFs: reduced model (load T^T f) against
// the full model (CHOLMOD solve), and at the interior DOFs recovered by u_i = Psi u_b + Phi q.
// The boundary values are exact for any number of modes (static condensation is exact on the
// boundary), so their error is a consistency check; the interior error measures how well the kept
// modes carry an interior load. K must be positive definite (a supported body). Not solved (with
// a message) when K is not definite or the load is zero (no translational DOF with mass).
struct StaticCheckResult {
  bool solved = false;
  std::string message;
  double rel_error = 0.0;           // max|u_b,red - u_b,full| / max|u_b,full|
  double interior_rel_error = 0.0;  // max|u_i,rec - u_i,full| / max|u_i,full|
  double max_displacement = 0.0;    // max|u_b,full| [m]
};
StaticCheckResult CompareStaticBodyLoad(const Eigen::SparseMatrix<double>& stiffness,
                                        const Eigen::SparseMatrix<double>& mass,
                                        const std::vector<DofId>& dofs, const ReducedModel& reduced,
                                        const Eigen::Vector3d& accel);

// ---- Rigid-body modes and mass properties ----------------------------------------------------

// n x 6 rigid-body displacement fields (translations x, y, z, then rotations about x, y, z through
// `reference`) of the DOFs `dofs`: components 1-3 translate, 4-6 rotate, 0 (scalar points such as
// modal coordinates) are zero; components are in each node's displacement system (rectangular
// CORD2R systems of `model`). Throws std::invalid_argument if a node has no coordinates in `model`,
// gives its position in a system other than basic, or names an unknown system.
Eigen::MatrixXd RigidBodyModes(const FeModel& model, const std::vector<DofId>& dofs,
                               const Eigen::Vector3d& reference = Eigen::Vector3d::Zero());

struct MassProperties {
  double mass = 0.0;                                            // [kg]
  Eigen::Vector3d center = Eigen::Vector3d::Zero();             // [m]
  Eigen::Matrix3d inertia_at_center = Eigen::Matrix3d::Zero();  // [kg m^2]
};
// From the 6 x 6 rigid-body mass matrix R^T M R (R about the origin). Throws if its mass <= 0.
MassProperties MassPropertiesFromRigidMass(const Eigen::Matrix<double, 6, 6>& rigid_mass);

// ---- Structural checks of a given Craig-Bampton model (e.g. a Nastran superelement) -----------

// K_r, M_r ordered [nb boundary DOFs | nq modal coordinates]: symmetry, K_bq = 0 (relative to
// max|K_r|), M_qq = I, K_qq diagonal (off-diagonal relative to its largest diagonal entry).
// stiffness_coupling here is max|K_bq| / max|K_r|; eigen_residual is not applicable (0).
// Throws std::invalid_argument on inconsistent sizes.
CraigBamptonChecks CheckCraigBamptonMatrices(const Eigen::MatrixXd& stiffness,
                                             const Eigen::MatrixXd& mass, int num_boundary);

}  // namespace fricrom
