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
#include "app/hdf5_writer.h"
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
      throw CLI::ValidationError("--components", "expected digits 1-6 (e.g. 123), got '" + text + "'");
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
  throw CLI::ValidationError(flag, "no matrix " + (given.empty() ? "named any of the defaults" : "'" + given + "'") +
                                       " in " + file + " (it holds: " +
                                       (names.empty() ? std::string("no matrices") : names) + ")");
}

json ChecksJson(const CraigBamptonChecks& c, double tolerance) {
  return {{"stiffness_symmetry", c.stiffness_symmetry}, {"mass_symmetry", c.mass_symmetry},
          {"stiffness_coupling_Kbq", c.stiffness_coupling}, {"modal_mass_Mqq_minus_I", c.modal_mass},
          {"modal_stiffness_Kqq_minus_diag", c.modal_stiffness}, {"eigen_residual", c.eigen_residual},
          {"tolerance", tolerance}, {"passed", c.Max() <= tolerance}};
}

json MassJson(const MassProperties& p) {
  json inertia = json::array();
  for (int i = 0; i < 3; ++i) inertia.push_back({p.inertia_at_center(i, 0), p.inertia_at_center(i, 1), p.inertia_at_center(i, 2)});
  // Units are the model file's (kg, m, kg m^2 for SI models such as fricrom's meshes).
  return {{"mass", p.mass}, {"center", {p.center.x(), p.center.y(), p.center.z()}},
          {"inertia_at_center", inertia}};
}

double RelDiff(const MassProperties& a, const MassProperties& b) {
  const double dm = std::abs(a.mass - b.mass) / a.mass;
  const double size = std::sqrt(std::max(a.inertia_at_center.trace() / a.mass, 1e-300));
  const double dc = (a.center - b.center).norm() / size;
  const double di = (a.inertia_at_center - b.inertia_at_center).cwiseAbs().maxCoeff() /
                    std::max(a.inertia_at_center.cwiseAbs().maxCoeff(), 1e-300);
  return std::max({dm, dc, di});
}

Eigen::Vector3d Centroid(const FeModel& m, const std::vector<DofId>& dofs) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  int n = 0;
  int64_t last = -1;
  for (const DofId& d : dofs) {
    if (d.component == 0 || d.node == last) continue;
    last = d.node;
    if (const FeNode* node = m.FindNode(d.node)) {
      c += node->xyz;
      ++n;
    }
  }
  return n ? Eigen::Vector3d(c / n) : c;
}

