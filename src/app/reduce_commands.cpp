#include "app/reduce_commands.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "app/cli_common.h"
#include "app/reduce_report.h"
#include "fricrom/basic_frame.h"
#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"
#include "fricrom/units.h"

namespace fricrom::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double PeakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

std::vector<std::string> SplitNames(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

std::vector<int> ParseComponents(const std::string& text) {
  std::vector<int> out;
  if (text.empty() || text == "all") return out;
  for (const char c : text) {
    if (c < '1' || c > '6') {
      throw CLI::ValidationError("--components",
                                 "expected digits 1-6 (e.g. 123), got '" + text + "'");
    }
    const int v = c - '0';
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The stiffness and mass matrices of a model: given names, else the usual export names, else the
// only matrix of a one-matrix file (Abaqus *_STIF1.mtx / *_MASS1.mtx, Matrix Market).
const FeMatrix& PickMatrix(const FeModel& m, const std::string& given,
                           const std::vector<std::string>& defaults, const std::string& flag,
                           const std::string& file) {
  std::vector<std::string> tries = given.empty() ? defaults : std::vector<std::string>{given};
  for (const std::string& name : tries) {
    if (const FeMatrix* mat = m.Find(name)) return *mat;
  }
  if (given.empty() && m.matrices.size() == 1) return m.matrices[0];
  std::string names;
  for (const FeMatrix& mat : m.matrices) names += (names.empty() ? "" : ", ") + mat.name;
  throw CLI::ValidationError(
      flag, "no matrix " + (given.empty() ? "named any of the defaults" : "'" + given + "'") +
                " in " + file +
                " (it holds: " + (names.empty() ? std::string("no matrices") : names) + ")");
}

// K and M as read: from one file, or K from MODEL and M from --mass-file.
struct Inputs {
  FeModel model;       // K's file (plus the --sets deck): DOF map, nodes, node sets
  FeModel mass_model;  // --mass-file
  const FeMatrix* k = nullptr;
  const FeMatrix* m = nullptr;
  std::string mass_path;
  double read_s = 0.0;
};

// Row (1-based) where two DOF maps first differ, described for an error message.
std::string FirstDofDifference(const FeMatrix& k, const FeMatrix& m) {
  if (k.row_dofs.empty() != m.row_dofs.empty()) {
    return std::string(k.row_dofs.empty() ? "the stiffness" : "the mass") +
           " has no DOF map (node, component per row) while the other has one";
  }
  for (size_t i = 0; i < k.row_dofs.size() && i < m.row_dofs.size(); ++i) {
    const DofId& a = k.row_dofs[i];
    const DofId& b = m.row_dofs[i];
    if (a.node != b.node || a.component != b.component) {
      return "row " + std::to_string(i + 1) + " is node " + std::to_string(a.node) + " component " +
             std::to_string(a.component) + " in the stiffness but node " + std::to_string(b.node) +
             " component " + std::to_string(b.component) + " in the mass";
    }
  }
  return std::to_string(k.rows) + " rows against " + std::to_string(m.rows);
}

std::vector<int64_t> ParseIds(const std::string& text, const char* flag, const char* what) {
  std::vector<int64_t> out;
  for (const std::string& t : SplitNames(text)) {
    try {
      size_t used = 0;
      const long long v = std::stoll(t, &used);
      if (used != t.size()) throw std::invalid_argument(t);
      out.push_back(v);
    } catch (const std::exception&) {
      throw CLI::ValidationError(flag, "'" + t + "' is not " + what + " (expected a comma list)");
    }
  }
  if (out.empty()) throw CLI::ValidationError(flag, std::string("no ") + what + " given");
  return out;
}

}  // namespace

struct ReduceCommands::State {
  CLI::App* reduce = nullptr;
  CLI::App* check = nullptr;
  std::string model_path, boundary, components = "all", to, stiffness_name, mass_name;
  std::string mass_file, boundary_nodes, boundary_dofs, sets_file;
  std::string dofs_path;
  int modes = 0;
  double cutoff_hz = 0.0, shift_hz = 0.0, modal_damping = -1.0, check_tolerance = 1e-8;
  int compare_modes = -1;
  bool as_json = false, quiet = false, no_reference = false;

  void Progress(const std::string& what) const {
    if (!quiet) std::cerr << "fricrom reduce: " << what << std::endl;
  }

  void ValidateOptions() const {
    if ((modes > 0) == (cutoff_hz > 0)) {
      throw CLI::ValidationError("--modes/--cutoff-hz",
                                 "give exactly one of --modes N (> 0) or --cutoff-hz F (> 0)");
    }
    if (fs::path(to).extension() != ".h5") {
      throw CLI::ValidationError("--to", "expected an HDF5 output OUT.h5, got '" + to + "'");
    }
    const int given = !boundary.empty() + !boundary_nodes.empty() + !boundary_dofs.empty();
    if (given != 1) {
      throw CLI::ValidationError("--boundary/--boundary-nodes/--boundary-dofs",
                                 "give exactly one of --boundary SET[,SET...] (or 'none'), "
                                 "--boundary-nodes ID[,ID...] or --boundary-dofs ROW[,ROW...]");
    }
    if (!boundary_dofs.empty() && components != "all") {
      throw CLI::ValidationError(
          "--components", "applies to --boundary / --boundary-nodes, not to --boundary-dofs");
    }
    if (!sets_file.empty() && boundary.empty()) {
      throw CLI::ValidationError("--sets",
                                 "the sets of " + sets_file + " are used by --boundary SET");
    }
  }

  void Read(Inputs* in) const {
    Progress("reading " + model_path + (mass_file.empty() ? "" : " and " + mass_file));
    const auto t_read = Clock::now();
    in->model = ReadFe(model_path);
    if (!mass_file.empty()) in->mass_model = ReadFe(mass_file);
    if (!sets_file.empty()) ReadMeshDeck(sets_file, in->model);
    if (!dofs_path.empty()) ApplyDofMap(in);
    // Grids with CP/CD: positions and DOF directions in the basic frame before anything uses them
    // (the reduced body is written in the basic frame).
    try {
      ExpressInBasic(&in->model, {&in->mass_model});
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("reduce", e.what());
    }
    in->read_s = std::chrono::duration<double>(Clock::now() - t_read).count();
    in->k = &PickMatrix(in->model, stiffness_name, {"STIFFNESS", "KAAX", "KXX", "K"}, "--stiffness",
                        model_path);
    in->mass_path = mass_file.empty() ? model_path : mass_file;
    in->m = &PickMatrix(mass_file.empty() ? in->model : in->mass_model, mass_name,
                        {"MASS", "MAAX", "MXX", "M"}, "--mass", in->mass_path);
    const FeMatrix& k = *in->k;
    const FeMatrix& m = *in->m;
    if (k.rows != m.rows || k.cols != m.cols || k.row_dofs != m.row_dofs) {
      throw CLI::ValidationError(
          mass_file.empty() ? "--mass" : "--mass-file",
          "stiffness " + k.name + " (" + model_path + ", " + std::to_string(k.rows) +
              " rows) and mass " + m.name + " (" + in->mass_path + ", " + std::to_string(m.rows) +
              " rows) have different sizes or DOF maps (" + FirstDofDifference(k, m) +
              "): they must come from the same model");
    }
  }

  // --dofs PUNCH: the DOF order of its EXTRN card becomes the DOF map of every matrix without one
  // that has as many rows (OP4 files carry none); its GRID / CORD2R cards join the model.
  void ApplyDofMap(Inputs* in) const {
    const FeModel d = ReadFe(dofs_path);
    if (d.external_dofs.empty()) {
      throw CLI::ValidationError("--dofs", dofs_path + " has no EXTRN card (DOF order)");
    }
    const int64_t n = static_cast<int64_t>(d.external_dofs.size());
    int applied = 0;
    for (FeModel* m : {&in->model, &in->mass_model}) {
      for (FeMatrix& a : m->matrices) {
        if (a.row_dofs.empty() && a.rows == n && a.cols == n) {
          a.row_dofs = a.col_dofs = d.external_dofs;
          ++applied;
        }
      }
    }
    if (applied == 0) {
      throw CLI::ValidationError("--dofs", "the EXTRN order of " + dofs_path + " has " +
                                               std::to_string(n) + " DOFs: no square matrix of " +
                                               "that size without a DOF map in " + model_path);
    }
    for (const FeNode& node : d.nodes) {
      if (!in->model.FindNode(node.id)) in->model.nodes.push_back(node);
    }
    for (const CoordinateSystem& c : d.systems) in->model.systems.push_back(c);
  }

  // Boundary rows: 1-based rows (--boundary-dofs), node / grid ids, or named node sets (of the
  // deck or --sets). A file without a DOF map can only be cut by rows.
  BoundarySelection SelectBoundary(Inputs& in, const std::vector<int>& comps) const {
    const FeMatrix& k = *in.k;
    if (!boundary_dofs.empty()) return SelectRows(k);
    const char* flag = boundary_nodes.empty() ? "--boundary" : "--boundary-nodes";
    std::vector<std::string> sets = SplitNames(boundary);
    if (!boundary_nodes.empty()) {
      in.model.node_sets.push_back(
          {"--boundary-nodes", ParseIds(boundary_nodes, flag, "a node id")});
      sets = {"--boundary-nodes"};
    }
    if (sets.size() == 1 && (sets[0] == "none" || sets[0] == "NONE")) return {};
    if (k.row_dofs.empty()) {
      throw CLI::ValidationError(
          flag, model_path +
                    " has no DOF map (node, component per row; e.g. Matrix Market without "
                    "its FILE.dof.csv sidecar): select boundary rows with --boundary-dofs "
                    "ROW[,ROW...] (1-based), or write the sidecar (header node,component, "
                    "one line per row)");
    }
    try {
      return SelectBoundaryDofs(in.model, k, sets, comps);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError(flag, e.what());
    }
  }

  BoundarySelection SelectRows(const FeMatrix& k) const {
    BoundarySelection sel;
    for (const int64_t row : ParseIds(boundary_dofs, "--boundary-dofs", "a row number")) {
      if (row < 1 || row > k.rows) {
        throw CLI::ValidationError("--boundary-dofs",
                                   "row " + std::to_string(row) + " is outside 1.." +
                                       std::to_string(k.rows) + " (" + model_path + ")");
      }
      const int r = static_cast<int>(row - 1);
      if (std::find(sel.indices.begin(), sel.indices.end(), r) != sel.indices.end()) {
        throw CLI::ValidationError("--boundary-dofs",
                                   "row " + std::to_string(row) + " given twice");
      }
      sel.indices.push_back(r);
      // Without a DOF map a row is a scalar DOF named by its row number (node = row, component 0).
      const DofId d = k.row_dofs.empty() ? DofId{row, 0} : k.row_dofs[r];
      sel.dofs.push_back(d);
      if (std::find(sel.nodes.begin(), sel.nodes.end(), d.node) == sel.nodes.end()) {
        sel.nodes.push_back(d.node);
      }
    }
    return sel;
  }

  CraigBamptonOptions ReductionOptions() const {
    CraigBamptonOptions opt;
    opt.num_modes = modes > 0 ? modes : 20;
    opt.cutoff_hz = cutoff_hz;
    opt.shift = shift_hz > 0 ? -EigenvalueFromHz(shift_hz) : 0.0;
    opt.check_tolerance = check_tolerance;
    std::string err;
    if (!opt.IsValid(&err)) throw CLI::ValidationError("reduce", err);
    return opt;
  }

  int RunReduce() {
    const auto t_start = Clock::now();
    ValidateOptions();
    Inputs in;
    Read(&in);
    const FeMatrix& k = *in.k;
    const BoundarySelection sel = SelectBoundary(in, ParseComponents(components));
    const CraigBamptonOptions opt = ReductionOptions();
    Progress("Craig-Bampton: " + std::to_string(k.rows) + " DOFs, " +
             std::to_string(sel.indices.size()) + " boundary DOFs on " +
             std::to_string(sel.nodes.size()) + " nodes, " +
             (cutoff_hz > 0 ? "modes up to " + std::to_string(cutoff_hz) + " Hz"
                            : std::to_string(modes) + " modes"));
    CraigBamptonSummary summary;
    const ReducedModel red = ReduceCraigBampton(k.real, in.m->real, sel.indices, opt, &summary);
    Progress(summary.BriefReport());
    const bool finite = red.stiffness.allFinite() && red.mass.allFinite();
    const bool have_model = finite && (summary.status == CraigBamptonStatus::kSuccess ||
                                       summary.status == CraigBamptonStatus::kChecksFailed);
    json out = Report(in, sel, summary, in.read_s);
    const auto write = [&](const json& report) {
      Progress("writing " + to);
      WriteReducedModel(
          to, {&in.model, in.m, &sel, &red, &summary,
               boundary_nodes.empty() ? (boundary_dofs.empty() ? boundary : "rows " + boundary_dofs)
                                      : "nodes " + boundary_nodes,
               SplitNames(boundary), cutoff_hz, modal_damping, &report});
    };
    ReferenceReport ref;
    if (have_model && !no_reference) {
      // The model first, so a run killed during the (long) full-model references keeps its
      // reduction; the file says the references are pending until it is rewritten below.
      json pending = out;
      AddReference(ReferenceReport{}, have_model, &pending);
      pending["checks"]["reference_passed"] = nullptr;
      pending["reference_status"] = "pending: written before the full-model reference checks";
      write(pending);
      ref = CompareWithFullModel(
          {&in.model, in.k, in.m, &sel, &red, &summary, cutoff_hz, compare_modes},
          [this](const std::string& w) { Progress(w); });
    }
    AddReference(ref, have_model, &out);
    if (have_model) write(out);
    out["wall_s"] = std::chrono::duration<double>(Clock::now() - t_start).count();
    out["peak_rss_mb"] = PeakRssMb();
    const json& rigid = out["rigid_body"];
    const bool ok = summary.status == CraigBamptonStatus::kSuccess && ref.failure.empty() &&
                    (rigid.is_null() || !rigid.contains("passed") || rigid["passed"].get<bool>());
    out["passed"] = ok;
    if (as_json) {
      std::cout << out.dump() << "\n";
    } else {
      PrintText(out, have_model);
    }
    return ok ? 0 : 1;
  }

  json Report(const Inputs& in, const BoundarySelection& sel, const CraigBamptonSummary& summary,
              double read_s) const {
    json out = {{"model", model_path},
                {"mass_file", mass_file.empty() ? json(nullptr) : json(mass_file)},
                {"to", to},
                {"status", ToString(summary.status)},
                {"message", summary.message},
                {"full_dofs", in.k->rows},
                {"boundary_dofs", sel.indices.size()},
                {"boundary_nodes", sel.nodes.size()},
                {"boundary_sets", SplitNames(boundary)},
                {"modes", summary.modes},
                {"cutoff_hz", cutoff_hz},
                {"units", "SI (m, kg, s, N); frequencies in Hz"}};
    out["fixed_interface_hz"] = summary.frequencies_hz;
    out["checks"] = ChecksJson(summary.checks, check_tolerance);
    out["eigen"] = {{"tolerance", 1e-12},
                    {"batches", summary.eigen_batches},
                    {"restarts", summary.eigen_restarts},
                    {"operator_applications", summary.operator_applications},
                    {"dense", summary.dense_eigensolver}};
    out["timings"] = {{"read_s", read_s},
                      {"factor_s", summary.factor_s},
                      {"constraint_modes_s", summary.constraint_modes_s},
                      {"eigen_s", summary.eigen_s},
                      {"assembly_s", summary.assembly_s},
                      {"reduction_s", summary.wall_s}};
    return out;
  }

  void AddReference(const ReferenceReport& ref, bool have_model, json* out) const {
    json& o = *out;
    for (const auto& [key, value] : ref.timings.items()) o["timings"][key] = value;
    if (!ref.shift.is_null()) o["reference_shift"] = ref.shift;
    o["static_body_load"] = ref.static_check;
    o["eigen_comparison"] = ref.table;
    o["reduced_infinite_eigenvalues"] = ref.reduced_infinite;
    const bool any = !ref.table.empty();
    o["max_rel_eig_error"] = any ? json(ref.max_err) : json(nullptr);
    o["max_rel_eig_error_below_quarter_cutoff"] = any ? json(ref.max_err_quarter) : json(nullptr);
    o["rigid_body"] = ref.rigid;
    if (!ref.rigid.is_null() && ref.rigid.contains("passed")) {
      o["checks"]["rigid_body_passed"] = ref.rigid["passed"];
    }
    if (no_reference || !have_model) {
      o["checks"]["reference_passed"] = nullptr;
      if (!have_model) o["reference_status"] = "not run: no usable reduced model";
    } else {
      o["checks"]["reference_passed"] = ref.failure.empty();
      if (!ref.failure.empty()) o["reference_status"] = ref.failure;
    }
  }

  void PrintText(const json& out, bool have_model) const {
    std::cout << "reduced " << model_path << ": " << out["full_dofs"] << " DOFs -> "
              << out["boundary_dofs"] << " boundary + " << out["modes"] << " modes ("
              << out["status"].get<std::string>() << ")\n";
    if (!out["message"].get<std::string>().empty()) {
      std::cout << "  " << out["message"].get<std::string>() << "\n";
    }
    for (const json& row : out["eigen_comparison"]) {
      std::printf("  mode %3d  full %12.4f Hz  reduced %12.4f Hz  rel. error %.2e%s\n",
                  row["mode"].get<int>(), row["full_hz"].get<double>(),
                  row["reduced_hz"].get<double>(), row["rel_error"].get<double>(),
                  row["rigid_body"].get<bool>() ? "  (rigid body)" : "");
    }
    std::cout << "  checks: " << out["checks"].dump() << "\n";
    if (out.contains("reference_status")) {
      std::cout << "  reference: " << out["reference_status"].get<std::string>() << "\n";
    }
    if (!out["rigid_body"].is_null())
      std::cout << "  rigid body: " << out["rigid_body"].dump() << "\n";
    if (!out["static_body_load"].is_null()) {
      std::cout << "  static body load: " << out["static_body_load"].dump() << "\n";
    }
    std::cout << "  wall " << out["wall_s"].get<double>() << " s, peak RSS "
              << out["peak_rss_mb"].get<double>() << " MB"
              << (have_model ? ", wrote " + to : std::string(", nothing written")) << "\n";
  }

  int RunCheck() {
    const FeModel model = ReadFe(model_path);
    FeModel dof_model;
    std::vector<DofId> order;
    const FeMatrix& k = PickMatrix(model, stiffness_name, {"KXX", "KAAX", "STIFFNESS", "K"},
                                   "--stiffness", model_path);
    const FeMatrix& m =
        PickMatrix(model, mass_name, {"MXX", "MAAX", "MASS", "M"}, "--mass", model_path);
    if (!dofs_path.empty()) {
      dof_model = ReadFe(dofs_path);
      order = dof_model.external_dofs;
      if (order.empty())
        throw CLI::ValidationError("--dofs",
                                   dofs_path + " has no EXTRN card (superelement DOF order)");
    } else {
      order = k.row_dofs;
      dof_model = model;
    }
    if (order.empty()) {
      throw CLI::ValidationError(
          "--dofs",
          model_path +
              " has no DOF map: give the punch file with the EXTRN card (--dofs FILE.pch)");
    }
    if (static_cast<int64_t>(order.size()) != k.rows || k.rows != m.rows) {
      throw CLI::ValidationError(
          "--dofs", "the DOF order has " + std::to_string(order.size()) + " entries but " + k.name +
                        " is " + std::to_string(k.rows) + " x " + std::to_string(k.cols));
    }
    // [grid DOFs | scalar points (modal coordinates)], keeping the file's order within each.
    std::vector<int> perm;
    for (size_t i = 0; i < order.size(); ++i)
      if (order[i].component != 0) perm.push_back(static_cast<int>(i));
    const int nb = static_cast<int>(perm.size());
    for (size_t i = 0; i < order.size(); ++i)
      if (order[i].component == 0) perm.push_back(static_cast<int>(i));
    const Eigen::MatrixXd kd(k.real), md(m.real);
    const int n = static_cast<int>(perm.size());
    Eigen::MatrixXd kr(n, n), mr(n, n);
    std::vector<DofId> dofs;
    for (int i = 0; i < n; ++i) {
      dofs.push_back(order[perm[i]]);
      for (int j = 0; j < n; ++j) {
        kr(i, j) = kd(perm[i], perm[j]);
        mr(i, j) = md(perm[i], perm[j]);
      }
    }
    const CraigBamptonChecks ch = CheckCraigBamptonMatrices(kr, mr, nb);
    json out = {{"model", model_path},
                {"dofs", dofs_path},
                {"boundary_dofs", nb},
                {"modes", n - nb},
                {"checks", ChecksJson(ch, check_tolerance)}};
    std::vector<double> fq;
    for (int j = nb; j < n; ++j) fq.push_back(HzFromEigenvalue(kr(j, j)));
    out["fixed_interface_hz"] = fq;
    bool ok = ch.Max() <= check_tolerance;
    try {
      const Eigen::MatrixXd r = RigidBodyModes(dof_model, dofs, Centroid(dof_model, dofs));
      const double res = (kr * r).cwiseAbs().maxCoeff() /
                         std::max(kr.cwiseAbs().maxCoeff() * r.cwiseAbs().maxCoeff(), 1e-300);
      json rb = {{"K_R_residual", res}, {"free_body", res < 1e-6}};
      if (res < 1e-6) {
        MassProperties p = MassPropertiesFromRigidMass(r.transpose() * mr * r);
        p.center += Centroid(dof_model, dofs);
        rb["mass_properties"] = MassJson(p);
      }
      out["rigid_body"] = rb;
    } catch (const std::invalid_argument& e) {
      out["rigid_body"] = {{"skipped", e.what()}};
    }
    if (as_json) {
      std::cout << out.dump() << "\n";
    } else {
      std::cout << model_path << ": Craig-Bampton model with " << nb << " boundary DOFs and "
                << n - nb << " modal coordinates; checks " << (ok ? "passed" : "FAILED") << "\n  "
                << out["checks"].dump() << "\n  rigid body: " << out["rigid_body"].dump() << "\n";
    }
    return ok ? 0 : 1;
  }
};

ReduceCommands::ReduceCommands() : state_(std::make_unique<State>()) {}
ReduceCommands::~ReduceCommands() = default;

void ReduceCommands::Register(CLI::App& app) {
  State& s = *state_;
  s.reduce = app.add_subcommand("reduce",
                                "Craig-Bampton reduction of an FE model onto node sets (SI units)");
  s.reduce
      ->add_option(
          "model", s.model_path,
          "FE model with stiffness and mass: CalculiX job (.inp deck beside .sti/.mas/.dof), "
          "or any file `fricrom info` reads")
      ->required();
  s.reduce->add_option("--boundary", s.boundary,
                       "Boundary node sets kept physical: SET[,SET...] (or 'none')");
  s.reduce->add_option(
      "--boundary-nodes", s.boundary_nodes,
      "Boundary nodes / Nastran grids by id: ID[,ID...] (all their DOFs, or --components)");
  s.reduce->add_option(
      "--boundary-dofs", s.boundary_dofs,
      "Boundary rows of the matrices, 1-based: ROW[,ROW...] (files without a DOF map, "
      "e.g. Matrix Market without FILE.dof.csv)");
  s.reduce->add_option("--dofs", s.dofs_path,
                       "Punch file whose EXTRN card gives the DOF order of matrices without one "
                       "(Nastran OP4); its GRID cards give node coordinates");
  s.reduce->add_option(
      "--sets", s.sets_file,
      "Deck with *NSET / *NODE NSET= node sets (Abaqus/CalculiX syntax) for --boundary");
  s.reduce->add_option(
      "--mass-file", s.mass_file,
      "Mass matrix from this file (any format `fricrom info` reads); stiffness from MODEL");
  s.reduce->add_option("--components", s.components,
                       "Boundary components, e.g. 123 (default: all the model has)");
  s.reduce->add_option("--modes", s.modes, "Number of fixed-interface modes")
      ->check(CLI::PositiveNumber);
  s.reduce
      ->add_option("--cutoff-hz", s.cutoff_hz,
                   "Keep every fixed-interface mode up to this frequency [Hz]")
      ->check(CLI::PositiveNumber);
  s.reduce
      ->add_option("--shift-hz", s.shift_hz,
                   "Negative spectral shift -(2 pi F)^2 for free-free interiors [Hz]")
      ->check(CLI::NonNegativeNumber);
  s.reduce
      ->add_option("--modal-damping", s.modal_damping,
                   "Modal damping ratio of the fixed-interface modes")
      ->check(CLI::Range(0.0, 1.0));
  s.reduce
      ->add_option("--compare-modes", s.compare_modes,
                   "Full-model modes computed for the accuracy table (default: those below the "
                   "cutoff, <= 60)")
      ->check(CLI::NonNegativeNumber);
  s.reduce->add_option("--check-tolerance", s.check_tolerance, "Tolerance of the structural checks")
      ->check(CLI::PositiveNumber);
  s.reduce->add_flag(
      "--no-reference", s.no_reference,
      "Skip the full-model references (eigenvalues, static load, rigid body): timing runs");
  s.reduce->add_option("--stiffness", s.stiffness_name,
                       "Stiffness matrix name (default STIFFNESS, KAAX, ...)");
  s.reduce->add_option("--mass", s.mass_name, "Mass matrix name (default MASS, MAAX, ...)");
  s.reduce->add_option("--to", s.to, "Output reduced model OUT.h5 (written atomically)")
      ->required();
  s.reduce->add_flag("--json", s.as_json, "Print one JSON object on stdout");
  s.reduce->add_flag("--quiet", s.quiet, "No progress lines on stderr");

  s.check = app.add_subcommand(
      "check-reduced",
      "Structural checks of a Craig-Bampton model (e.g. Nastran EXTSEOUT KXX/MXX)");
  s.check->add_option("model", s.model_path, "File with the reduced K and M (e.g. inboard.op4)")
      ->required();
  s.check->add_option("--dofs", s.dofs_path,
                      "File with the DOF order (punch with EXTRN and GRID cards)");
  s.check->add_option("--stiffness", s.stiffness_name,
                      "Stiffness matrix name (default KXX, KAAX, ...)");
  s.check->add_option("--mass", s.mass_name, "Mass matrix name (default MXX, MAAX, ...)");
  s.check->add_option("--check-tolerance", s.check_tolerance, "Tolerance of the structural checks")
      ->check(CLI::PositiveNumber);
  s.check->add_flag("--json", s.as_json, "Print one JSON object on stdout");
}

int ReduceCommands::Run() {
  State& s = *state_;
  if (*s.reduce) return s.RunReduce();
  if (*s.check) return s.RunCheck();
  return -1;
}

}  // namespace fricrom::app
