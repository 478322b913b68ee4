// Reference quantities for judging a reduced model: the lowest modes of the full sparse model
// (ARPACK on the Cholesky-transformed operator of a CHOLMOD factor), eigenvalues of a dense reduced
// model, rigid-body modes and mass properties, and the structural checks of a given Craig-Bampton
// model.

// GCC 12 false -Wmaybe-uninitialized inside Eigen's eigensolvers (see craig_bampton.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "arpack_eigs.h"
#include "cholmod_factor.h"
#include "dense_modes.h"
#include "fricrom/reduction.h"
#include "fricrom/units.h"
#include "interior_modes.h"

namespace fricrom {
namespace {

using Clock = std::chrono::steady_clock;

double MaxAbsDiag(const Eigen::SparseMatrix<double>& a) {
  double m = 0.0;
  for (int k = 0; k < a.outerSize(); ++k) m = std::max(m, std::abs(a.coeff(k, k)));
  return m;
}

double MaxAbsEntry(const Eigen::MatrixXd& a) { return a.size() ? a.cwiseAbs().maxCoeff() : 0.0; }

void CheckFinite(const Eigen::SparseMatrix<double>& a, const char* what) {
  for (int k = 0; k < a.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw std::invalid_argument(std::string(what) + " holds a non-finite value at row " +
                                    std::to_string(it.row() + 1) + ", column " +
                                    std::to_string(it.col() + 1));
      }
    }
  }
}

}  // namespace

const char* ToString(ModalSolveStatus status) {
  switch (status) {
    case ModalSolveStatus::kSuccess:
      return "SUCCESS";
    case ModalSolveStatus::kFactorizationFailed:
      return "FACTORIZATION_FAILED";
    case ModalSolveStatus::kNotConverged:
      return "NOT_CONVERGED";
  }
  return "UNKNOWN";
}

bool ModalSolveOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (num_modes < 1) return fail("num_modes must be >= 1");
  if (!std::isfinite(shift) || shift > 0) return fail("shift must be finite and <= 0");
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return fail("tolerance must be >= 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (dense_max_size < 0) return fail("dense_max_size must be >= 0");
  return true;
}

ModalSolveResult SolveLowestModes(const Eigen::SparseMatrix<double>& stiffness,
                                  const Eigen::SparseMatrix<double>& mass,
                                  const ModalSolveOptions& options) {
  std::string err;
  if (!options.IsValid(&err)) throw std::invalid_argument("SolveLowestModes: " + err);
  const int n = static_cast<int>(stiffness.rows());
  if (n == 0 || stiffness.cols() != n || mass.rows() != n || mass.cols() != n) {
    throw std::invalid_argument("SolveLowestModes: K and M must be square, non-empty, same size");
  }
  CheckFinite(stiffness, "SolveLowestModes: K");
  CheckFinite(mass, "SolveLowestModes: M");
  const auto t0 = Clock::now();
  ModalSolveResult r;
  const int count = std::min(options.num_modes, n);
  // Candidate shifts: the given one, then (auto_shift) negative shifts of growing size relative
  // to the largest diagonal ratio, which makes K - sigma M positive definite for a free body.
  std::vector<double> shifts{options.shift};
  if (options.auto_shift) {
    const double scale = MaxAbsDiag(stiffness) / std::max(MaxAbsDiag(mass), 1e-300);
    for (const double f : {1e-8, 1e-6, 1e-4}) shifts.push_back(-f * scale);
  }
  // Dense also for a large share of the spectrum (slow for Lanczos; with massless DOFs there may
  // be fewer finite modes than asked for).
  const bool dense = n <= options.dense_max_size || count > n - 2 ||
                     (4 * count > n && n <= reduction_detail::kDenseFallbackMax);
  auto finish = [&](ModalSolveStatus st, const std::string& msg) {
    r.status = st;
    r.message = msg;
    r.frequencies_hz = r.lambda.unaryExpr(&HzFromEigenvalue);
    r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  };
  for (const double sigma : shifts) {
    r.shift_used = sigma;
    if (dense) {
      if (reduction_detail::DenseLowestModes(stiffness, mass, sigma, count, &r.lambda, &r.modes,
                                             nullptr)) {
        return finish(ModalSolveStatus::kSuccess, "dense eigensolver");
      }
      continue;
    }
    reduction_detail::CholeskyTransformOp op(stiffness, mass);
    if (!op.set_shift(sigma, &err)) continue;
    const reduction_detail::EigsResult e =
        reduction_detail::LowestEigs(op, count, options.tolerance, options.max_iterations);
    r.restarts = e.restarts;
    if (!e.converged) {
      if (n <= reduction_detail::kDenseFallbackMax &&
          reduction_detail::DenseLowestModes(stiffness, mass, sigma, count, &r.lambda, &r.modes,
                                             nullptr)) {
        return finish(ModalSolveStatus::kSuccess, "ARPACK: " + e.message + "; dense eigensolver");
      }
      return finish(ModalSolveStatus::kNotConverged, e.message);
    }
    r.lambda = e.lambda;
    r.modes = e.vectors;
    return finish(ModalSolveStatus::kSuccess, "");
  }
  return finish(ModalSolveStatus::kFactorizationFailed,
                "K - sigma M is not positive definite for any tried shift (is M positive "
                "semi-definite and K symmetric?)");
}