// Relative residual of K R (R: rigid-body fields): small for a body free of supports.
double RigidResidual(const Eigen::SparseMatrix<double>& k, const Eigen::MatrixXd& r) {
  const Eigen::MatrixXd kr = k * r;
  double kmax = 0.0;
  for (int c = 0; c < k.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it)
      kmax = std::max(kmax, std::abs(it.value()));
  return kr.cwiseAbs().maxCoeff() / std::max(kmax * r.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

struct ReduceCommands::State {
  CLI::App* reduce = nullptr;
  CLI::App* check = nullptr;
  std::string model_path, boundary, components = "all", to, stiffness_name, mass_name;
  std::string mass_file, boundary_nodes, sets_file;

  // Boundary DOFs: named node sets (of the deck or --sets), or node / grid ids.
  BoundarySelection SelectBoundary(FeModel& model, const FeMatrix& k,
                                   const std::vector<int>& comps) const {
    std::vector<std::string> sets = SplitNames(boundary);
    const char* flag = "--boundary";
    if (!boundary_nodes.empty()) {
      flag = "--boundary-nodes";
      NodeSet ids{"--boundary-nodes", {}};
      for (const std::string& t : SplitNames(boundary_nodes)) {
        try {
          size_t used = 0;
          const long long v = std::stoll(t, &used);
          if (used != t.size()) throw std::invalid_argument(t);
          ids.nodes.push_back(v);
        } catch (const std::exception&) {
          throw CLI::ValidationError("--boundary-nodes", "'" + t + "' is not a node id (expected ID[,ID...])");
        }
      }
      if (ids.nodes.empty()) throw CLI::ValidationError("--boundary-nodes", "no node id given");
      model.node_sets.push_back(ids);
      sets = {"--boundary-nodes"};
    }
    if (sets.size() == 1 && (sets[0] == "none" || sets[0] == "NONE")) return {};
    try {
      return SelectBoundaryDofs(model, k, sets, comps);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError(flag, e.what());
    }
  }
  std::string dofs_path;
  int modes = 0;
  double cutoff_hz = 0.0, shift_hz = 0.0, modal_damping = -1.0, check_tolerance = 1e-8;
  int compare_modes = -1;
  bool as_json = false, quiet = false, no_reference = false;

  void Progress(const std::string& what) const {
    if (!quiet) std::cerr << "fricrom reduce: " << what << std::endl;
  }

  int RunReduce() {
    const auto t_start = Clock::now();
    if ((modes > 0) == (cutoff_hz > 0)) {
      throw CLI::ValidationError("--modes/--cutoff-hz", "give exactly one of --modes N (> 0) or --cutoff-hz F (> 0)");
    }
    if (fs::path(to).extension() != ".h5") {
      throw CLI::ValidationError("--to", "expected an HDF5 output OUT.h5, got '" + to + "'");
    }
    if (boundary.empty() == boundary_nodes.empty()) {
      throw CLI::ValidationError("--boundary/--boundary-nodes",
                                 "give exactly one of --boundary SET[,SET...] (or 'none') or "
                                 "--boundary-nodes ID[,ID...]");
    }
    Progress("reading " + model_path + (mass_file.empty() ? "" : " and " + mass_file));
    const auto t_read = Clock::now();
    FeModel model = ReadFe(model_path);
    const FeModel mass_model = mass_file.empty() ? FeModel{} : ReadFe(mass_file);
    if (!sets_file.empty()) ReadInpNodesAndSets(sets_file, model);
    const double read_s = std::chrono::duration<double>(Clock::now() - t_read).count();
    const FeMatrix& k = PickMatrix(model, stiffness_name, {"STIFFNESS", "KAAX", "KXX", "K"}, "--stiffness", model_path);
    const std::string& mass_path = mass_file.empty() ? model_path : mass_file;
    const FeMatrix& m = PickMatrix(mass_file.empty() ? model : mass_model, mass_name,
                                   {"MASS", "MAAX", "MXX", "M"}, "--mass", mass_path);
    if (k.rows != m.rows || k.cols != m.cols || k.row_dofs != m.row_dofs) {
      throw CLI::ValidationError(
          mass_file.empty() ? "--mass" : "--mass-file",
          "stiffness " + k.name + " (" + model_path + ", " + std::to_string(k.rows) + " rows) and mass " +
              m.name + " (" + mass_path + ", " + std::to_string(m.rows) +
              " rows) have different sizes or DOF maps: they must come from the same model");
    }
    const std::vector<int> comps = ParseComponents(components);
    BoundarySelection sel = SelectBoundary(model, k, comps);
    const std::vector<std::string> sets = SplitNames(boundary);
    CraigBamptonOptions opt;
    opt.num_modes = modes > 0 ? modes : 20;
    opt.cutoff_hz = cutoff_hz;
    opt.shift = shift_hz > 0 ? -std::pow(kTwoPi * shift_hz, 2) : 0.0;
    opt.check_tolerance = check_tolerance;
    std::string err;
    if (!opt.IsValid(&err)) throw CLI::ValidationError("reduce", err);
    Progress("Craig-Bampton: " + std::to_string(k.rows) + " DOFs, " + std::to_string(sel.indices.size()) +
             " boundary DOFs on " + std::to_string(sel.nodes.size()) + " nodes, " +
             (cutoff_hz > 0 ? "modes up to " + std::to_string(cutoff_hz) + " Hz" : std::to_string(modes) + " modes"));
    CraigBamptonSummary summary;
    const ReducedModel red = ReduceCraigBampton(k.real, m.real, sel.indices, opt, &summary);
    Progress(summary.BriefReport());
    const int nb = static_cast<int>(sel.indices.size()), nq = summary.modes;
    const bool have_model = summary.status == CraigBamptonStatus::kSuccess ||
                            summary.status == CraigBamptonStatus::kChecksFailed;

    json out = {{"model", model_path}, {"to", to}, {"status", ToString(summary.status)},
                {"message", summary.message}, {"full_dofs", k.rows}, {"boundary_dofs", nb},
                {"boundary_nodes", sel.nodes.size()}, {"boundary_sets", sets}, {"modes", nq},
                {"cutoff_hz", cutoff_hz}, {"units", "SI (m, kg, s, N); frequencies in Hz"}};
    out["fixed_interface_hz"] = summary.frequencies_hz;
    out["checks"] = ChecksJson(summary.checks, check_tolerance);
    out["eigen"] = {{"tolerance", opt.eigen_tolerance}, {"batches", summary.eigen_batches},
                    {"restarts", summary.eigen_restarts},
                    {"operator_applications", summary.operator_applications},
                    {"dense", summary.dense_eigensolver}};
    json timings = {{"read_s", read_s}, {"factor_s", summary.factor_s}, {"constraint_modes_s", summary.constraint_modes_s},
                    {"eigen_s", summary.eigen_s}, {"assembly_s", summary.assembly_s},
                    {"reduction_s", summary.wall_s}};

    // Reference: the full model's lowest eigenfrequencies against the reduced model's.
    json table = json::array();
    double max_err = 0.0, max_err_quarter = 0.0;
    Eigen::VectorXd reduced_lambda;
    json rigid = nullptr;
    if (have_model && !no_reference) {
      reduced_lambda = ReducedEigenvalues(red.stiffness, red.mass);
      const double f_top = cutoff_hz > 0 ? cutoff_hz
                                         : (nq > 0 ? summary.frequencies_hz.back() : 0.0);
      int count = compare_modes;
      if (count < 0) {
        count = 0;
        for (Eigen::Index j = 0; j < reduced_lambda.size(); ++j) {
          if (std::sqrt(std::max(reduced_lambda(j), 0.0)) / kTwoPi <= f_top) ++count;
        }
        count = std::clamp(count, 1, 60);
      }
      count = std::min<int>(count, static_cast<int>(reduced_lambda.size()));
      if (count > 0) {
        Progress("reference: " + std::to_string(count) + " lowest modes of the full model (ARPACK)");
        ModalSolveOptions mo;
        mo.num_modes = count;
        const ModalSolveResult full = SolveLowestModes(k.real, m.real, mo);
        timings["full_model_modes_s"] = full.wall_s;
        if (full.status != ModalSolveStatus::kSuccess) {
          out["reference_status"] = std::string(ToString(full.status)) + ": " + full.message;
        } else {
          out["reference_shift"] = full.shift_used;
          // Rigid-body (zero) modes: compare absolutely against the first elastic eigenvalue.
          const double lam_scale = std::max(
              {std::abs(full.lambda(full.lambda.size() - 1)), std::abs(full.shift_used), 1e-300});
          for (int j = 0; j < full.lambda.size(); ++j) {
            const double lf = full.lambda(j), lr = reduced_lambda(j);
            const bool rigid_mode = std::abs(lf) < 1e-8 * lam_scale;
            const double ff = std::sqrt(std::max(lf, 0.0)) / kTwoPi;
            const double fr = std::sqrt(std::max(lr, 0.0)) / kTwoPi;
            const double e = rigid_mode ? std::abs(lr - lf) / lam_scale : std::abs(fr - ff) / ff;
            table.push_back({{"mode", j + 1}, {"full_hz", ff}, {"reduced_hz", fr}, {"rel_error", e},
                             {"rigid_body", rigid_mode}});
            max_err = std::max(max_err, e);
            if (ff <= 0.25 * f_top) max_err_quarter = std::max(max_err_quarter, e);
          }
        }
      }
      // Free body: rigid-body fields annihilated by K; compare mass properties full vs reduced.
      if (!model.nodes.empty()) {
        try {
          const Eigen::Vector3d ref = Centroid(model, k.row_dofs);
          const Eigen::MatrixXd r_full = RigidBodyModes(model, k.row_dofs, ref);
          const double res = RigidResidual(k.real, r_full);
          if (res < 1e-8) {
            const Eigen::Matrix<double, 6, 6> mrr_full = r_full.transpose() * (m.real * r_full);
            Eigen::MatrixXd r_red = Eigen::MatrixXd::Zero(nb + nq, 6);
            for (int i = 0; i < nb; ++i) r_red.row(i) = r_full.row(sel.indices[i]);
            const Eigen::Matrix<double, 6, 6> mrr_red = r_red.transpose() * red.mass * r_red;
            const double res_red = (red.stiffness * r_red).cwiseAbs().maxCoeff() /
                                   std::max(red.stiffness.cwiseAbs().maxCoeff() * r_red.cwiseAbs().maxCoeff(), 1e-300);
            MassProperties pf = MassPropertiesFromRigidMass(mrr_full);
            MassProperties pr = MassPropertiesFromRigidMass(mrr_red);
            pf.center += ref;
            pr.center += ref;
            int zero_modes = 0;
            const double lam_el = reduced_lambda.size() > 6 ? std::abs(reduced_lambda(6)) : 1.0;
            for (Eigen::Index j = 0; j < reduced_lambda.size(); ++j)
              zero_modes += std::abs(reduced_lambda(j)) < 1e-6 * lam_el ? 1 : 0;
            const double dev = RelDiff(pf, pr);
            rigid = {{"free_body", true}, {"full_K_R_residual", res}, {"reduced_K_R_residual", res_red},
                     {"reduced_zero_modes", zero_modes}, {"full", MassJson(pf)}, {"reduced", MassJson(pr)},
                     {"mass_properties_rel_diff", dev},
                     {"passed", zero_modes == 6 && res_red < 1e-8 && dev < 1e-8}};
          } else {
            rigid = {{"free_body", false}, {"full_K_R_residual", res}};
          }
        } catch (const std::invalid_argument& e) {
          rigid = {{"free_body", nullptr}, {"skipped", e.what()}};
        }
      }
    }
    // Interior load: uniform acceleration along (1,1,1)/sqrt(3) on a supported body.
    json static_check = nullptr;
    const bool free_body = !rigid.is_null() && rigid.value("free_body", false) == true;
    if (have_model && !free_body && !no_reference) {
      Progress("reference: static body load on the full model (CHOLMOD)");
      const auto ts = Clock::now();
      const StaticCheckResult st =
          CompareStaticBodyLoad(k.real, m.real, k.row_dofs, red, Eigen::Vector3d::Constant(1.0 / std::sqrt(3.0)));
      timings["full_model_static_s"] = std::chrono::duration<double>(Clock::now() - ts).count();
      static_check = {{"load", "uniform acceleration 1 m/s^2 along (1,1,1)/sqrt(3)"}, {"solved", st.solved},
                      {"rel_error_at_boundary", st.solved ? json(st.rel_error) : json(nullptr)},
                      {"rel_error_interior_recovered", st.solved ? json(st.interior_rel_error) : json(nullptr)},
                      {"max_boundary_displacement_m", st.max_displacement}, {"message", st.message}};
    }
    out["static_body_load"] = static_check;
    out["eigen_comparison"] = table;
    out["max_rel_eig_error"] = table.empty() ? json(nullptr) : json(max_err);
    out["max_rel_eig_error_below_quarter_cutoff"] = table.empty() ? json(nullptr) : json(max_err_quarter);
    out["rigid_body"] = rigid;
    if (!rigid.is_null() && rigid.contains("passed")) out["checks"]["rigid_body_passed"] = rigid["passed"];

    if (have_model) {
      Progress("writing " + to);
      Hdf5Writer h5{fs::path(to)};
      h5.Attribute("", "fricrom_version", Version());
      h5.Attribute("", "schema", "fricrom-reduced-model-1");
      h5.Attribute("", "method", "Craig-Bampton (fixed-interface modes + constraint modes)");
      h5.Attribute("", "source", model.source);
      h5.Attribute("", "units", "SI: stiffness N/m (N/rad for rotations), mass kg, frequencies Hz, coordinates m");
      h5.Attribute("", "status", ToString(summary.status));
      h5.Attribute("", "layout", "reduced/{stiffness,mass[,damping]}: rows/cols [boundary DOFs (dof_node, "
                                 "dof_component) | modal coordinates (dof_node 0, dof_component 0)]");
      h5.Attribute("", "boundary_sets", boundary);
      h5.Attribute("", "cutoff_hz", cutoff_hz);
      h5.Attribute("", "num_boundary", static_cast<double>(nb));
      h5.Attribute("", "num_modes", static_cast<double>(nq));
      h5.Matrix("reduced/stiffness", red.stiffness);
      h5.Matrix("reduced/mass", red.mass);
      if (modal_damping >= 0) {
        Eigen::MatrixXd c = Eigen::MatrixXd::Zero(nb + nq, nb + nq);
        for (int j = 0; j < nq; ++j) c(nb + j, nb + j) = 2 * modal_damping * std::sqrt(std::max(red.stiffness(nb + j, nb + j), 0.0));
        h5.Matrix("reduced/damping", c);
        h5.Attribute("reduced/damping", "modal_damping_ratio", modal_damping);
      }
      std::vector<int64_t> dn, dc;
      for (const DofId& d : sel.dofs) {
        dn.push_back(d.node);
        dc.push_back(d.component);
      }
      dn.resize(nb + nq, 0);
      dc.resize(nb + nq, 0);
      h5.Int64Vector("reduced/dof_node", dn);
      h5.Int64Vector("reduced/dof_component", dc);
      h5.Vector("reduced/fixed_interface_hz", red.modal_frequencies_hz);
      std::vector<int64_t> ids;
      Eigen::MatrixXd xyz(sel.nodes.size(), 3);
      for (size_t i = 0; i < sel.nodes.size(); ++i) {
        ids.push_back(sel.nodes[i]);
        const FeNode* node = model.FindNode(sel.nodes[i]);
        xyz.row(static_cast<Eigen::Index>(i)) = node ? Eigen::RowVector3d(node->xyz.transpose()) : Eigen::RowVector3d::Constant(std::nan(""));
      }
      h5.Int64Vector("boundary/node_id", ids);
      h5.Matrix("boundary/node_xyz", xyz);
      for (const std::string& name : sets) {
        if (const NodeSet* s = model.FindNodeSet(name)) h5.Int64Vector("boundary/sets/" + s->name, s->nodes);
      }
      if (!table.empty()) {
        std::vector<double> fh, rh, re;
        for (const json& row : table) {
          fh.push_back(row["full_hz"]);
          rh.push_back(row["reduced_hz"]);
          re.push_back(row["rel_error"]);
        }
        h5.Vector("checks/full_hz", fh);
        h5.Vector("checks/reduced_hz", rh);
        h5.Vector("checks/rel_error", re);
      }
      h5.String("checks/json", out["checks"].dump());
      h5.Commit();
    }
    out["wall_s"] = std::chrono::duration<double>(Clock::now() - t_start).count();
    out["timings"] = timings;
    out["peak_rss_mb"] = PeakRssMb();
    const bool ok = summary.status == CraigBamptonStatus::kSuccess &&
                    (rigid.is_null() || !rigid.contains("passed") || rigid["passed"].get<bool>());
    if (as_json) {
      std::cout << out.dump() << "\n";
    } else {
      std::cout << "reduced " << model_path << ": " << k.rows << " DOFs -> " << nb << " boundary + " << nq
                << " modes (" << ToString(summary.status) << ")\n";
      for (const json& row : table) {
        std::printf("  mode %3d  full %12.4f Hz  reduced %12.4f Hz  rel. error %.2e%s\n", row["mode"].get<int>(),
                    row["full_hz"].get<double>(), row["reduced_hz"].get<double>(), row["rel_error"].get<double>(),
                    row["rigid_body"].get<bool>() ? "  (rigid body)" : "");
      }
      std::cout << "  checks: " << out["checks"].dump() << "\n";
      if (!rigid.is_null()) std::cout << "  rigid body: " << rigid.dump() << "\n";
      if (!static_check.is_null()) std::cout << "  static body load: " << static_check.dump() << "\n";
      std::cout << "  wall " << out["wall_s"].get<double>() << " s, peak RSS " << out["peak_rss_mb"].get<double>()
                << " MB" << (have_model ? ", wrote " + to : std::string()) << "\n";
    }
    return ok ? 0 : 1;
  }

  int RunCheck() {
    const FeModel model = ReadFe(model_path);
    FeModel dof_model;
    std::vector<DofId> order;
    const FeMatrix& k = PickMatrix(model, stiffness_name, {"KXX", "KAAX", "STIFFNESS", "K"}, "--stiffness", model_path);
    const FeMatrix& m = PickMatrix(model, mass_name, {"MXX", "MAAX", "MASS", "M"}, "--mass", model_path);
    if (!dofs_path.empty()) {
      dof_model = ReadFe(dofs_path);
      order = dof_model.external_dofs;
      if (order.empty()) throw CLI::ValidationError("--dofs", dofs_path + " has no EXTRN card (superelement DOF order)");
    } else {
      order = k.row_dofs;
      dof_model = model;
    }
    if (order.empty()) {
      throw CLI::ValidationError("--dofs", model_path + " has no DOF map: give the punch file with the EXTRN card (--dofs FILE.pch)");
    }
    if (static_cast<int64_t>(order.size()) != k.rows || k.rows != m.rows) {
      throw CLI::ValidationError("--dofs", "the DOF order has " + std::to_string(order.size()) + " entries but " + k.name +
                                               " is " + std::to_string(k.rows) + " x " + std::to_string(k.cols));
    }
    // [grid DOFs | scalar points (modal coordinates)], keeping the file's order within each.
    std::vector<int> perm;
    for (size_t i = 0; i < order.size(); ++i) if (order[i].component != 0) perm.push_back(static_cast<int>(i));
    const int nb = static_cast<int>(perm.size());
    for (size_t i = 0; i < order.size(); ++i) if (order[i].component == 0) perm.push_back(static_cast<int>(i));
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
    json out = {{"model", model_path}, {"dofs", dofs_path}, {"boundary_dofs", nb}, {"modes", n - nb},
                {"checks", ChecksJson(ch, check_tolerance)}};
    std::vector<double> fq;
    for (int j = nb; j < n; ++j) fq.push_back(std::sqrt(std::max(kr(j, j), 0.0)) / kTwoPi);
    out["fixed_interface_hz"] = fq;
    bool ok = ch.Max() <= check_tolerance;
    try {
      const Eigen::MatrixXd r = RigidBodyModes(dof_model, dofs, Centroid(dof_model, dofs));
      const double res = (kr * r).cwiseAbs().maxCoeff() / std::max(kr.cwiseAbs().maxCoeff() * r.cwiseAbs().maxCoeff(), 1e-300);
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
      std::cout << model_path << ": Craig-Bampton model with " << nb << " boundary DOFs and " << n - nb
                << " modal coordinates; checks " << (ok ? "passed" : "FAILED") << "\n  " << out["checks"].dump()
                << "\n  rigid body: " << out["rigid_body"].dump() << "\n";
    }
    return ok ? 0 : 1;
  }
};

ReduceCommands::ReduceCommands() : state_(std::make_unique<State>()) {}
ReduceCommands::~ReduceCommands() = default;

void ReduceCommands::Register(CLI::App& app) {
  State& s = *state_;
  s.reduce = app.add_subcommand("reduce", "Craig-Bampton reduction of an FE model onto node sets (SI units)");
  s.reduce->add_option("model", s.model_path,
                       "FE model with stiffness and mass: CalculiX job (.inp deck beside .sti/.mas/.dof), "
                       "or any file `fricrom info` reads")->required();
  s.reduce->add_option("--boundary", s.boundary, "Boundary node sets kept physical: SET[,SET...] (or 'none')");
  s.reduce->add_option("--boundary-nodes", s.boundary_nodes,
                       "Boundary nodes / Nastran grids by id: ID[,ID...] (all their DOFs, or --components)");
  s.reduce->add_option("--sets", s.sets_file,
                       "Deck with *NSET / *NODE NSET= node sets (Abaqus/CalculiX syntax) for --boundary");
  s.reduce->add_option("--mass-file", s.mass_file,
                       "Mass matrix from this file (any format `fricrom info` reads); stiffness from MODEL");
  s.reduce->add_option("--components", s.components, "Boundary components, e.g. 123 (default: all the model has)");
  s.reduce->add_option("--modes", s.modes, "Number of fixed-interface modes")->check(CLI::PositiveNumber);
  s.reduce->add_option("--cutoff-hz", s.cutoff_hz, "Keep every fixed-interface mode up to this frequency [Hz]")
      ->check(CLI::PositiveNumber);
  s.reduce->add_option("--shift-hz", s.shift_hz, "Negative spectral shift -(2 pi F)^2 for free-free interiors [Hz]")
      ->check(CLI::NonNegativeNumber);
  s.reduce->add_option("--modal-damping", s.modal_damping, "Modal damping ratio of the fixed-interface modes")
      ->check(CLI::Range(0.0, 1.0));
  s.reduce->add_option("--compare-modes", s.compare_modes,
                       "Full-model modes computed for the accuracy table (default: those below the cutoff, <= 60)")
      ->check(CLI::NonNegativeNumber);
  s.reduce->add_option("--check-tolerance", s.check_tolerance, "Tolerance of the structural checks")
      ->check(CLI::PositiveNumber);
  s.reduce->add_flag("--no-reference", s.no_reference,
                     "Skip the full-model references (eigenvalues, static load, rigid body): timing runs");
  s.reduce->add_option("--stiffness", s.stiffness_name, "Stiffness matrix name (default STIFFNESS, KAAX, ...)");
  s.reduce->add_option("--mass", s.mass_name, "Mass matrix name (default MASS, MAAX, ...)");
  s.reduce->add_option("--to", s.to, "Output reduced model OUT.h5 (written atomically)")->required();
  s.reduce->add_flag("--json", s.as_json, "Print one JSON object on stdout");
  s.reduce->add_flag("--quiet", s.quiet, "No progress lines on stderr");

  s.check = app.add_subcommand("check-reduced",
                               "Structural checks of a Craig-Bampton model (e.g. Nastran EXTSEOUT KXX/MXX)");
  s.check->add_option("model", s.model_path, "File with the reduced K and M (e.g. inboard.op4)")->required();
  s.check->add_option("--dofs", s.dofs_path, "File with the DOF order (punch with EXTRN and GRID cards)");
  s.check->add_option("--stiffness", s.stiffness_name, "Stiffness matrix name (default KXX, KAAX, ...)");
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
