#include "app/fe_commands.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli_common.h"
#include "fricrom/fe_model.h"
#include "io/hdf5_file.h"

namespace fricrom::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// info and convert read every matrix in coordinate form: memory by entries, never by the
// declared dimensions (a 10^8-column matrix with two entries costs bytes, not 400 MB of column
// index).
FeReadOptions Coordinates(const std::string& only_matrix = "") {
  FeReadOptions o;
  o.coordinate = true;
  o.only_matrix = only_matrix;
  return o;
}

// max |A - Aᵀ| <= 1e-12 max|A| (real and imaginary parts) by binary search of each transposed
// position in the (column, row)-sorted entries: O(nnz log nnz), no copy.
bool IsSymmetric(const FeMatrix& m) {
  if (m.rows != m.cols) return false;
  const FeCoordinates& c = m.coo;
  const size_t n = c.re.size();
  const auto at = [&](int64_t row, int64_t col, const std::vector<double>& v) {
    size_t lo = 0, hi = n;  // first k with (col[k], row[k]) >= (col, row)
    while (lo < hi) {
      const size_t mid = (lo + hi) / 2;
      if (std::make_pair(c.col[mid], c.row[mid]) < std::make_pair(col, row)) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    return lo < n && c.col[lo] == col && c.row[lo] == row ? v[lo] : 0.0;
  };
  const auto part = [&](const std::vector<double>& v) {
    double amax = 0.0, diff = 0.0;
    for (size_t k = 0; k < n; ++k) {
      amax = std::max(amax, std::abs(v[k]));
      diff = std::max(diff, std::abs(v[k] - at(c.col[k], c.row[k], v)));
    }
    return diff <= 1e-12 * std::max(amax, 1e-300);
  };
  return part(c.re) && (!m.is_complex || part(c.im));
}

json MatrixInfo(const FeMatrix& m) {
  double squares = 0.0;
  for (const double v : m.coo.re) squares += v * v;
  for (const double v : m.coo.im) squares += v * v;
  const double fro = std::sqrt(squares);
  json j = {{"name", m.name},
            {"rows", m.rows},
            {"cols", m.cols},
            {"nnz", m.coo.re.size()},
            {"symmetric", IsSymmetric(m)},
            {"declared_symmetric", m.symmetric},
            {"frobenius", fro},
            {"type", m.is_complex ? "complex" : "real"},
            {"source_precision_bits", m.source_precision_bits}};
  if (!m.row_dofs.empty()) {
    int grids = 0, spoints = 0;
    std::vector<int64_t> nodes;
    for (const DofId& d : m.row_dofs) {
      (d.component == 0 ? spoints : grids)++;
      if (nodes.empty() || nodes.back() != d.node) nodes.push_back(d.node);
    }
    j["dof_map"] = {{"rows", m.row_dofs.size()},
                    {"grid_dofs", grids},
                    {"scalar_points", spoints},
                    {"first", {m.row_dofs.front().node, m.row_dofs.front().component}},
                    {"last", {m.row_dofs.back().node, m.row_dofs.back().component}}};
  } else {
    j["dof_map"] = nullptr;
  }
  return j;
}

// Coordinate (COO) triplets as read: the file holds what the matrix holds (nnz), whatever its
// declared dimensions (a CSC column index would cost 8 bytes per column: 800 MB for 10^8).
void WriteSparse(Hdf5Writer& h5, const std::string& group, const FeMatrix& m) {
  h5.Int64Vector(group + "/row", m.coo.row);
  h5.Int64Vector(group + "/col", m.coo.col);
  h5.Vector(group + "/values", m.coo.re);
  if (m.is_complex) h5.Vector(group + "/values_imag", m.coo.im);
}

// An FE model as HDF5 (schema fricrom-fe-model-1): the chosen matrices with their DOFs, the
// nodes, the superelement DOF order and the coordinate systems.
void WriteFeModelHdf5(const fs::path& out, const FeModel& m,
                      const std::vector<const FeMatrix*>& chosen) {
  Hdf5Writer h5(out);
  h5.Attribute("", "fricrom_version", Version());
  h5.Attribute("", "schema", "fricrom-fe-model-1");
  h5.Attribute("", "source", m.source);
  h5.Attribute("", "format", m.format);
  h5.Attribute("", "layout",
               "matrices/<name>: coordinate triplets, 0-based (row, col, "
               "values[, values_imag]) sorted by column then row, attributes "
               "rows, cols; "
               "dofs: node, component (0 = scalar point)");
  for (const FeMatrix* mat : chosen) {
    const std::string g = "matrices/" + mat->name;
    WriteSparse(h5, g, *mat);
    std::vector<int64_t> nodes, comps;
    for (const DofId& d : mat->row_dofs) {
      nodes.push_back(d.node);
      comps.push_back(d.component);
    }
    if (!nodes.empty()) {
      h5.Int64Vector(g + "/dof_node", nodes);
      h5.Int64Vector(g + "/dof_component", comps);
    }
    h5.Attribute(g, "rows", static_cast<double>(mat->rows));
    h5.Attribute(g, "cols", static_cast<double>(mat->cols));
    h5.Attribute(g, "declared_symmetric", mat->symmetric ? 1.0 : 0.0);
  }
  if (!m.nodes.empty()) {
    std::vector<int64_t> ids;
    std::vector<int> cp, cd;
    Eigen::MatrixXd xyz(m.nodes.size(), 3);
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      ids.push_back(m.nodes[i].id);
      cp.push_back(m.nodes[i].position_system);
      cd.push_back(m.nodes[i].displacement_system);
      xyz.row(i) = m.nodes[i].xyz.transpose();
    }
    h5.Int64Vector("nodes/id", ids);
    h5.Matrix("nodes/xyz", xyz);
    h5.IntVector("nodes/position_system", cp);
    h5.IntVector("nodes/displacement_system", cd);
  }
  if (!m.external_dofs.empty()) {
    std::vector<int64_t> nodes, comps;
    for (const DofId& d : m.external_dofs) {
      nodes.push_back(d.node);
      comps.push_back(d.component);
    }
    h5.Int64Vector("external_dofs/node", nodes);
    h5.Int64Vector("external_dofs/component", comps);
  }
  for (const CoordinateSystem& cs : m.systems) {
    const std::string g = "systems/" + std::to_string(cs.id);
    h5.Vector(g + "/a", Eigen::VectorXd(cs.a));
    h5.Vector(g + "/b", Eigen::VectorXd(cs.b));
    h5.Vector(g + "/c", Eigen::VectorXd(cs.c));
    h5.Attribute(g, "reference", static_cast<double>(cs.reference));
  }
  h5.Commit();
}

}  // namespace