StaticCheckResult CompareStaticBodyLoad(const Eigen::SparseMatrix<double>& k,
                                        const Eigen::SparseMatrix<double>& m,
                                        const std::vector<DofId>& dofs, const ReducedModel& red,
                                        const Eigen::Vector3d& accel) {
  const Eigen::Index n = k.rows();
  if (static_cast<Eigen::Index>(dofs.size()) != n || m.rows() != n) {
    throw std::invalid_argument("CompareStaticBodyLoad: K, M and the DOF map differ in size");
  }
  const Eigen::Index nb = static_cast<Eigen::Index>(red.boundary_dofs.size());
  const Eigen::Index nq = red.normal_modes.cols();
  if (red.stiffness.rows() != nb + nq ||
      static_cast<Eigen::Index>(red.interior_dofs.size()) + nb != n) {
    throw std::invalid_argument("CompareStaticBodyLoad: reduced model does not match K");
  }
  StaticCheckResult out;
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int c = dofs[static_cast<size_t>(i)].component;
    if (c >= 1 && c <= 3) a(i) = accel(c - 1);
  }
  const Eigen::VectorXd f = m * a;
  if (!(f.cwiseAbs().maxCoeff() > 0.0)) {
    out.message =
        "the body load is zero (no translational DOFs with mass in the DOF map): "
        "nothing to compare";
    return out;
  }
  reduction_detail::CholmodFactor factor;
  std::string err;
  if (!factor.Factorize(k, &err)) {
    out.message = "full K not positive definite (free body?): " + err;
    return out;
  }
  Eigen::VectorXd u(n);
  factor.Solve(f, u);
  // Reduced load T^T f = [f_b + Psi^T f_i; Phi^T f_i].
  Eigen::VectorXd fb(nb), fi(static_cast<Eigen::Index>(red.interior_dofs.size()));
  for (Eigen::Index i = 0; i < nb; ++i) fb(i) = f(red.boundary_dofs[static_cast<size_t>(i)]);
  for (Eigen::Index i = 0; i < fi.size(); ++i) fi(i) = f(red.interior_dofs[static_cast<size_t>(i)]);
  Eigen::VectorXd fr(nb + nq);
  fr.head(nb) =
      fb + (red.constraint_modes.size() ? Eigen::VectorXd(red.constraint_modes.transpose() * fi)
                                        : Eigen::VectorXd::Zero(nb));
  if (nq > 0) fr.tail(nq) = red.normal_modes.transpose() * fi;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(red.stiffness);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    out.message = "reduced K not positive definite";
    return out;
  }
  const Eigen::VectorXd ur = ldlt.solve(fr);
  double diff = 0.0, scale = 0.0;
  for (Eigen::Index i = 0; i < nb; ++i) {
    const double full = u(red.boundary_dofs[static_cast<size_t>(i)]);
    diff = std::max(diff, std::abs(ur(i) - full));
    scale = std::max(scale, std::abs(full));
  }
  Eigen::VectorXd ui = Eigen::VectorXd::Zero(fi.size());
  if (red.constraint_modes.size()) ui += red.constraint_modes * ur.head(nb);
  if (nq > 0) ui += red.normal_modes * ur.tail(nq);
  double idiff = 0.0, iscale = 0.0;
  for (Eigen::Index i = 0; i < fi.size(); ++i) {
    const double full = u(red.interior_dofs[static_cast<size_t>(i)]);
    idiff = std::max(idiff, std::abs(ui(i) - full));
    iscale = std::max(iscale, std::abs(full));
  }
  out.interior_rel_error = iscale > 0 ? idiff / iscale : idiff;
  out.solved = true;
  out.max_displacement = scale;
  out.rel_error = scale > 0 ? diff / scale : diff;
  return out;
}

