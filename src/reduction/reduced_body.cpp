// Reduced bodies: construction from a Craig-Bampton reduction, modal damping, and the reduced.h5
// file (schema fricrom-reduced-model-1) that `fricrom reduce` and ReduceFeBody's cache write.
#include "fricrom/reduced_body.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <stdexcept>

#include "fricrom/reduced_loads.h"
#include "io/hdf5_file.h"

namespace fricrom {
namespace {

constexpr const char* kSchema = "fricrom-reduced-model-1";

// First non-finite entry of a matrix as " (row r, column c)", empty when all are finite.
std::string NonFinite(const Eigen::MatrixXd& a) {
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    for (Eigen::Index r = 0; r < a.rows(); ++r) {
      if (!std::isfinite(a(r, c))) {
        return " (row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1) + ")";
      }
    }
  }
  return "";
}

// Sizes and values the file format needs; `what` prefixes the message (the file or the body).
void CheckBody(const ReducedBody& b, const std::string& what) {
  const Eigen::Index n = b.stiffness.rows();
  const auto fail = [&](const std::string& msg) { throw std::invalid_argument(what + ": " + msg); };
  if (b.stiffness.cols() != n || b.mass.rows() != n || b.mass.cols() != n) {
    fail("stiffness and mass must be square and of one size");
  }
  if (b.damping.size() != 0 && (b.damping.rows() != n || b.damping.cols() != n)) {
    fail("damping must be n x n or empty");
  }
  if (static_cast<Eigen::Index>(b.dofs.size()) != n) fail("dofs must have one entry per row");
  if (b.num_boundary < 0 || b.num_boundary > n ||
      b.modal_frequencies_hz.size() != n - b.num_boundary) {
    fail("num_boundary + modal_frequencies_hz.size() must equal the number of rows");
  }
  for (const auto& [name, m] :
       {std::pair<const char*, const Eigen::MatrixXd*>{"stiffness", &b.stiffness},
        {"mass", &b.mass},
        {"damping", &b.damping}}) {
    const std::string bad = NonFinite(*m);
    if (!bad.empty()) fail(std::string(name) + " has a non-finite value" + bad);
  }
  const Eigen::MatrixXd& g = b.unit_acceleration_loads;
  if (g.size() != 0 && (g.rows() != n || g.cols() != 3)) {
    fail("unit_acceleration_loads must be n x 3 or empty");
  }
  if (!NonFinite(g).empty()) fail("unit_acceleration_loads has a non-finite value" + NonFinite(g));
  for (const NodeSet& s : b.node_sets) {
    if (s.name.empty() || s.name.find('/') != std::string::npos) {
      fail("node set name '" + s.name + "' is empty or has a '/'");
    }
  }
}

std::string JoinSetNames(const std::vector<NodeSet>& sets) {
  std::string out;
  for (const NodeSet& s : sets) out += (out.empty() ? "" : ",") + s.name;
  return out;
}

// The matrices, DOF map and boundary of the file; `fail` throws naming the file and dataset.
template <typename Fail>
void ReadMatrices(const Hdf5Reader& r, const Fail& fail, ReducedBody* b) {
  b->stiffness = r.Matrix("reduced/stiffness");
  const Eigen::Index n = b->stiffness.rows();
  if (b->stiffness.cols() != n) fail("reduced/stiffness", "is not square");
  b->mass = r.Matrix("reduced/mass");
  if (b->mass.rows() != n || b->mass.cols() != n) {
    fail("reduced/mass", "is " + std::to_string(b->mass.rows()) + " x " +
                             std::to_string(b->mass.cols()) + ", reduced/stiffness " +
                             std::to_string(n) + " x " + std::to_string(n));
  }
  if (r.Has("reduced/damping")) {
    b->damping = r.Matrix("reduced/damping");
    if (b->damping.rows() != n || b->damping.cols() != n) {
      fail("reduced/damping", "is not " + std::to_string(n) + " x " + std::to_string(n));
    }
  }
  for (const auto& [name, m] :
       {std::pair<const char*, const Eigen::MatrixXd*>{"reduced/stiffness", &b->stiffness},
        {"reduced/mass", &b->mass},
        {"reduced/damping", &b->damping}}) {
    const std::string bad = NonFinite(*m);
    if (!bad.empty()) fail(name, "has a non-finite value" + bad);
  }
  if (r.Has("reduced/unit_acceleration_loads")) {
    b->unit_acceleration_loads = r.Matrix("reduced/unit_acceleration_loads");
    const Eigen::MatrixXd& g = b->unit_acceleration_loads;
    if (g.rows() != n || g.cols() != 3) {
      fail("reduced/unit_acceleration_loads", "is not " + std::to_string(n) + " x 3");
    }
    const std::string bad = NonFinite(g);
    if (!bad.empty()) fail("reduced/unit_acceleration_loads", "has a non-finite value" + bad);
  }
  b->modal_frequencies_hz = r.Vector("reduced/fixed_interface_hz");
  const Eigen::Index nq = b->modal_frequencies_hz.size();
  if (nq > n) fail("reduced/fixed_interface_hz", "has more entries than the matrices have rows");
  if (!b->modal_frequencies_hz.allFinite()) fail("reduced/fixed_interface_hz", "is not finite");
  b->num_boundary = static_cast<int>(n - nq);
  if (r.HasAttribute("", "num_boundary") &&
      r.DoubleAttribute("", "num_boundary") != static_cast<double>(b->num_boundary)) {
    fail("reduced/fixed_interface_hz", "has " + std::to_string(nq) +
                                           " modes but the num_boundary attribute does not equal "
                                           "the remaining " +
                                           std::to_string(b->num_boundary) + " rows");
  }
}

