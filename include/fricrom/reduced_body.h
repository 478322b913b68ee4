// Reduced (Craig-Bampton) FE bodies as the assembly uses them: read from a reduced.h5 written by
// `fricrom reduce`, or reduced from the FE files on first use and cached on disk (content-hashed
// key). HDF5 is used inside src/ only. See docs/reduction.md, "Reduced bodies in the library".
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"

namespace fricrom {

// A reduced (Craig-Bampton) body as the assembly uses it: physical boundary DOFs (node,
// component 1..3 translations, maybe 4..6) then modal coordinates (DofId{node = -1 - k,
// component = 0} for mode k). A boundary row selected by row number from a file without a DOF
// map is DofId{row (1-based), 0}. In reduced.h5 the modal rows are stored as dof_node 0,
// dof_component 0; the reader maps them to -1 - k.
struct ReducedBody {
  std::string source;                    // reduced.h5 path or the FE files it came from
  Eigen::MatrixXd stiffness, mass;       // n x n, n = boundary DOFs + modes [N/m, kg]
  Eigen::MatrixXd damping;               // n x n or empty (0 x 0) when none [N s/m]
  std::vector<DofId> dofs;               // n entries, order of the rows
  int num_boundary = 0;                  // rows [0, num_boundary) are physical
  Eigen::VectorXd modal_frequencies_hz;  // fixed-interface frequencies of the modal coordinates
  std::vector<FeNode> nodes;  // the boundary nodes with coordinates [m] (NaN: none in the model)
  std::vector<NodeSet> node_sets;  // the boundary node sets (restricted to boundary nodes)
  // n x 3: reduced loads of unit accelerations along x, y, z, T^T M g (UnitAccelerationLoads,
  // exact for the full model's mass) [N per m/s^2]; empty when the full model had no DOF map or
  // the file predates them (reduced/unit_acceleration_loads).
  Eigen::MatrixXd unit_acceleration_loads;
  bool from_cache = false;  // ReduceFeBody: true when read from the cache
};

// Reads a reduced.h5 written by `fricrom reduce` (or by ReduceFeBody's cache). Throws
// std::runtime_error naming the file and the missing/inconsistent dataset (sizes, non-finite
// values, a status other than SUCCESS, unknown schema).
ReducedBody ReadReducedBody(const std::string& path);
// Writes it (atomically: temp file + rename) in the same schema. Throws std::invalid_argument
// when the body is inconsistent (sizes, non-finite matrices), std::runtime_error on I/O errors.
void WriteReducedBody(const ReducedBody& body, const std::string& path);

// What `fricrom reduce` stores beside the body (attributes and the checks group).
struct ReducedBodyFileInfo {
  std::string status = "SUCCESS";     // CraigBamptonStatus string; the reader accepts SUCCESS only
  std::string source;                 // "source" attribute; empty: body.source
  std::string boundary_label;         // "boundary_sets" attribute; empty: the node set names
  double cutoff_hz = 0.0;             // 0: count mode (or unknown)
  int64_t full_dofs = -1;             // DOFs of the full model; < 0: not written
  double modal_damping_ratio = -1.0;  // attribute of reduced/damping when >= 0
  std::string cache_key;              // ReduceFeBody's key; empty: not written
  // checks/{full_hz, reduced_hz, rel_error} (written when not empty) and checks/json.
  std::vector<double> full_hz, reduced_hz, rel_error;
  std::string checks_json;
};
void WriteReducedBody(const ReducedBody& body, const std::string& path,
                      const ReducedBodyFileInfo& info);

// Viscous damping of the fixed-interface modes: C is zero except C_qq = diag(2 zeta w_j) with
// w_j = sqrt(max(K_qq(j, j), 0)) (mass-normalised modes: M_qq = I, K_qq = diag(w_j^2)), so each
// fixed-interface mode has the ratio zeta when the boundary is held; boundary rows and columns
// (constraint modes) are undamped. zeta >= 0.
Eigen::MatrixXd FixedInterfaceModalDamping(const Eigen::MatrixXd& reduced_stiffness,
                                           int num_boundary, double zeta);

// Viscous damping of the component's own modes (the reduced body with its boundary free):
// C = M Φ diag(2 zeta w_k) Φᵀ M over the eigenpairs K φ = w² M φ (Φᵀ M Φ = I), so that every mode
// of the body — its first bending mode too, which a CB model with the excitation and response
// nodes on the boundary carries mostly in its constraint modes — has the ratio zeta. Modes with
// w² <= 0 (rigid) are undamped. Throws std::invalid_argument on sizes or zeta < 0, and when M is
// not positive definite.
Eigen::MatrixXd ComponentModalDamping(const Eigen::MatrixXd& reduced_stiffness,
                                      const Eigen::MatrixXd& reduced_mass, double zeta);

// The body of a reduction of (K, `mass`) of `model`: boundary DOFs of `boundary` then modal
// coordinates, the boundary nodes with their coordinates from `model` (NaN when it has none), the
// named sets of `model` that exist restricted to the boundary nodes, the unit acceleration loads
// (when `mass` has a DOF map) and FixedInterfaceModalDamping when zeta >= 0 (< 0: no damping
// matrix). source = model.source.
ReducedBody MakeReducedBody(const FeModel& model, const FeMatrix& mass,
                            const BoundarySelection& boundary, const ReducedModel& reduced,
                            const std::vector<std::string>& sets, double modal_damping_zeta = -1.0);

// An FE body named in a case file: the matrix files, the node sets, the boundary and the options.
struct FeBodySpec {
  std::string stiffness_file;  // any format ReadFe reads (CalculiX .sti with .dof/.inp beside, ...)
  // Empty: the mass comes from the same source as K (e.g. CalculiX .mas beside .sti / a file
  // holding both). Matrices are found by name (STIFFNESS, KAAX, KXX, K / MASS, MAAX, MXX, M) or
  // are the only matrix of their file.
  std::string mass_file;
  std::string sets_file;  // empty: node sets from the deck beside the matrices (as `reduce`)
  // Empty: the matrices' own DOF map; else the order of the matrices that carry none (OP4): a
  // CSV or the EXTRN punch of a superelement, whose grids come along (ReadDofMap).
  std::string dofs_file;
  std::vector<std::string> boundary_sets;   // node set names kept physical (at least one)
  std::vector<int> components = {1, 2, 3};  // 1..6; empty: every component the matrix has
  CraigBamptonOptions reduction;            // modes / cutoff etc.
  // >= 0 (< 1): the ratio of the modes named by damping_basis when > 0; 0: no damping matrix.
  double modal_damping_ratio = 0.0;
  enum class DampingBasis {
    kFixedInterface,  // FixedInterfaceModalDamping: the CB modes only (boundary undamped)
    kComponent,       // ComponentModalDamping: every mode of the reduced body
  };
  DampingBasis damping_basis = DampingBasis::kFixedInterface;
  bool IsValid(std::string* error) const;
};

struct ReduceFeBodyOptions {
  std::string cache_dir;  // empty: no cache; else reduced bodies are stored here as <stem>-<key>.h5
  std::function<void(const std::string&)> progress;  // optional, e.g. "reducing x.sti (4077 DOFs)"
};

// Reduces the body, or reads it from the cache when a file with the same key exists. The key is a
// hash of the CONTENT of every input file (stiffness, mass, sets, the .dof/.inp files read beside)
// and of every option that changes the result; a changed input or option re-reduces. A cache file
// that cannot be read (truncated, other schema) is re-reduced and replaced, never trusted. Throws
// std::runtime_error when the reduction does not reach SUCCESS (message = the summary's).
// Throws std::invalid_argument on an invalid spec or an unknown boundary set (named).
// summary (optional): the reduction's; for a cache hit status kSuccess, the sizes, the modes and
// message "read from the cache <file>".
ReducedBody ReduceFeBody(const FeBodySpec& spec, const ReduceFeBodyOptions& options,
                         CraigBamptonSummary* summary = nullptr);

// The files ReduceFeBody reads for `spec` (hashed into the key): the stiffness file and, for a
// CalculiX job, every prefix.{dof,sti,mas,inp} that exists and the decks *INCLUDEd by the .inp;
// a Matrix Market file's FILE.dof.csv sidecar; the same for mass_file and sets_file.
std::vector<std::string> FeBodyInputFiles(const FeBodySpec& spec);
// 32 hex digits: two 64-bit hashes (FNV-1a and a word-wise multiply-xorshift) of a schema/version
// string, the canonical options and the size and bytes of every input file.
std::string ReducedBodyCacheKey(const FeBodySpec& spec);
// <cache_dir>/<stem of the stiffness file>-<key>.h5
std::string ReducedBodyCachePath(const FeBodySpec& spec, const std::string& cache_dir);

}  // namespace fricrom
