// Loss factor of an HbmSystem solution with its exact gradient (the bounds' η objective).
#include <numbers>

#include "fricrom/hbm_system.h"

namespace fricrom {
namespace {

// The linear part of the residual, R = Z(ω) x − F̂exc + F̂c(x, α), needed to separate the contact
// forces F̂c from R for the loss factor.
struct LinearPart {
  Eigen::MatrixXd z;
  Eigen::VectorXd excitation;
};

LinearPart MakeLinearPart(const HbmSystem& sys, double omega) {
  const Model& m = sys.model();
  const int n = sys.num_dofs(), nx = sys.num_unknowns(), harmonics = sys.options().harmonics;
  LinearPart lp;
  lp.z.setZero(nx, nx);
  lp.z.block(0, 0, n, n) = m.stiffness;
  for (int h = 1; h <= harmonics; ++h) {
    const int ia = sys.Index(0, 2 * h - 1), ib = sys.Index(0, 2 * h);
    const double hw = h * omega;
    const Eigen::MatrixXd kd = m.stiffness - hw * hw * m.mass;
    lp.z.block(ia, ia, n, n) = kd;
    lp.z.block(ib, ib, n, n) = kd;
    lp.z.block(ia, ib, n, n) = hw * m.damping;
    lp.z.block(ib, ia, n, n) = -hw * m.damping;
  }
  lp.excitation.setZero(nx);
  for (const HarmonicLoad& load : m.loads) {
    if (load.harmonic == 0) {
      lp.excitation.segment(0, n) += load.cos;
    } else {
      lp.excitation.segment(sys.Index(0, 2 * load.harmonic - 1), n) += load.cos;
      lp.excitation.segment(sys.Index(0, 2 * load.harmonic), n) += load.sin;
    }
  }
  return lp;
}

// Loss factor η = (W_visc + W_fric) / (2π U_pot) (as HbmSystem::Energies) and, when the
// evaluation carries the Jacobians, its exact gradient with respect to x and α. Works on the
// global contact force vector F̂c = R − Z x + F̂exc: for every contact, Σ_dofs F̂c·x̂ equals
// Σ (T̂·û + N̂·v̂), so the per-contact sums of Energies become sums over DOFs.
double LossFactorOf(const HbmSystem& sys, const LinearPart& lp, double omega,
                    const Eigen::VectorXd& x, const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                    Eigen::VectorXd* grad_alpha) {
  const Model& m = sys.model();
  const int n = sys.num_dofs(), nx = sys.num_unknowns(), harmonics = sys.options().harmonics;
  const double pi = std::numbers::pi;
  const Eigen::VectorXd fc = e.residual - lp.z * x + lp.excitation;
  Eigen::VectorXd sx = Eigen::VectorXd::Zero(nx);   // S x: W_fric = π F̂cᵀ S x
  Eigen::VectorXd stf = Eigen::VectorXd::Zero(nx);  // Sᵀ F̂c
  Eigen::VectorXd dx = x;                           // D x: U_cont = ½ F̂cᵀ D x
  dx.segment(0, n).setZero();
  Eigen::VectorXd g_w = Eigen::VectorXd::Zero(nx), g_u = Eigen::VectorXd::Zero(nx);
  double w_visc = 0.0, u_lin = 0.0;
  for (int h = 1; h <= harmonics; ++h) {
    const int ia = sys.Index(0, 2 * h - 1), ib = sys.Index(0, 2 * h);
    const auto a = x.segment(ia, n), b = x.segment(ib, n);
    const Eigen::VectorXd ca = m.damping * a, cb = m.damping * b;
    const Eigen::VectorXd ka = m.stiffness * a, kb = m.stiffness * b;
    w_visc += pi * h * h * omega * (a.dot(ca) + b.dot(cb));
    u_lin += 0.5 * (a.dot(ka) + b.dot(kb));
    sx.segment(ia, n) = h * b;
    sx.segment(ib, n) = -h * a;
    stf.segment(ia, n) = -h * fc.segment(ib, n);
    stf.segment(ib, n) = h * fc.segment(ia, n);
    g_w.segment(ia, n) = 2.0 * pi * h * h * omega * ca;
    g_w.segment(ib, n) = 2.0 * pi * h * h * omega * cb;
    g_u.segment(ia, n) = ka;
    g_u.segment(ib, n) = kb;
  }
  const double w = w_visc + pi * fc.dot(sx);
  const double u = u_lin + 0.5 * fc.dot(dx);
  const double eta = w / (2.0 * pi * u);
  if (grad_x != nullptr) {
    const Eigen::MatrixXd dfc = e.jacobian - lp.z;  // ∂F̂c/∂x
    g_w += pi * (dfc.transpose() * sx + stf);
    Eigen::VectorXd dfc_dx = fc;
    dfc_dx.segment(0, n).setZero();
    g_u += 0.5 * (dfc.transpose() * dx + dfc_dx);
    *grad_x = (g_w - 2.0 * pi * eta * g_u) / (2.0 * pi * u);
    *grad_alpha = (pi * e.alpha_jacobian.transpose() * sx -
                   2.0 * pi * eta * 0.5 * e.alpha_jacobian.transpose() * dx) /
                  (2.0 * pi * u);
  }
  return eta;
}

}  // namespace

double HbmSystem::LossFactor(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                             const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                             Eigen::VectorXd* grad_alpha) const {
  (void)alpha;  // F̂c is read off the residual in `e`
  const LinearPart lp = MakeLinearPart(*this, omega);
  return LossFactorOf(*this, lp, omega, x, e, grad_x, grad_alpha);
}

}  // namespace fricrom