template <typename Fail>
void ReadDofs(const Hdf5Reader& r, const Fail& fail, ReducedBody* b) {
  const std::vector<int64_t> node = r.Int64Vector("reduced/dof_node");
  const std::vector<int64_t> comp = r.Int64Vector("reduced/dof_component");
  const size_t n = static_cast<size_t>(b->stiffness.rows());
  if (node.size() != n) fail("reduced/dof_node", "does not have one entry per matrix row");
  if (comp.size() != n) fail("reduced/dof_component", "does not have one entry per matrix row");
  for (size_t i = 0; i < n; ++i) {
    const bool modal = static_cast<int>(i) >= b->num_boundary;
    if (comp[i] < 0 || comp[i] > 6 || (modal && (comp[i] != 0 || node[i] != 0))) {
      fail("reduced/dof_component", "row " + std::to_string(i + 1) + " is (" +
                                        std::to_string(node[i]) + ", " + std::to_string(comp[i]) +
                                        "): expected a component 0..6 on a boundary row, (0, 0) "
                                        "on a modal row");
    }
    const int64_t k = static_cast<int64_t>(i) - b->num_boundary;
    b->dofs.push_back(modal ? DofId{-1 - k, 0} : DofId{node[i], static_cast<int>(comp[i])});
  }
}

template <typename Fail>
void ReadBoundary(const Hdf5Reader& r, const Fail& fail, ReducedBody* b) {
  const std::vector<int64_t> ids = r.Int64Vector("boundary/node_id");
  const Eigen::MatrixXd xyz = r.Matrix("boundary/node_xyz");
  if (xyz.rows() != static_cast<Eigen::Index>(ids.size()) || xyz.cols() != 3) {
    fail("boundary/node_xyz", "is not " + std::to_string(ids.size()) + " x 3 (boundary/node_id)");
  }
  const std::set<int64_t> known(ids.begin(), ids.end());
  if (known.size() != ids.size()) fail("boundary/node_id", "has a repeated node id");
  for (size_t i = 0; i < ids.size(); ++i) {
    const Eigen::Vector3d p = xyz.row(static_cast<Eigen::Index>(i)).transpose();
    // A node without coordinates in the model is written as NaN, NaN, NaN; anything else must be
    // finite.
    if (!p.allFinite() && !p.array().isNaN().all()) {
      fail("boundary/node_xyz", "row " + std::to_string(i + 1) + " is not finite");
    }
    b->nodes.push_back(FeNode{ids[i], p, 0, 0});
  }
  for (int i = 0; i < b->num_boundary; ++i) {
    if (!known.count(b->dofs[i].node)) {
      fail("reduced/dof_node", "row " + std::to_string(i + 1) + " is node " +
                                   std::to_string(b->dofs[i].node) +
                                   ", which boundary/node_id does not list");
    }
  }
  for (const std::string& name : r.Children("boundary/sets")) {
    const std::string path = "boundary/sets/" + name;
    NodeSet s{name, r.Int64Vector(path)};
    for (const int64_t id : s.nodes) {
      if (!known.count(id)) fail(path, "has node " + std::to_string(id) + ", not a boundary node");
    }
    b->node_sets.push_back(std::move(s));
  }
}

}  // namespace