struct FeCommands::State {
  CLI::App* info = nullptr;
  CLI::App* convert = nullptr;
  std::vector<std::string> files;
  std::string file, matrix, to;
  bool as_json = false;

  int RunInfo() {
    json all = json::array();
    for (const std::string& f : files) {
      const FeModel m = ReadFe(f, Coordinates());
      json j = {{"file", f},
                {"format", m.format},
                {"nodes", m.nodes.size()},
                {"coordinate_systems", m.systems.size()},
                {"external_dofs", m.external_dofs.size()}};
      json mats = json::array();
      for (const FeMatrix& mat : m.matrices) mats.push_back(MatrixInfo(mat));
      j["matrices"] = mats;
      json sets = json::object();
      for (const NodeSet& set : m.node_sets) sets[set.name] = set.nodes.size();
      j["node_sets"] = sets;
      all.push_back(j);
    }
    if (as_json) {
      std::cout << (all.size() == 1 ? all[0] : all).dump() << "\n";
      return 0;
    }
    for (const json& j : all) {
      std::cout << j["file"].get<std::string>() << " (" << j["format"].get<std::string>()
                << "): " << j["nodes"] << " nodes, " << j["coordinate_systems"]
                << " coordinate systems"
                << (j["external_dofs"].get<size_t>() > 0 ? ", superelement DOF order (EXTRN) of " +
                                                               j["external_dofs"].dump() + " DOFs"
                                                         : "")
                << "\n";
      if (!j["node_sets"].empty()) {
        std::cout << "  node sets:";
        for (const auto& [name, count] : j["node_sets"].items())
          std::cout << " " << name << " (" << count << ")";
        std::cout << "\n";
      }
      for (const json& m : j["matrices"]) {
        std::cout << "  " << m["name"].get<std::string>() << ": " << m["rows"] << " x " << m["cols"]
                  << ", nnz " << m["nnz"] << ", " << m["type"].get<std::string>()
                  << (m["symmetric"].get<bool>() ? ", symmetric" : "") << ", |A|_F "
                  << m["frobenius"] << (m["dof_map"].is_null() ? ", no DOF map" : ", DOF map")
                  << "\n";
      }
    }
    return 0;
  }

