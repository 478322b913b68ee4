// Matrices exported from FE codes (Nastran DMIG/OUTPUT4/EXTSEOUT, Abaqus, CalculiX, Matrix
// Market) in one common form: named sparse matrices with the DOF map that ties every row and
// column to a node (or scalar point) and a component, plus nodes and coordinate systems when the
// file carries them. Readers live in src/io/, one file per format.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fricrom {

// Bad or unsupported FE input. The message names the file, the line (text) or byte offset
// (binary) and what was expected.
class FeReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One row/column of a matrix: grid node and component 1..6, or a scalar point (component 0).
struct DofId {
  int64_t node = 0;
  int component = 0;
  friend bool operator==(const DofId&, const DofId&) = default;
};

// Coordinate form of a matrix: 0-based entries sorted by column, then row, each position once;
// symmetric storage expanded to both triangles as in FeMatrix::real. Memory by nonzeros only.
struct FeCoordinates {
  std::vector<int64_t> row, col;
  std::vector<double> re;
  std::vector<double> im;  // same length as re when the matrix is complex, else empty
};

struct FeMatrix {
  std::string name;
  int64_t rows = 0;
  int64_t cols = 0;
  bool symmetric = false;  // declared symmetric in the file; storage is expanded
  bool is_complex = false;
  int source_precision_bits = 64;    // 32 for single-precision sources
  Eigen::SparseMatrix<double> real;  // full (both triangles), rows x cols
  Eigen::SparseMatrix<double> imag;  // same shape when is_complex, else empty
  std::vector<DofId> row_dofs;       // empty when the file carries no DOF map
  std::vector<DofId> col_dofs;
  // Read with FeReadOptions::coordinate: the entries are in `coo`, and real/imag stay empty.
  bool coordinate = false;
  FeCoordinates coo;
};

// Reader options; the defaults give every matrix in compressed-column form (FeMatrix::real).
struct FeReadOptions {
  // Only the matrix of this name (case-insensitive) is kept, "" = all. The others are still read
  // for errors but never assembled (no per-column storage); a name the file lacks is an error.
  std::string only_matrix;
  // Coordinate form (FeMatrix::coo) instead of compressed columns, which cost 4 bytes per
  // declared column: for listing and converting huge sparse matrices. Dimensions up to 2^53.
  bool coordinate = false;
  // Largest storage one matrix may take, in bytes; 0 = the physical memory. Compressed columns
  // also need dimensions below 2^31 (Eigen's index).
  uint64_t memory_limit_bytes = 0;
};

struct FeNode {
  int64_t id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  // in coordinate system `position_system`
  int position_system = 0;
  int displacement_system = 0;
};

// Coordinate system given by three points (Nastran CORD2R/CORD2C/CORD2S): origin A, a point B on
// z, a point C in the x-z plane, all in system `reference`. type 'R' rectangular (x, y, z), 'C'
// cylindrical (r, theta [deg], z), 'S' spherical (r, theta [deg] from z, phi [deg]). A CORD1R/C/S
// (defined by grid points) is kept with by_grids = true so that a grid using it is refused by name.
struct CoordinateSystem {
  int id = 0;
  int reference = 0;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  char type = 'R';
  bool by_grids = false;
};

// Named set of nodes from an input deck (Abaqus/CalculiX *NSET, *NODE NSET=); names upper-case.
struct NodeSet {
  std::string name;
  std::vector<int64_t> nodes;  // in the order of the deck, without repeats
};

// Element of an input deck (*ELEMENT, TYPE=...): type upper case as written (C3D10, S4, ...);
// nodes in the deck's order (C3D10: corners 1-4, then mid-sides of 1-2, 2-3, 3-1, 1-4, 2-4, 3-4).
struct FeElement {
  int64_t id = 0;
  std::string type;
  std::vector<int64_t> nodes;
};

struct FeModel {
  std::string source;  // file path(s) read
  std::string format;  // "op4", "dmig", "abaqus", "calculix", "matrix-market", ...
  std::vector<FeMatrix> matrices;
  std::vector<FeNode> nodes;
  std::vector<CoordinateSystem> systems;
  // DOF order of an external superelement (Nastran EXTRN card: grids with their components, then
  // the modal SPOINTs); empty when the file has none.
  std::vector<DofId> external_dofs;
  std::vector<NodeSet> node_sets;
  std::vector<FeElement> elements;  // in the order of the deck

  // Case-insensitive lookups; nullptr if absent.
  const FeMatrix* Find(const std::string& name) const;
  const NodeSet* FindNodeSet(const std::string& name) const;
  const FeNode* FindNode(int64_t id) const;
};

// Readers. Each throws FeReadError on bad input; none returns a partially read matrix.
FeModel ReadOp4(const std::string& path,
                const FeReadOptions& options = {});  // Nastran OUTPUT4, ASCII or binary
FeModel ReadNastranPunch(const std::string& path,
                         const FeReadOptions& options = {});  // DMIG (+ EXTRN, GRID, CORD2R) .pch
FeModel ReadAbaqusMatrix(const std::string& path,
                         const FeReadOptions& options = {});  // *MATRIX GENERATE .mtx
// prefix.sti, prefix.mas, prefix.dof; plus nodes and node sets of the deck prefix.inp when present.
FeModel ReadCalculix(const std::string& prefix, const FeReadOptions& options = {});
// Nodes (*NODE, rectangular coordinates), node sets (*NSET with or without GENERATE, NSET= of
// *NODE) and elements (*ELEMENT, TYPE=...; a data line ending in a comma continues on the next)
// of an Abaqus/CalculiX input deck, following *INCLUDE (relative to the including file); other
// keywords and their data lines are skipped. Appended to `model`.
void ReadInpNodesAndSets(const std::string& path, FeModel& model);
// Nodes and node sets of a mesh deck, appended to `model` (ids it already has are kept): Nastran
// bulk data by extension (.pch .bdf .dat .nas .blk .asm .bulk: GRID, CORD2R/C/S, SET1 as set
// "SET1_<id>", ASET/ASET1 grids as set "ASET"; positions stay in their CP/CD systems until
// ExpressInBasic) or an Abaqus/CalculiX deck (ReadInpNodesAndSets). A deck that adds neither a
// node nor a set is an error.
void ReadMeshDeck(const std::string& path, FeModel& model);
// The DOF order of a matrix file that carries none (OP4, Matrix Market), in external_dofs: a CSV
// (header node,component, one row per matrix row) or the EXTRN card of a Nastran punch/.asm,
// whose GRID and CORD2R/C/S cards come along (nodes, systems). Errors name the file.
FeModel ReadDofMap(const std::string& path);
// Matrix Market coordinate real general/symmetric; DOF map from `dof_csv` (node,component rows)
// when given.
FeModel ReadMatrixMarket(const std::string& path, const std::string& dof_csv = "",
                         const FeReadOptions& options = {});
// Writes every value with %.17g; the DOF-map sidecar when the matrix has one. Atomic writes.
// Takes either storage (FeMatrix::coordinate).
void WriteMatrixMarket(const FeMatrix& matrix, const std::string& path,
                       const std::string& dof_csv = "");
// Chooses the reader from the file's extension and content (a CalculiX deck `job.inp` reads
// job.sti/job.mas/job.dof beside it).
FeModel ReadFe(const std::string& path, const FeReadOptions& options = {});

}  // namespace fricrom