Eigen::MatrixXd FixedInterfaceModalDamping(const Eigen::MatrixXd& reduced_stiffness,
                                           int num_boundary, double zeta) {
  const Eigen::Index n = reduced_stiffness.rows();
  if (reduced_stiffness.cols() != n || num_boundary < 0 || num_boundary > n || !(zeta >= 0)) {
    throw std::invalid_argument(
        "FixedInterfaceModalDamping: needs a square stiffness, 0 <= num_boundary <= n and "
        "zeta >= 0");
  }
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = num_boundary; j < n; ++j) {
    c(j, j) = 2 * zeta * std::sqrt(std::max(reduced_stiffness(j, j), 0.0));
  }
  return c;
}

Eigen::MatrixXd ComponentModalDamping(const Eigen::MatrixXd& reduced_stiffness,
                                      const Eigen::MatrixXd& reduced_mass, double zeta) {
  const Eigen::Index n = reduced_stiffness.rows();
  if (reduced_stiffness.cols() != n || reduced_mass.rows() != n || reduced_mass.cols() != n ||
      !(zeta >= 0)) {
    throw std::invalid_argument(
        "ComponentModalDamping: needs square K and M of one size and zeta >= 0");
  }
  if (n == 0) return Eigen::MatrixXd();
  // Symmetrised: the reduced matrices are symmetric up to round-off.
  const Eigen::MatrixXd k = 0.5 * (reduced_stiffness + reduced_stiffness.transpose());
  const Eigen::MatrixXd m = 0.5 * (reduced_mass + reduced_mass.transpose());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
  if (Eigen::LLT<Eigen::MatrixXd>(m).info() != Eigen::Success || eig.info() != Eigen::Success) {
    throw std::invalid_argument("ComponentModalDamping: M is not positive definite");
  }
  const Eigen::VectorXd w2 = eig.eigenvalues();
  Eigen::VectorXd d(n);
  for (Eigen::Index j = 0; j < n; ++j) d[j] = w2[j] > 0 ? 2 * zeta * std::sqrt(w2[j]) : 0.0;
  const Eigen::MatrixXd mphi = m * eig.eigenvectors();
  Eigen::MatrixXd c = mphi * d.asDiagonal() * mphi.transpose();
  return 0.5 * (c + c.transpose());
}

ReducedBody MakeReducedBody(const FeModel& model, const FeMatrix& mass,
                            const BoundarySelection& boundary, const ReducedModel& reduced,
                            const std::vector<std::string>& sets, double modal_damping_zeta) {
  ReducedBody b;
  b.source = model.source;
  b.stiffness = reduced.stiffness;
  b.mass = reduced.mass;
  b.num_boundary = static_cast<int>(boundary.indices.size());
  b.modal_frequencies_hz = reduced.modal_frequencies_hz;
  b.dofs = boundary.dofs;
  const int nq = static_cast<int>(reduced.stiffness.rows()) - b.num_boundary;
  for (int k = 0; k < nq; ++k) b.dofs.push_back(DofId{-1 - k, 0});
  if (static_cast<int64_t>(mass.row_dofs.size()) == mass.rows) {
    b.unit_acceleration_loads = UnitAccelerationLoads(mass.real, mass.row_dofs, reduced);
  }
  if (modal_damping_zeta >= 0) {
    b.damping = FixedInterfaceModalDamping(b.stiffness, b.num_boundary, modal_damping_zeta);
  }
  const std::set<int64_t> on_boundary(boundary.nodes.begin(), boundary.nodes.end());
  for (const int64_t id : boundary.nodes) {
    const FeNode* node = model.FindNode(id);
    b.nodes.push_back(node ? *node : FeNode{id, Eigen::Vector3d::Constant(std::nan("")), 0, 0});
  }
  for (const std::string& name : sets) {
    const NodeSet* s = model.FindNodeSet(name);
    if (!s) continue;
    NodeSet kept{s->name, {}};
    for (const int64_t id : s->nodes) {
      if (on_boundary.count(id)) kept.nodes.push_back(id);
    }
    b.node_sets.push_back(std::move(kept));
  }
  return b;
}

void WriteReducedBody(const ReducedBody& body, const std::string& path) {
  WriteReducedBody(body, path, ReducedBodyFileInfo{});
}