Eigen::VectorXd ReducedEigenvalues(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass) {
  if (stiffness.rows() != stiffness.cols() || mass.rows() != stiffness.rows() ||
      mass.cols() != stiffness.cols()) {
    throw std::invalid_argument("ReducedEigenvalues: K and M must be square and the same size");
  }
  if (stiffness.size() == 0) return {};
  if (!stiffness.allFinite() || !mass.allFinite()) {
    throw std::invalid_argument("ReducedEigenvalues: K or M holds non-finite values");
  }
  // Through a Cholesky factor of K - sigma M, not of M: a reduced mass matrix is only positive
  // semi-definite when boundary DOFs carry no mass (massless nodes, lumped masses without rotary
  // inertia); their infinite eigenvalues are dropped. sigma = 0 for a supported body, else a
  // negative shift (free body: K singular).
  const Eigen::SparseMatrix<double> k = stiffness.sparseView(), m = mass.sparseView();
  const double ratio = stiffness.diagonal().cwiseAbs().maxCoeff() /
                       std::max(mass.diagonal().cwiseAbs().maxCoeff(), 1e-300);
  Eigen::VectorXd lambda;
  Eigen::MatrixXd phi;
  std::string error;
  for (double sigma : {0.0, -1e-6 * ratio, -1e-3 * ratio, -ratio}) {
    if (reduction_detail::DenseLowestModes(k, m, sigma, static_cast<int>(stiffness.rows()), &lambda,
                                           &phi, &error)) {
      return lambda;
    }
  }
  throw std::invalid_argument("ReducedEigenvalues: " + error + " for every shift tried");
}

namespace {

// Rows = the system's unit axes in basic coordinates (u_local = axes * u_basic). Rectangular
// systems only (CORD2R), following the chain of reference systems.
Eigen::Matrix3d SystemAxes(const FeModel& model, int id, int depth = 0) {
  if (id == 0) return Eigen::Matrix3d::Identity();
  if (depth > 32) throw std::invalid_argument("RigidBodyModes: coordinate system chain too deep");
  const CoordinateSystem* cs = nullptr;
  for (const CoordinateSystem& c : model.systems) {
    if (c.id == id) cs = &c;
  }
  if (!cs) {
    throw std::invalid_argument("RigidBodyModes: coordinate system " + std::to_string(id) +
                                " is not defined in " + model.source);
  }
  const Eigen::Matrix3d ref = SystemAxes(model, cs->reference, depth + 1);
  // Points of the card are in the reference system; directions to basic by ref^T.
  const Eigen::Vector3d ez = ref.transpose() * (cs->b - cs->a).normalized();
  const Eigen::Vector3d ey = ez.cross(ref.transpose() * (cs->c - cs->a)).normalized();
  const Eigen::Vector3d ex = ey.cross(ez);
  Eigen::Matrix3d axes;
  axes.row(0) = ex.transpose();
  axes.row(1) = ey.transpose();
  axes.row(2) = ez.transpose();
  return axes;
}

}  // namespace