  int RunConvert() {
    // Only the matrix asked for is assembled; the reader names the matrices when it is absent.
    const FeModel m = ReadFe(file, Coordinates(matrix));
    std::vector<const FeMatrix*> chosen;
    for (const FeMatrix& mat : m.matrices) {
      if (matrix.empty() || m.Find(matrix) == &mat) chosen.push_back(&mat);
    }
    const fs::path out(to);
    // A file with no matrices (an EXTSEOUT punch whose matrices went to .op4) still carries nodes,
    // coordinate systems and the superelement DOF order: HDF5 takes it, Matrix Market cannot.
    const bool model_only = chosen.empty() && matrix.empty() && out.extension() == ".h5";
    if (m.matrices.empty() && !model_only) {
      throw CLI::ValidationError("--to", file +
                                             " holds no matrices (only nodes, coordinate "
                                             "systems or a DOF order); convert it to .h5");
    }
    if (chosen.empty() && !model_only) {
      std::string names;
      for (const FeMatrix& mat : m.matrices) names += (names.empty() ? "" : ", ") + mat.name;
      throw CLI::ValidationError(
          "--matrix", "no matrix '" + matrix + "' in " + file + " (it holds: " + names + ")");
    }
    if (out.extension() == ".mtx") {
      if (chosen.size() != 1) {
        throw CLI::ValidationError("--matrix", file + " holds " + std::to_string(chosen.size()) +
                                                   " matrices; choose one for a .mtx output");
      }
      if (chosen[0]->is_complex) {
        throw CLI::ValidationError("--to", "matrix '" + chosen[0]->name +
                                               "' is complex; Matrix Market output is real only "
                                               "(use .h5)");
      }
      // The sidecar that ReadFe picks up: K.mtx <-> K.dof.csv.
      const std::string dofs =
          chosen[0]->row_dofs.empty() ? "" : fs::path(out).replace_extension(".dof.csv").string();
      WriteMatrixMarket(*chosen[0], out.string(), dofs);
      if (!as_json) {
        std::cout << "wrote " << out.string() << (dofs.empty() ? "" : " and " + dofs) << "\n";
      }
    } else if (out.extension() == ".h5") {
      WriteFeModelHdf5(out, m, chosen);
      if (!as_json) std::cout << "wrote " << out.string() << "\n";
    } else {
      throw CLI::ValidationError("--to", "expected a .mtx or .h5 output, got '" + to + "'");
    }
    if (as_json) {
      json mats = json::array();
      for (const FeMatrix* mat : chosen) mats.push_back(MatrixInfo(*mat));
      std::cout << json({{"file", file}, {"to", to}, {"matrices", mats}}).dump() << "\n";
    }
    return 0;
  }
};

FeCommands::FeCommands() : state_(std::make_unique<State>()) {}
FeCommands::~FeCommands() = default;

void FeCommands::Register(CLI::App& app) {
  State& s = *state_;
  s.info = app.add_subcommand("info", "List the matrices (and DOF maps) in FE export files");
  s.info->add_option("files", s.files, "FE files (.op4, .pch, .mtx, .sti/.mas/.dof)")->required();
  s.info->add_flag("--json", s.as_json, "Print JSON on stdout");
  s.convert = app.add_subcommand("convert", "Convert an FE export to Matrix Market or HDF5");
  s.convert->add_option("file", s.file, "FE file")->required();
  s.convert->add_option("--matrix", s.matrix, "Matrix name (default: all; one for .mtx)");
  s.convert->add_option("--to", s.to, "Output: OUT.mtx (+ OUT.dof.csv DOF map) or OUT.h5")
      ->required();
  s.convert->add_flag("--json", s.as_json, "Print JSON on stdout");
}

int FeCommands::Run() {
  State& s = *state_;
  if (*s.info) return s.RunInfo();
  if (*s.convert) return s.RunConvert();
  return -1;
}

}  // namespace fricrom::app