void WriteReducedBody(const ReducedBody& b, const std::string& path,
                      const ReducedBodyFileInfo& info) {
  CheckBody(b, "WriteReducedBody(" + path + ")");
  const int nb = b.num_boundary;
  const int n = static_cast<int>(b.stiffness.rows());
  Hdf5Writer h5{std::filesystem::path(path)};
  h5.Attribute("", "fricrom_version", FRICROM_VERSION);
  h5.Attribute("", "schema", kSchema);
  h5.Attribute("", "method", "Craig-Bampton (fixed-interface modes + constraint modes)");
  h5.Attribute("", "source", info.source.empty() ? b.source : info.source);
  h5.Attribute("", "units",
               "SI: stiffness N/m (N/rad for rotations), mass kg, frequencies Hz, coordinates m");
  h5.Attribute("", "status", info.status);
  h5.Attribute("", "layout",
               "reduced/{stiffness,mass[,damping]}: rows/cols [boundary DOFs (dof_node, "
               "dof_component) | modal coordinates (dof_node 0, dof_component 0)]");
  h5.Attribute("", "boundary_sets",
               info.boundary_label.empty() ? JoinSetNames(b.node_sets) : info.boundary_label);
  h5.Attribute("", "cutoff_hz", info.cutoff_hz);
  h5.Attribute("", "num_boundary", static_cast<double>(nb));
  h5.Attribute("", "num_modes", static_cast<double>(n - nb));
  if (info.full_dofs >= 0) h5.Attribute("", "full_dofs", static_cast<double>(info.full_dofs));
  if (!info.cache_key.empty()) h5.Attribute("", "cache_key", info.cache_key);
  h5.Matrix("reduced/stiffness", b.stiffness);
  h5.Matrix("reduced/mass", b.mass);
  if (b.damping.size() != 0) {
    h5.Matrix("reduced/damping", b.damping);
    if (info.modal_damping_ratio >= 0) {
      h5.Attribute("reduced/damping", "modal_damping_ratio", info.modal_damping_ratio);
    }
  }
  if (b.unit_acceleration_loads.size() != 0) {
    h5.Matrix("reduced/unit_acceleration_loads", b.unit_acceleration_loads);
    h5.Attribute("reduced/unit_acceleration_loads", "meaning",
                 "columns x, y, z: T^T M g, reduced load of a unit acceleration [N per m/s^2]");
  }
  // Modal rows are (0, 0) in the file (the layout `fricrom reduce` has always written).
  std::vector<int64_t> dn(static_cast<size_t>(n), 0), dc(static_cast<size_t>(n), 0);
  for (int i = 0; i < nb; ++i) {
    dn[i] = b.dofs[i].node;
    dc[i] = b.dofs[i].component;
  }
  h5.Int64Vector("reduced/dof_node", dn);
  h5.Int64Vector("reduced/dof_component", dc);
  h5.Vector("reduced/fixed_interface_hz", b.modal_frequencies_hz);
  std::vector<int64_t> ids;
  Eigen::MatrixXd xyz(static_cast<Eigen::Index>(b.nodes.size()), 3);
  for (size_t i = 0; i < b.nodes.size(); ++i) {
    ids.push_back(b.nodes[i].id);
    xyz.row(static_cast<Eigen::Index>(i)) = b.nodes[i].xyz.transpose();
  }
  h5.Int64Vector("boundary/node_id", ids);
  h5.Matrix("boundary/node_xyz", xyz);
  for (const NodeSet& s : b.node_sets) h5.Int64Vector("boundary/sets/" + s.name, s.nodes);
  if (!info.full_hz.empty()) {
    h5.Vector("checks/full_hz", info.full_hz);
    h5.Vector("checks/reduced_hz", info.reduced_hz);
    h5.Vector("checks/rel_error", info.rel_error);
  }
  if (!info.checks_json.empty()) h5.String("checks/json", info.checks_json);
  h5.Commit();
}

ReducedBody ReadReducedBody(const std::string& path) {
  const Hdf5Reader r(path);
  const auto fail = [&](const std::string& dataset, const std::string& what) {
    throw std::runtime_error(path + ": " + dataset + " " + what);
  };
  const std::string schema = r.HasAttribute("", "schema") ? r.StringAttribute("", "schema") : "";
  if (schema != kSchema) {
    fail("attribute 'schema'", "is '" + schema + "': unknown schema (expected " + kSchema + ")");
  }
  const std::string status = r.HasAttribute("", "status") ? r.StringAttribute("", "status") : "";
  if (status != "SUCCESS") {
    fail("attribute 'status'",
         "is '" + status + "': only a reduction that reached SUCCESS is a usable body");
  }
  ReducedBody b;
  b.source = path;
  ReadMatrices(r, fail, &b);
  ReadDofs(r, fail, &b);
  ReadBoundary(r, fail, &b);
  return b;
}

}  // namespace fricrom