Eigen::MatrixXd RigidBodyModes(const FeModel& model, const std::vector<DofId>& dofs,
                               const Eigen::Vector3d& reference) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(dofs.size()), 6);
  const FeNode* last = nullptr;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  for (size_t i = 0; i < dofs.size(); ++i) {
    const DofId& d = dofs[i];
    if (d.component == 0) continue;  // scalar point: no rigid motion
    if (d.component < 1 || d.component > 6) {
      throw std::invalid_argument("RigidBodyModes: component " + std::to_string(d.component) +
                                  " of node " + std::to_string(d.node) + " is not 0..6");
    }
    if (!last || last->id != d.node) {
      last = model.FindNode(d.node);
      if (!last) {
        throw std::invalid_argument("RigidBodyModes: node " + std::to_string(d.node) +
                                    " has no coordinates in " + model.source);
      }
      if (last->position_system != 0) {
        throw std::invalid_argument(
            "RigidBodyModes: node " + std::to_string(d.node) + " gives its position in system " +
            std::to_string(last->position_system) + " (only basic positions are supported)");
      }
      axes = SystemAxes(model, last->displacement_system);
    }
    const Eigen::Vector3d x = last->xyz - reference;
    // Basic-frame rigid motion of the node: translation t + theta x x, rotation theta.
    Eigen::Matrix<double, 3, 6> trans = Eigen::Matrix<double, 3, 6>::Zero();
    Eigen::Matrix<double, 3, 6> rot = Eigen::Matrix<double, 3, 6>::Zero();
    for (int a = 0; a < 3; ++a) {
      trans(a, a) = 1.0;
      trans.col(3 + a) = Eigen::Vector3d::Unit(a).cross(x);
      rot(a, 3 + a) = 1.0;
    }
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    if (d.component <= 3) {
      r.row(row) = (axes * trans).row(d.component - 1);
    } else {
      r.row(row) = (axes * rot).row(d.component - 4);
    }
  }
  return r;
}

MassProperties MassPropertiesFromRigidMass(const Eigen::Matrix<double, 6, 6>& mrr) {
  MassProperties p;
  p.mass = mrr.topLeftCorner<3, 3>().trace() / 3.0;
  if (!(p.mass > 0)) throw std::invalid_argument("MassPropertiesFromRigidMass: mass <= 0");
  // First moments S = sum m x from the translation-rotation coupling (e_a . (e_b x x)).
  const Eigen::Vector3d first(mrr(1, 5), mrr(2, 3), mrr(0, 4));
  p.center = first / p.mass;
  const Eigen::Matrix3d j_origin = mrr.bottomRightCorner<3, 3>();
  const Eigen::Vector3d& c = p.center;
  p.inertia_at_center =
      j_origin - p.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  return p;
}

CraigBamptonChecks CheckCraigBamptonMatrices(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m,
                                             int nb) {
  if (k.rows() != k.cols() || m.rows() != k.rows() || m.cols() != k.cols() || nb < 0 ||
      nb > k.rows()) {
    throw std::invalid_argument(
        "CheckCraigBamptonMatrices: K and M must be square, the same size, and 0 <= nb <= n");
  }
  const int n = static_cast<int>(k.rows()), nq = n - nb;
  CraigBamptonChecks ch;
  const double kmax = MaxAbsEntry(k), mmax = MaxAbsEntry(m);
  ch.stiffness_symmetry = kmax > 0 ? MaxAbsEntry(Eigen::MatrixXd(k - k.transpose())) / kmax : 0.0;
  ch.mass_symmetry = mmax > 0 ? MaxAbsEntry(Eigen::MatrixXd(m - m.transpose())) / mmax : 0.0;
  if (nq > 0 && nb > 0) {
    ch.stiffness_coupling = kmax > 0 ? std::max(MaxAbsEntry(k.topRightCorner(nb, nq)),
                                                MaxAbsEntry(k.bottomLeftCorner(nq, nb))) /
                                           kmax
                                     : 0.0;
  }
  if (nq > 0) {
    const Eigen::MatrixXd mqq = m.bottomRightCorner(nq, nq);
    ch.modal_mass = MaxAbsEntry(Eigen::MatrixXd(mqq - Eigen::MatrixXd::Identity(nq, nq)));
    Eigen::MatrixXd kqq = k.bottomRightCorner(nq, nq);
    const double dmax = std::max(kqq.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    kqq.diagonal().setZero();
    ch.modal_stiffness = MaxAbsEntry(kqq) / dmax;
  }
  return ch;
}

}  // namespace fricrom
