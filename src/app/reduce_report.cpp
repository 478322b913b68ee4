#include "app/reduce_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "app/cli_common.h"
#include "fricrom/reduced_body.h"
#include "fricrom/units.h"

namespace fricrom::app {
namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double RelDiff(const MassProperties& a, const MassProperties& b) {
  const double dm = std::abs(a.mass - b.mass) / a.mass;
  const double size = std::sqrt(std::max(a.inertia_at_center.trace() / a.mass, 1e-300));
  const double dc = (a.center - b.center).norm() / size;
  const double di = (a.inertia_at_center - b.inertia_at_center).cwiseAbs().maxCoeff() /
                    std::max(a.inertia_at_center.cwiseAbs().maxCoeff(), 1e-300);
  return NanMax(NanMax(dm, dc), di);
}

// Relative residual of K R (R: rigid-body fields): small for a body free of supports.
double RigidResidual(const Eigen::SparseMatrix<double>& k, const Eigen::MatrixXd& r) {
  const Eigen::MatrixXd kr = k * r;
  double kmax = 0.0;
  for (int c = 0; c < k.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it)
      kmax = NanMax(kmax, std::abs(it.value()));
  return kr.cwiseAbs().maxCoeff() / std::max(kmax * r.cwiseAbs().maxCoeff(), 1e-300);
}

// Full-model modes against the reduced eigenvalues; fills the table and the failure reason.
void EigenTable(const ReferenceInput& in, const Eigen::VectorXd& reduced_lambda,
                const std::function<void(const std::string&)>& progress, ReferenceReport* rep) {
  const CraigBamptonSummary& s = *in.summary;
  const double f_top =
      in.cutoff_hz > 0 ? in.cutoff_hz : (s.modes > 0 ? s.frequencies_hz.back() : 0.0);
  int count = in.compare_modes;
  if (count < 0) {
    count = 0;
    for (Eigen::Index j = 0; j < reduced_lambda.size(); ++j)
      count += HzFromEigenvalue(reduced_lambda(j)) <= f_top;
    count = std::clamp(count, 1, 60);
  }
  count = std::min<int>(count, static_cast<int>(reduced_lambda.size()));
  if (count == 0) return;
  progress("reference: " + std::to_string(count) + " lowest modes of the full model");
  ModalSolveOptions mo;
  mo.num_modes = count;
  const ModalSolveResult full = SolveLowestModes(in.k->real, in.m->real, mo);
  rep->timings["full_model_modes_s"] = full.wall_s;
  if (full.status != ModalSolveStatus::kSuccess) {
    rep->failure = "full-model modes: " + std::string(ToString(full.status)) + ": " + full.message;
    return;
  }
  rep->shift = full.shift_used;
  // Rigid-body (zero) modes: compared absolutely against the highest eigenvalue of the table or
  // of the kept fixed-interface modes (a table of rigid modes only has no elastic scale).
  const double lam_scale = std::max({std::abs(full.lambda(full.lambda.size() - 1)),
                                     std::abs(full.shift_used), EigenvalueFromHz(f_top), 1e-300});
  for (int j = 0; j < full.lambda.size(); ++j) {
    const double lf = full.lambda(j), lr = reduced_lambda(j);
    const bool rigid_mode = std::abs(lf) < 1e-8 * lam_scale;
    const double ff = HzFromEigenvalue(lf), fr = HzFromEigenvalue(lr);
    const double e = rigid_mode ? std::abs(lr - lf) / lam_scale : std::abs(fr - ff) / ff;
    rep->table.push_back({{"mode", j + 1},
                          {"full_hz", ff},
                          {"reduced_hz", fr},
                          {"rel_error", e},
                          {"rigid_body", rigid_mode}});
    rep->max_err = NanMax(rep->max_err, e);
    if (ff <= 0.25 * f_top) rep->max_err_quarter = NanMax(rep->max_err_quarter, e);
    if (!std::isfinite(e) || !std::isfinite(lr) || !std::isfinite(lf)) {
      if (rep->failure.empty())
        rep->failure =
            "non-finite value in the eigenvalue table (mode " + std::to_string(j + 1) + ")";
    } else if (!rigid_mode && lr < lf * (1.0 - 2e-6) && rep->failure.empty()) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "reduced mode %d at %.9g Hz lies below the full model's %.9g Hz: a "
                    "Rayleigh-Ritz bound is violated, the reduced model is wrong",
                    j + 1, fr, ff);
      rep->failure = buf;
    }
  }
}

