// Response bounds by interior-point optimisation (Ipopt) over [x̂, α] subject to R = 0.
// Ipopt stays inside this file; the public header only needs Eigen.
#include "fricrom/bounds.h"

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpSolveStatistics.hpp>
#include <coin/IpTNLP.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "fricrom/frf.h"
#include "fricrom/solve.h"

namespace fricrom {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// A returned point counts as a solution only if ‖R‖ ≤ kFeasibility · ResidualScale().
constexpr double kFeasibility = 1e-6;

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
    if (load.harmonic > harmonics) continue;
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
double LossFactor(const HbmSystem& sys, const LinearPart& lp, double omega,
                  const Eigen::VectorXd& x, const HbmEvaluation& e, Eigen::VectorXd* grad_x,
                  Eigen::VectorXd* grad_alpha) {
  const Model& m = sys.model();
  const int n = sys.num_dofs(), nx = sys.num_unknowns(), harmonics = sys.options().harmonics;
  const double pi = std::numbers::pi;
  const Eigen::VectorXd fc = e.residual - lp.z * x + lp.excitation;
  Eigen::VectorXd sx = Eigen::VectorXd::Zero(nx);  // S x: W_fric = π F̂cᵀ S x
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

struct RunSetup {
  const HbmSystem* system = nullptr;
  const LinearPart* linear = nullptr;
  double omega = 0.0;
  BoundsOptions::Objective objective = BoundsOptions::kAmplitude;
  double sign = 1.0;             // +1 minimises the objective, −1 maximises it
  double objective_scale = 1.0;  // objective divided by this
  Eigen::VectorXd x_scale;       // x = x_scale ∘ z
  double residual_scale = 1.0;   // constraints g = R / residual_scale
};

// The NLP in scaled variables z = [x ⊘ x_scale, α], constraints g = R / residual_scale, dense
// Jacobian, quasi-Newton Hessian.
class BoundsNlp : public Ipopt::TNLP {
 public:
  BoundsNlp(const RunSetup& setup, const Eigen::VectorXd& x0, const Eigen::VectorXd& alpha0)
      : s_(setup),
        nx_(setup.system->num_unknowns()),
        nc_(setup.system->num_contacts()),
        x0_(x0),
        alpha0_(alpha0) {}

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                    Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = nx_ + nc_;
    m = nx_;
    nnz_jac_g = nx_ * (nx_ + nc_);
    nnz_h_lag = 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index, Ipopt::Number* z_l, Ipopt::Number* z_u, Ipopt::Index,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override {
    constexpr double kInf = 2e19;  // Ipopt's default nlp_upper_bound_inf is 1e19
    for (int i = 0; i < nx_; ++i) {
      z_l[i] = -kInf;
      z_u[i] = kInf;
      g_l[i] = g_u[i] = 0.0;
    }
    for (int c = 0; c < nc_; ++c) {
      z_l[nx_ + c] = -1.0;
      z_u[nx_ + c] = 1.0;
    }
    return true;
  }

  bool get_starting_point(Ipopt::Index, bool init_z, Ipopt::Number* z, bool init_z_bounds,
                          Ipopt::Number*, Ipopt::Number*, Ipopt::Index, bool init_lambda,
                          Ipopt::Number*) override {
    if (!init_z || init_z_bounds || init_lambda) return false;
    for (int i = 0; i < nx_; ++i) z[i] = x0_[i] / s_.x_scale[i];
    for (int c = 0; c < nc_; ++c) z[nx_ + c] = alpha0_[c];
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number* z, bool new_z, Ipopt::Number& f) override {
    if (s_.objective == BoundsOptions::kAmplitude) {
      const int ia = AmplitudeIndex(1), ib = AmplitudeIndex(2);
      const double a = z[ia] * s_.x_scale[ia], b = z[ib] * s_.x_scale[ib];
      f = s_.sign * (a * a + b * b) / s_.objective_scale;
      return std::isfinite(f);
    }
    if (!Update(z, new_z, false)) return false;
    f = s_.sign * LossFactor(*s_.system, *s_.linear, s_.omega, x_, eval_, nullptr, nullptr) /
        s_.objective_scale;
    return std::isfinite(f);
  }

  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* z, bool new_z,
                   Ipopt::Number* grad) override {
    std::fill(grad, grad + n, 0.0);
    if (s_.objective == BoundsOptions::kAmplitude) {
      for (int j : {1, 2}) {
        const int i = AmplitudeIndex(j);
        grad[i] = s_.sign * 2.0 * z[i] * s_.x_scale[i] * s_.x_scale[i] / s_.objective_scale;
      }
      return true;
    }
    if (!Update(z, new_z, true)) return false;
    Eigen::VectorXd gx, ga;
    LossFactor(*s_.system, *s_.linear, s_.omega, x_, eval_, &gx, &ga);
    for (int i = 0; i < nx_; ++i) grad[i] = s_.sign * gx[i] * s_.x_scale[i] / s_.objective_scale;
    for (int c = 0; c < nc_; ++c) grad[nx_ + c] = s_.sign * ga[c] / s_.objective_scale;
    return gx.allFinite() && ga.allFinite();
  }

  bool eval_g(Ipopt::Index, const Ipopt::Number* z, bool new_z, Ipopt::Index,
              Ipopt::Number* g) override {
    if (!Update(z, new_z, false)) return false;
    for (int i = 0; i < nx_; ++i) g[i] = eval_.residual[i] / s_.residual_scale;
    return true;
  }

  bool eval_jac_g(Ipopt::Index, const Ipopt::Number* z, bool new_z, Ipopt::Index, Ipopt::Index,
                  Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override {
    const int n = nx_ + nc_;
    if (values == nullptr) {  // dense structure, row-major
      for (int i = 0; i < nx_; ++i) {
        for (int j = 0; j < n; ++j) {
          rows[i * n + j] = i;
          cols[i * n + j] = j;
        }
      }
      return true;
    }
    if (!Update(z, new_z, true)) return false;
    for (int i = 0; i < nx_; ++i) {
      for (int j = 0; j < nx_; ++j) {
        values[i * n + j] = eval_.jacobian(i, j) * s_.x_scale[j] / s_.residual_scale;
      }
      for (int c = 0; c < nc_; ++c) {
        values[i * n + nx_ + c] = eval_.alpha_jacobian(i, c) / s_.residual_scale;
      }
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index, const Ipopt::Number* z,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    status_ = status;
    finalized_ = true;
    Unscale(z, &x_final_, &alpha_final_);
  }

  bool finalized() const { return finalized_; }
  Ipopt::SolverReturn status() const { return status_; }
  const Eigen::VectorXd& x_final() const { return x_final_; }
  const Eigen::VectorXd& alpha_final() const { return alpha_final_; }

 private:
  int AmplitudeIndex(int coefficient) const {
    return s_.system->Index(s_.system->model().response_dof, coefficient);
  }

  // α is clamped to [−1, 1]: Ipopt may relax the bounds by a hair.
  void Unscale(const Ipopt::Number* z, Eigen::VectorXd* x, Eigen::VectorXd* alpha) const {
    x->resize(nx_);
    alpha->resize(nc_);
    for (int i = 0; i < nx_; ++i) (*x)[i] = z[i] * s_.x_scale[i];
    for (int c = 0; c < nc_; ++c) (*alpha)[c] = std::clamp(z[nx_ + c], -1.0, 1.0);
  }

  // Evaluates R (and the Jacobians when asked) at z unless the cache already holds them.
  bool Update(const Ipopt::Number* z, bool new_z, bool jacobians) {
    if (new_z || !have_residual_) {
      have_residual_ = have_jacobians_ = false;
      Unscale(z, &x_, &alpha_);
    }
    if (have_residual_ && (have_jacobians_ || !jacobians)) return eval_ok_;
    HbmRequest req;
    req.jacobian = req.alpha_jacobian = jacobians;
    try {
      s_.system->Evaluate(x_, s_.omega, alpha_, req, &eval_);
      eval_ok_ = eval_.residual.allFinite() &&
                 (!jacobians || (eval_.jacobian.allFinite() && eval_.alpha_jacobian.allFinite()));
    } catch (const std::exception&) {  // never let an exception cross Ipopt
      eval_ok_ = false;
    }
    have_residual_ = true;
    have_jacobians_ = jacobians;
    return eval_ok_;
  }

  RunSetup s_;
  int nx_, nc_;
  Eigen::VectorXd x0_, alpha0_;
  Eigen::VectorXd x_, alpha_;
  HbmEvaluation eval_;
  bool have_residual_ = false, have_jacobians_ = false, eval_ok_ = false;
  bool finalized_ = false;
  Ipopt::SolverReturn status_ = Ipopt::UNASSIGNED;
  Eigen::VectorXd x_final_, alpha_final_;
};

const char* SolverReturnText(Ipopt::SolverReturn r) {
  switch (r) {
    case Ipopt::SUCCESS: return "optimal point found";
    case Ipopt::MAXITER_EXCEEDED: return "maximum number of iterations exceeded";
    case Ipopt::CPUTIME_EXCEEDED: return "maximum CPU time exceeded";
    case Ipopt::STOP_AT_TINY_STEP: return "search direction became too small";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT: return "solved to acceptable level only";
    case Ipopt::LOCAL_INFEASIBILITY: return "converged to a point of local infeasibility";
    case Ipopt::USER_REQUESTED_STOP: return "stopped by the user";
    case Ipopt::FEASIBLE_POINT_FOUND: return "feasible point found";
    case Ipopt::DIVERGING_ITERATES: return "iterates diverging";
    case Ipopt::RESTORATION_FAILURE: return "restoration phase failed";
    case Ipopt::ERROR_IN_STEP_COMPUTATION: return "error in step computation";
    case Ipopt::INVALID_NUMBER_DETECTED: return "invalid number in an evaluation";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM: return "too few degrees of freedom";
    case Ipopt::INVALID_OPTION: return "invalid option";
    case Ipopt::OUT_OF_MEMORY: return "out of memory";
    case Ipopt::INTERNAL_ERROR: return "internal error";
    case Ipopt::UNASSIGNED: break;
  }
  return "no result";
}

BoundStatus MapStatus(Ipopt::SolverReturn r) {
  switch (r) {
    case Ipopt::SUCCESS: return BoundStatus::kConverged;
    case Ipopt::MAXITER_EXCEEDED:
    case Ipopt::CPUTIME_EXCEEDED: return BoundStatus::kMaxIterations;
    case Ipopt::LOCAL_INFEASIBILITY: return BoundStatus::kInfeasible;
    default: return BoundStatus::kFailed;
  }
}

std::vector<ContactRegime> Regimes(const HbmSystem& sys, const Eigen::VectorXd& x, double omega,
                                   const Eigen::VectorXd& alpha) {
  std::vector<ContactRegime> out;
  for (const ContactHistory& h : sys.ContactHistories(x, omega, alpha)) out.push_back(h.regime);
  return out;
}

double ResidualNorm(const HbmSystem& sys, const Eigen::VectorXd& x, double omega,
                    const Eigen::VectorXd& alpha) {
  HbmEvaluation e;
  sys.Evaluate(x, omega, alpha, HbmRequest{}, &e);
  return e.residual.norm() / sys.ResidualScale();
}

// Fills the derived fields of a solution (x, α set).
void Describe(const HbmSystem& sys, double omega, BoundSolution* s) {
  s->amplitude = sys.Amplitude(s->x);
  s->residual = ResidualNorm(sys, s->x, omega, s->alpha);
  s->loss_factor = sys.Energies(s->x, omega, s->alpha).loss_factor();
  s->regimes = Regimes(sys, s->x, omega, s->alpha);
}

// A converged harmonic-balance solution at α to start from: SolveAtFrequencies at f, then
// Newton from the other seeds' starts, then SolveAtFrequencies on a ramp up to f (its
// continuation fallback follows the branch).
bool StartSolution(const HbmSystem& sys, double freq_hz, const Eigen::VectorXd& alpha,
                   const std::vector<Eigen::VectorXd>& other_starts, Eigen::VectorXd* x) {
  const FrfOptions frf;
  std::vector<FrfPoint> pts = SolveAtFrequencies(sys, alpha, {freq_hz}, frf);
  if (pts.back().status == SolverStatus::kConverged) {
    *x = pts.back().x;
    return true;
  }
  const HbmAtFrequency at(sys, kTwoPi * freq_hz, alpha);
  for (auto it = other_starts.rbegin(); it != other_starts.rend(); ++it) {
    *x = *it;
    if (SolveNewton(at, frf.newton, x).IsSolutionUsable()) return true;
  }
  std::vector<double> ramp;
  for (int k = 10; k >= 0; --k) ramp.push_back(freq_hz * (1.0 - 0.005 * k));
  pts = SolveAtFrequencies(sys, alpha, ramp, frf);
  if (pts.back().status == SolverStatus::kConverged) {
    *x = pts.back().x;
    return true;
  }
  return false;
}

std::string FormatVector(const Eigen::VectorXd& v) {
  std::ostringstream os;
  os << "[";
  for (int i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

// One optimisation run from a feasible start; the result is verified (and polished by Newton at
// the final α so that R = 0 holds to the harmonic-balance tolerance).
BoundSolution Run(Ipopt::IpoptApplication& app, const RunSetup& setup, const Eigen::VectorXd& x0,
                  const Eigen::VectorXd& alpha0, int seed) {
  const HbmSystem& sys = *setup.system;
  BoundSolution out;
  out.seed = seed;
  Ipopt::SmartPtr<BoundsNlp> nlp = new BoundsNlp(setup, x0, alpha0);
  const Ipopt::ApplicationReturnStatus rc = app.OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(nlp));
  Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app.Statistics();
  if (Ipopt::IsValid(stats)) out.iterations = stats->IterationCount();
  if (!nlp->finalized()) {
    out.status = BoundStatus::kFailed;
    out.message = "Ipopt stopped before a solution (return code " +
                  std::to_string(static_cast<int>(rc)) + ")";
    out.x = x0;
    out.alpha = alpha0;
    Describe(sys, setup.omega, &out);
    return out;
  }
  out.status = MapStatus(nlp->status());
  out.message = std::string("Ipopt: ") + SolverReturnText(nlp->status());
  out.x = nlp->x_final();
  out.alpha = nlp->alpha_final();
  if (!out.x.allFinite()) {
    out.status = BoundStatus::kFailed;
    out.message += "; non-finite iterate";
    out.x = x0;
    out.alpha = alpha0;
    Describe(sys, setup.omega, &out);
    return out;
  }
  // Polish: Newton on R(·, α) = 0 at the final α from the optimiser's x.
  Eigen::VectorXd polished = out.x;
  const NewtonSummary ns =
      SolveNewton(HbmAtFrequency(sys, setup.omega, out.alpha), NewtonOptions{}, &polished);
  if (ns.IsSolutionUsable() &&
      std::abs(sys.Amplitude(polished) - sys.Amplitude(out.x)) <=
          1e-3 * std::max(sys.Amplitude(out.x), 1e-300)) {
    out.x = polished;
  }
  Describe(sys, setup.omega, &out);
  if (out.status == BoundStatus::kConverged && !(out.residual <= kFeasibility)) {
    out.status = BoundStatus::kFailed;
    std::ostringstream os;
    os << "; returned point violates R = 0: |R|/scale = " << out.residual;
    out.message += os.str();
  }
  return out;
}

// Ranks runs: the larger, the more response (the maximum response minimises η).
double RankValue(const BoundSolution& s, BoundsOptions::Objective objective) {
  return objective == BoundsOptions::kAmplitude ? s.amplitude : -s.loss_factor;
}

}  // namespace

bool BoundsOptions::IsValid(std::string* error) const {
  if (max_iterations < 1) {
    *error = "BoundsOptions.max_iterations must be >= 1, got " + std::to_string(max_iterations);
    return false;
  }
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    *error = "BoundsOptions.tolerance must be positive and finite";
    return false;
  }
  if (objective != kAmplitude && objective != kLossFactor) {
    *error = "BoundsOptions.objective must be kAmplitude or kLossFactor";
    return false;
  }
  for (size_t i = 0; i < alpha_seeds.size(); ++i) {
    const Eigen::VectorXd& a = alpha_seeds[i];
    if (a.size() != alpha_seeds[0].size()) {
      *error = "BoundsOptions.alpha_seeds[" + std::to_string(i) + "] has " +
               std::to_string(a.size()) + " entries, alpha_seeds[0] has " +
               std::to_string(alpha_seeds[0].size());
      return false;
    }
    for (int c = 0; c < a.size(); ++c) {
      if (!(std::abs(a[c]) <= 1.0)) {
        std::ostringstream os;
        os << "BoundsOptions.alpha_seeds[" << i << "][" << c << "] must lie in [-1, 1], got "
           << a[c];
        *error = os.str();
        return false;
      }
    }
  }
  return true;
}

std::vector<Eigen::VectorXd> DefaultAlphaSeeds(int num_contacts) {
  if (num_contacts < 0) throw std::invalid_argument("DefaultAlphaSeeds: num_contacts < 0");
  const int n = num_contacts;
  std::vector<Eigen::VectorXd> seeds;
  auto add = [&seeds](const Eigen::VectorXd& a) {
    for (const Eigen::VectorXd& s : seeds) {
      if (s == a) return;
    }
    seeds.push_back(a);
  };
  Eigen::VectorXd alt(n);
  for (int c = 0; c < n; ++c) alt[c] = (c % 2 == 0) ? 1.0 : -1.0;
  add(Eigen::VectorXd::Zero(n));
  add(Eigen::VectorXd::Constant(n, 0.5));
  add(Eigen::VectorXd::Constant(n, -0.5));
  add(alt);
  add(-alt);
  add(Eigen::VectorXd::Constant(n, 1.0));
  add(Eigen::VectorXd::Constant(n, -1.0));
  return seeds;
}

std::string ToString(BoundStatus status) {
  switch (status) {
    case BoundStatus::kConverged: return "converged";
    case BoundStatus::kMaxIterations: return "max-iterations";
    case BoundStatus::kInfeasible: return "infeasible";
    case BoundStatus::kFailed: return "failed";
  }
  return "unknown";
}

double BoundsResult::robustness() const {
  if (!IsUsable() || !(max.amplitude > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 1.0 - (max.amplitude - min.amplitude) / max.amplitude;
}

std::string BoundsResult::BriefReport() const {
  std::ostringstream os;
  auto one = [&os](const char* name, const BoundSolution& s) {
    os << "  " << name << ": " << ToString(s.status);
    if (s.seed >= 0) {
      os << " (seed " << s.seed << ", " << s.iterations << " it.), amplitude " << s.amplitude
         << " m, eta " << s.loss_factor << ", |R|/scale " << s.residual << ", alpha "
         << FormatVector(s.alpha) << ", regimes [";
      for (size_t i = 0; i < s.regimes.size(); ++i) os << (i ? ", " : "") << ToString(s.regimes[i]);
      os << "]";
    }
    os << " -- " << s.message << "\n";
  };
  os << "Response bounds at " << freq_hz << " Hz: robustness " << robustness() << "\n";
  one("min", min);
  one("max", max);
  os << "  seeds: " << seeds_tried << " tried, " << seeds_converged << " fully converged, "
     << start_failures << " start failures, " << min_failures << " failed min runs, "
     << max_failures << " failed max runs; spread of the optimum over seeds: min " << spread_min
     << ", max " << spread_max;
  return os.str();
}

BoundsResult ComputeBounds(const HbmSystem& system, double freq_hz, const BoundsOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (!(freq_hz > 0.0) || !std::isfinite(freq_hz)) {
    throw std::invalid_argument("ComputeBounds: freq_hz must be positive and finite, got " +
                                std::to_string(freq_hz));
  }
  const int nc = system.num_contacts();
  const std::vector<Eigen::VectorXd> seeds =
      options.alpha_seeds.empty() ? DefaultAlphaSeeds(nc) : options.alpha_seeds;
  if (seeds[0].size() != nc) {
    throw std::invalid_argument("ComputeBounds: alpha seeds have " +
                                std::to_string(seeds[0].size()) + " entries, the system has " +
                                std::to_string(nc) + " contacts");
  }
  const double omega = kTwoPi * freq_hz;

  BoundsResult result;
  result.freq_hz = freq_hz;
  result.seeds_tried = static_cast<int>(seeds.size());
  result.min.message = result.max.message = "no seed produced a starting solution";

  // Scaling: per harmonic-coefficient block of the full-stick solution.
  const int n = system.num_dofs(), nh = system.num_coefficients();
  const Eigen::VectorXd x_stick = system.StickLinearSolution(omega);
  const double x_ref = std::max(x_stick.lpNorm<Eigen::Infinity>(), 1e-300);
  RunSetup setup;
  setup.system = &system;
  const LinearPart linear = MakeLinearPart(system, omega);
  setup.linear = &linear;
  setup.omega = omega;
  setup.objective = options.objective;
  setup.residual_scale = system.ResidualScale();
  setup.x_scale.resize(system.num_unknowns());
  for (int j = 0; j < nh; ++j) {
    const double block = x_stick.segment(j * n, n).lpNorm<Eigen::Infinity>();
    setup.x_scale.segment(j * n, n).setConstant(std::max(block, 1e-6 * x_ref));
  }

#ifdef BOUNDS_DEBUG
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(true);
  app->Options()->SetIntegerValue("print_level", BOUNDS_DEBUG);
#else
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(false);
  app->Options()->SetIntegerValue("print_level", 0);
#endif
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetNumericValue("constr_viol_tol", 1e-10);
  app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  if (app->Initialize("") != Ipopt::Solve_Succeeded) {
    throw std::runtime_error("ComputeBounds: Ipopt failed to initialise");
  }

  std::vector<Eigen::VectorXd> starts;
  bool have_min = false, have_max = false;
  double min_lo = 0, min_hi = 0, max_lo = 0, max_hi = 0;
  for (int s = 0; s < static_cast<int>(seeds.size()); ++s) {
    Eigen::VectorXd x0;
    if (!StartSolution(system, freq_hz, seeds[s], starts, &x0)) {
      ++result.start_failures;
      continue;
    }
    starts.push_back(x0);
    if (options.objective == BoundsOptions::kAmplitude) {
      const double y0 = system.Amplitude(x0);
      setup.objective_scale = std::max(y0 * y0, 1e-300);
    } else {
      setup.objective_scale = std::max(std::abs(system.Energies(x0, omega, seeds[s]).loss_factor()),
                                       1e-6);
    }
    bool both = true;
    for (int dir = 0; dir < 2; ++dir) {
      const bool maximise_response = dir == 1;
      // Minimum response: min a², or max η; maximum response: max a², or min η.
      const bool amp = options.objective == BoundsOptions::kAmplitude;
      setup.sign = (maximise_response == amp) ? -1.0 : 1.0;
      BoundSolution sol;
      if (nc == 0) {  // nothing to optimise: the start is the unique solution
        sol.x = x0;
        sol.alpha = seeds[s];
        sol.seed = s;
        sol.status = BoundStatus::kConverged;
        sol.message = "no contacts: unique response";
        Describe(system, omega, &sol);
      } else {
        sol = Run(*app, setup, x0, seeds[s], s);
      }
      BoundSolution& best = maximise_response ? result.max : result.min;
      bool& have = maximise_response ? have_max : have_min;
      if (!sol.IsUsable()) {
        both = false;
        ++(maximise_response ? result.max_failures : result.min_failures);
        if (!have) best = sol;  // keep a failure on record until a run converges
        continue;
      }
      const double v = RankValue(sol, options.objective);
      const double obj = amp ? sol.amplitude : sol.loss_factor;
      double& lo = maximise_response ? max_lo : min_lo;
      double& hi = maximise_response ? max_hi : min_hi;
      if (!have) {
        lo = hi = obj;
      } else {
        lo = std::min(lo, obj);
        hi = std::max(hi, obj);
      }
      const double v_best = have ? RankValue(best, options.objective) : 0.0;
      const bool better = !have || (maximise_response ? v > v_best : v < v_best);
      if (better) best = std::move(sol);
      have = true;
    }
    if (both) ++result.seeds_converged;
  }
  result.spread_min = min_hi - min_lo;
  result.spread_max = max_hi - max_lo;
  return result;
}

}  // namespace fricrom