// Free body: rigid-body fields annihilated by K; full vs reduced mass properties.
json RigidBodyCheck(const ReferenceInput& in, const Eigen::VectorXd& reduced_lambda) {
  const FeModel& model = *in.model;
  const FeMatrix& k = *in.k;
  const ReducedModel& red = *in.reduced;
  const int nb = static_cast<int>(in.boundary->indices.size());
  const int nq = static_cast<int>(red.stiffness.rows()) - nb;
  try {
    const Eigen::Vector3d ref = Centroid(model, k.row_dofs);
    const Eigen::MatrixXd r_full = RigidBodyModes(model, k.row_dofs, ref);
    const double res = RigidResidual(k.real, r_full);
    if (!(res < 1e-8)) return {{"free_body", false}, {"full_K_R_residual", res}};
    const Eigen::Matrix<double, 6, 6> mrr_full = r_full.transpose() * (in.m->real * r_full);
    Eigen::MatrixXd r_red = Eigen::MatrixXd::Zero(nb + nq, 6);
    for (int i = 0; i < nb; ++i) r_red.row(i) = r_full.row(in.boundary->indices[i]);
    const Eigen::Matrix<double, 6, 6> mrr_red = r_red.transpose() * red.mass * r_red;
    const double res_red =
        (red.stiffness * r_red).cwiseAbs().maxCoeff() /
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
    return {{"free_body", true},
            {"full_K_R_residual", res},
            {"reduced_K_R_residual", res_red},
            {"reduced_zero_modes", zero_modes},
            {"full", MassJson(pf)},
            {"reduced", MassJson(pr)},
            {"mass_properties_rel_diff", dev},
            {"passed", zero_modes == 6 && res_red < 1e-8 && dev < 1e-8}};
  } catch (const std::invalid_argument& e) {
    return {{"free_body", nullptr}, {"skipped", e.what()}};
  }
}

}  // namespace

json ChecksJson(const CraigBamptonChecks& c, double tolerance) {
  return {{"stiffness_symmetry", c.stiffness_symmetry},
          {"mass_symmetry", c.mass_symmetry},
          {"stiffness_coupling_Kbq", c.stiffness_coupling},
          {"modal_mass_Mqq_minus_I", c.modal_mass},
          {"modal_stiffness_Kqq_minus_diag", c.modal_stiffness},
          {"eigen_residual", c.eigen_residual},
          {"tolerance", tolerance},
          {"passed", c.Max() <= tolerance}};
}

json MassJson(const MassProperties& p) {
  json inertia = json::array();
  for (int i = 0; i < 3; ++i) {
    inertia.push_back(
        {p.inertia_at_center(i, 0), p.inertia_at_center(i, 1), p.inertia_at_center(i, 2)});
  }
  // Units are the model file's (kg, m, kg m^2 for SI models such as fricrom's meshes).
  return {{"mass", p.mass},
          {"center", {p.center.x(), p.center.y(), p.center.z()}},
          {"inertia_at_center", inertia}};
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

ReferenceReport CompareWithFullModel(const ReferenceInput& in,
                                     const std::function<void(const std::string&)>& progress) {
  ReferenceReport rep;
  Eigen::VectorXd reduced_lambda;
  try {
    reduced_lambda = ReducedEigenvalues(in.reduced->stiffness, in.reduced->mass);
  } catch (const std::invalid_argument& e) {
    rep.failure = std::string("eigenvalues of the reduced model: ") + e.what();
    return rep;
  }
  rep.reduced_infinite = static_cast<int>(in.reduced->stiffness.rows() - reduced_lambda.size());
  EigenTable(in, reduced_lambda, progress, &rep);
  if (!in.model->nodes.empty()) rep.rigid = RigidBodyCheck(in, reduced_lambda);
  // Interior load: uniform acceleration along (1,1,1)/sqrt(3) on a supported body.
  const bool free_body = !rep.rigid.is_null() && rep.rigid.value("free_body", false) == true;
  if (!free_body && in.k->row_dofs.empty()) {
    rep.static_check = {{"solved", false},
                        {"message", "no DOF map: which rows translate is unknown, no body load"}};
  } else if (!free_body) {
    progress("reference: static body load on the full model (CHOLMOD)");
    const auto ts = Clock::now();
    const StaticCheckResult st =
        CompareStaticBodyLoad(in.k->real, in.m->real, in.k->row_dofs, *in.reduced,
                              Eigen::Vector3d::Constant(1.0 / std::sqrt(3.0)));
    rep.timings["full_model_static_s"] = Since(ts);
    const auto value = [&](double v) { return st.solved ? json(v) : json(nullptr); };
    rep.static_check = {{"load", "uniform acceleration 1 m/s^2 along (1,1,1)/sqrt(3)"},
                        {"solved", st.solved},
                        {"rel_error_at_boundary", value(st.rel_error)},
                        {"rel_error_interior_recovered", value(st.interior_rel_error)},
                        {"max_boundary_displacement_m", st.max_displacement},
                        {"message", st.message}};
  }
  return rep;
}

void WriteReducedModel(const std::string& path, const ReducedFileInput& in) {
  // One implementation with the library (ReducedBody, FixedInterfaceModalDamping): the file
  // ReadReducedBody and ReduceFeBody's cache read.
  const ReducedBody body =
      MakeReducedBody(*in.model, *in.mass, *in.boundary, *in.reduced, in.sets, in.modal_damping);
  ReducedBodyFileInfo info;
  info.status = ToString(in.summary->status);
  info.boundary_label = in.boundary_label;
  info.cutoff_hz = in.cutoff_hz;
  info.full_dofs = in.summary->num_dofs;
  info.modal_damping_ratio = in.modal_damping;
  for (const json& row : in.report->at("eigen_comparison")) {
    info.full_hz.push_back(row["full_hz"]);
    info.reduced_hz.push_back(row["reduced_hz"]);
    info.rel_error.push_back(row["rel_error"]);
  }
  info.checks_json = in.report->at("checks").dump();
  WriteReducedBody(body, path, info);
}

}  // namespace fricrom::app
