// Response bounds by interior-point optimisation (Ipopt) over [x̂, α] subject to R = 0.
// Ipopt stays inside this file; the public header only needs Eigen.
#include "fricrom/bounds.h"

#include <algorithm>
#include <cmath>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpIpoptCalculatedQuantities.hpp>
#include <coin/IpSolveStatistics.hpp>
#include <coin/IpTNLP.hpp>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "fricrom/units.h"
#include "linear/dense_lapack.h"
#include "optimise_bounds.h"

namespace fricrom {
namespace {

// A returned point counts as a solution only if ‖R‖ ≤ kFeasibility · ResidualScale().
constexpr double kFeasibility = 1e-6;
// Stall test: scaled constraint violation (max-norm of R / ResidualScale()) and iteration count.
constexpr double kStallFeasibility = 1e-8;
constexpr int kStallIterations = 10;
constexpr int kSlowIterations = 10;
constexpr double kSlowProgress = 1e-5;

struct RunSetup {
  const HarmonicBalance* system = nullptr;
  double omega = 0.0;
  BoundsOptions::Objective objective = BoundsOptions::kAmplitude;
  double sign = 1.0;              // +1 minimises the objective, −1 maximises it
  double objective_scale = 1.0;   // objective divided by this
  double stall_tolerance = 1e-9;  // relative objective change that counts as no change
  Eigen::VectorXd x_scale;        // x = x_scale ∘ z
  double residual_scale = 1.0;    // constraints g = R / residual_scale
};

// The run's objective sign·φ(x, α)/objective_scale (φ = a1² + b1² of the response DOF, or η) and,
// when grad_x is given, its gradient in the unscaled variables. `e` must hold R at (x, α) for the
// loss factor, and the Jacobians as well for its gradient.
double Objective(const RunSetup& s, const Eigen::VectorXd& x, const Eigen::VectorXd& alpha,
                 const HbmEvaluation& e, Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_alpha) {
  const HarmonicBalance& sys = *s.system;
  const double factor = s.sign / s.objective_scale;
  if (s.objective == BoundsOptions::kAmplitude) {
    if (grad_x != nullptr) {
      *grad_x = factor * sys.AmplitudeSquaredGradient(x);
      grad_alpha->setZero(sys.num_alpha());
    }
    const double y = sys.Amplitude(x);
    return factor * y * y;
  }
  const double eta = sys.LossFactor(x, s.omega, alpha, e, grad_x, grad_alpha);
  if (grad_x != nullptr) {
    *grad_x *= factor;
    *grad_alpha *= factor;
  }
  return factor * eta;
}

// Whether the (feasible) start already satisfies the first-order optimality conditions: the
// reduced gradient g = ∂φ/∂α − (∂R/∂α)ᵀ (∂R/∂x)⁻ᵀ ∂φ/∂x vanishes (to `tolerance`) in every free
// α direction and points out of the box at an active bound. This is typical on the plateaus of
// the response over α (contacts that slip or whose first-period force saturates forget α), where
// the interior-point method would only spend its iterations driving the barrier to zero.
bool StartIsKktPoint(const RunSetup& s, const Eigen::VectorXd& x0, const Eigen::VectorXd& alpha0,
                     double tolerance) {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = req.alpha_jacobian = true;
  s.system->Evaluate(x0, s.omega, alpha0, req, &e);
  Eigen::VectorXd gx, ga;
  Objective(s, x0, alpha0, e, &gx, &ga);
  dense::Lu lu;
  lu.ComputeTransposed(e.jacobian);
  if (!(lu.rcond() > 1e-12)) return false;
  const Eigen::VectorXd lambda = lu.Solve(gx);
  const Eigen::VectorXd g = ga - e.alpha_jacobian.transpose() * lambda;
  if (!g.allFinite()) return false;
  for (int c = 0; c < g.size(); ++c) {
    const bool at_upper = alpha0[c] >= 1.0, at_lower = alpha0[c] <= -1.0;
    // Minimising: at the upper bound the gradient may be negative, at the lower one positive.
    const bool ok = at_upper ? g[c] <= tolerance
                             : (at_lower ? g[c] >= -tolerance : std::abs(g[c]) <= tolerance);
    if (!ok) return false;
  }
  return true;
}

// The NLP in scaled variables z = [x ⊘ x_scale, α], constraints g = R / residual_scale, dense
// Jacobian, quasi-Newton Hessian.
class BoundsNlp : public Ipopt::TNLP {
 public:
  explicit BoundsNlp(const HarmonicBalance& system)
      : nx_(system.num_unknowns()), nc_(system.num_alpha()) {}

  // Prepares the next run (the structure never changes, so Ipopt can re-optimise this object).
  void Reset(const RunSetup& setup, const Eigen::VectorXd& x0, const Eigen::VectorXd& alpha0) {
    s_ = setup;
    x0_ = x0;
    alpha0_ = alpha0;
    have_point_ = have_residual_ = have_jacobians_ = eval_ok_ = false;
    finalized_ = false;
    stalled_ = no_progress_ = false;
    objectives_.clear();
    errors_.clear();
    last_error_ = 0.0;
    status_ = Ipopt::UNASSIGNED;
  }

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
    const bool need_residual = s_.objective == BoundsOptions::kLossFactor;
    if (need_residual ? !Update(z, new_z, false) : !Unscaled(z, new_z)) return false;
    f = Objective(s_, x_, alpha_, eval_, nullptr, nullptr);
    return std::isfinite(f);
  }

  bool eval_grad_f(Ipopt::Index, const Ipopt::Number* z, bool new_z, Ipopt::Number* grad) override {
    const bool need_jacobians = s_.objective == BoundsOptions::kLossFactor;
    if (need_jacobians ? !Update(z, new_z, true) : !Unscaled(z, new_z)) return false;
    Eigen::VectorXd gx, ga;
    Objective(s_, x_, alpha_, eval_, &gx, &ga);
    for (int i = 0; i < nx_; ++i) grad[i] = gx[i] * s_.x_scale[i];
    for (int c = 0; c < nc_; ++c) grad[nx_ + c] = ga[c];
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

  // Watches the feasible iterates of a run for two symptoms of the kinks of the piecewise-smooth
  // problem (typically where a full-stick contact's first-period force starts to saturate, so
  // the objective turns flat in α), where no KKT point exists and the barrier keeps the iterates
  // crawling along the kink:
  //  - stalled: the objective stays constant (relative stall_tolerance) over kStallIterations
  //    iterations: a nonsmooth local optimum, reported as converged with its own message;
  //  - no progress: over kSlowIterations iterations the objective improves by less than
  //    kSlowProgress (relative) and the KKT error does not fall tenfold: stopped and reported as
  //    failed (it would otherwise crawl to max_iterations).
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index, Ipopt::Number obj,
                             Ipopt::Number inf_pr, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Index,
                             const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities* cq) override {
    if (cq != nullptr) last_error_ = cq->curr_nlp_error();
    if (mode != Ipopt::RegularMode || !(inf_pr <= kStallFeasibility)) {
      objectives_.clear();
      errors_.clear();
      return true;
    }
    objectives_.push_back(obj);
    errors_.push_back(last_error_);
    const int count = static_cast<int>(objectives_.size());
    const double scale = std::max(1.0, std::abs(obj));
    auto span = [this, count](int last) {
      const auto first = objectives_.begin() + (count - last);
      const auto [lo, hi] = std::minmax_element(first, objectives_.end());
      return *hi - *lo;
    };
    if (count > kStallIterations && span(kStallIterations + 1) <= s_.stall_tolerance * scale) {
      stalled_ = true;
      return false;
    }
    if (count > kSlowIterations) {
      const double gain = objectives_[count - 1 - kSlowIterations] - obj;  // objective decrease
      if (gain < kSlowProgress * scale &&
          !(last_error_ < 0.1 * errors_[count - 1 - kSlowIterations])) {
        no_progress_ = true;
        return false;
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
  bool stalled() const { return stalled_; }
  bool no_progress() const { return no_progress_; }
  double last_error() const { return last_error_; }
  Ipopt::SolverReturn status() const { return status_; }
  const Eigen::VectorXd& x_final() const { return x_final_; }
  const Eigen::VectorXd& alpha_final() const { return alpha_final_; }

 private:
  // α is clamped to [−1, 1]: Ipopt may relax the bounds by a hair.
  void Unscale(const Ipopt::Number* z, Eigen::VectorXd* x, Eigen::VectorXd* alpha) const {
    x->resize(nx_);
    alpha->resize(nc_);
    for (int i = 0; i < nx_; ++i) (*x)[i] = z[i] * s_.x_scale[i];
    for (int c = 0; c < nc_; ++c) (*alpha)[c] = std::clamp(z[nx_ + c], -1.0, 1.0);
  }

  // Makes x_, alpha_ the unscaled z (dropping cached evaluations when z is new).
  bool Unscaled(const Ipopt::Number* z, bool new_z) {
    if (new_z || !have_point_) {
      have_residual_ = have_jacobians_ = false;
      Unscale(z, &x_, &alpha_);
      have_point_ = true;
    }
    return true;
  }

  // Evaluates R (and the Jacobians when asked) at z unless the cache already holds them.
  bool Update(const Ipopt::Number* z, bool new_z, bool jacobians) {
    Unscaled(z, new_z);
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
  bool have_point_ = false, have_residual_ = false, have_jacobians_ = false, eval_ok_ = false;
  bool finalized_ = false;
  bool stalled_ = false, no_progress_ = false;
  std::vector<double> objectives_, errors_;  // over the current streak of feasible iterations
  double last_error_ = 0.0;                  // scaled KKT error of the last iterate
  Ipopt::SolverReturn status_ = Ipopt::UNASSIGNED;
  Eigen::VectorXd x_final_, alpha_final_;
};

const char* SolverReturnText(Ipopt::SolverReturn r) {
  switch (r) {
    case Ipopt::SUCCESS:
      return "optimal point found";
    case Ipopt::MAXITER_EXCEEDED:
      return "maximum number of iterations exceeded";
    case Ipopt::CPUTIME_EXCEEDED:
      return "maximum CPU time exceeded";
    case Ipopt::STOP_AT_TINY_STEP:
      return "search direction became too small";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT:
      return "solved to acceptable level only";
    case Ipopt::LOCAL_INFEASIBILITY:
      return "converged to a point of local infeasibility";
    case Ipopt::USER_REQUESTED_STOP:
      return "stopped by the user";
    case Ipopt::FEASIBLE_POINT_FOUND:
      return "feasible point found";
    case Ipopt::DIVERGING_ITERATES:
      return "iterates diverging";
    case Ipopt::RESTORATION_FAILURE:
      return "restoration phase failed";
    case Ipopt::ERROR_IN_STEP_COMPUTATION:
      return "error in step computation";
    case Ipopt::INVALID_NUMBER_DETECTED:
      return "invalid number in an evaluation";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM:
      return "too few degrees of freedom";
    case Ipopt::INVALID_OPTION:
      return "invalid option";
    case Ipopt::OUT_OF_MEMORY:
      return "out of memory";
    case Ipopt::INTERNAL_ERROR:
      return "internal error";
    case Ipopt::UNASSIGNED:
      break;
  }
  return "no result";
}

BoundStatus MapStatus(Ipopt::SolverReturn r) {
  switch (r) {
    case Ipopt::SUCCESS:
      return BoundStatus::kConverged;
    case Ipopt::MAXITER_EXCEEDED:
    case Ipopt::CPUTIME_EXCEEDED:
      return BoundStatus::kMaxIterations;
    case Ipopt::LOCAL_INFEASIBILITY:
      return BoundStatus::kInfeasible;
    default:
      return BoundStatus::kFailed;
  }
}

std::vector<ContactRegime> Regimes(const HarmonicBalance& sys, const Eigen::VectorXd& x,
                                   double omega, const Eigen::VectorXd& alpha) {
  std::vector<ContactRegime> out;
  for (const ContactHistory& h : sys.ContactHistories(x, omega, alpha)) out.push_back(h.regime);
  return out;
}

double ResidualNorm(const HarmonicBalance& sys, const Eigen::VectorXd& x, double omega,
                    const Eigen::VectorXd& alpha) {
  HbmEvaluation e;
  sys.Evaluate(x, omega, alpha, HbmRequest{}, &e);
  return e.residual.norm() / sys.ResidualScale();
}

// Fills the derived fields of a solution (x, α set).
void Describe(const HarmonicBalance& sys, double omega, BoundSolution* s) {
  s->amplitude = sys.Amplitude(s->x);
  s->residual = ResidualNorm(sys, s->x, omega, s->alpha);
  s->loss_factor = sys.Energies(s->x, omega, s->alpha).loss_factor();
  s->regimes = Regimes(sys, s->x, omega, s->alpha);
}

// A converged harmonic-balance solution at α to start from: SolveAtFrequencies at f, then
// Newton from the other seeds' starts, then SolveAtFrequencies on a ramp up to f (its
// continuation fallback follows the branch).
bool StartSolution(const HarmonicBalance& sys, double freq_hz, const Eigen::VectorXd& alpha,
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
BoundSolution Run(Ipopt::IpoptApplication& app, const Ipopt::SmartPtr<BoundsNlp>& nlp,
                  bool* first_run, const RunSetup& setup, const Eigen::VectorXd& x0,
                  const Eigen::VectorXd& alpha0, int seed) {
  const HarmonicBalance& sys = *setup.system;
  BoundSolution out;
  out.seed = seed;
  nlp->Reset(setup, x0, alpha0);
  const Ipopt::SmartPtr<Ipopt::TNLP> tnlp = Ipopt::GetRawPtr(nlp);
  const Ipopt::ApplicationReturnStatus rc =
      *first_run ? app.OptimizeTNLP(tnlp) : app.ReOptimizeTNLP(tnlp);
  if (nlp->finalized()) *first_run = false;
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
  if (nlp->status() == Ipopt::USER_REQUESTED_STOP && nlp->stalled()) {
    out.status = BoundStatus::kConverged;
    std::ostringstream os;
    os << "objective stationary over " << kStallIterations
       << " feasible iterations at a nonsmooth point (KKT error " << nlp->last_error()
       << " stays above the tolerance)";
    out.message = os.str();
  } else if (nlp->status() == Ipopt::USER_REQUESTED_STOP && nlp->no_progress()) {
    out.status = BoundStatus::kFailed;
    std::ostringstream os;
    os << "stopped: no progress over " << kSlowIterations
       << " feasible iterations along a nonsmooth ridge (KKT error " << nlp->last_error() << ")";
    out.message = os.str();
  }
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
  if (ns.IsSolutionUsable() && std::abs(sys.Amplitude(polished) - sys.Amplitude(out.x)) <=
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

// Chord iterations x ← x − J₀⁻¹ R(x) with the factorised transpose J₀ᵀ of the last accepted
// point. Where no contact changes state between the two α the balance is linear in x (stick) or
// nearly so, and one or two steps converge without a new factorisation. On success x solves
// R = 0 to Newton's tolerance; on failure x is left as the best iterate (a warm start).
bool ChordSolve(const SquareSystem& at, const dense::Lu& lu_transposed, const NewtonOptions& o,
                Eigen::VectorXd* x) {
  constexpr int kChordSteps = 4;
  const double scale = at.ResidualScale();
  Eigen::VectorXd r, x_trial, r_trial;
  at.Evaluate(*x, &r, nullptr);
  double norm = r.norm() / scale;
  for (int k = 0; k < kChordSteps && std::isfinite(norm); ++k) {
    if (norm <= o.residual_tolerance) return true;
    x_trial = *x - lu_transposed.Solve(r, true);
    at.Evaluate(x_trial, &r_trial, nullptr);
    const double trial = r_trial.norm() / scale;
    if (!(trial < 0.25 * norm)) return false;  // too slow a contraction: Newton takes over
    x->swap(x_trial);
    r.swap(r_trial);
    norm = trial;
  }
  return norm <= o.residual_tolerance;
}

// Reduced-space run: projected gradient with Armijo backtracking and Barzilai-Borwein steps over
// the α box; x(α) from Newton warm-started at the last iterate, so every iterate satisfies R = 0,
// and the reduced gradient g = ∂φ/∂α − (∂R/∂α)ᵀ(∂R/∂x)⁻ᵀ∂φ/∂x by one adjoint solve.
BoundSolution RunReduced(const RunSetup& s, const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                         int seed, int max_iterations, double tolerance) {
  const HarmonicBalance& sys = *s.system;
  BoundSolution out;
  out.seed = seed;
  // φ and the reduced gradient at a solution (x, a); `lu` keeps the factorised (∂R/∂x)ᵀ.
  auto value_and_gradient = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& a, double* phi,
                                Eigen::VectorXd* g, dense::Lu* lu) {
    HbmEvaluation e;
    HbmRequest req;
    req.jacobian = req.alpha_jacobian = true;
    sys.Evaluate(x, s.omega, a, req, &e);
    Eigen::VectorXd gx, ga;
    *phi = Objective(s, x, a, e, &gx, &ga);
    lu->ComputeTransposed(e.jacobian);
    if (!(lu->rcond() > 1e-14)) return false;
    *g = ga - e.alpha_jacobian.transpose() * lu->Solve(gx);
    return g->allFinite();
  };
  Eigen::VectorXd x = x0, a = a0, g;
  double phi = 0.0;
  dense::Lu lu, lu_new;
  // Chord steps pay off where an LU is dear; small (lumped) systems keep plain Newton.
  const bool chord = sys.num_unknowns() >= dense::kLapackMinSize;
  std::vector<ContactRegime> regimes, regimes_new;
  if (chord) regimes = Regimes(sys, x, s.omega, a);
  auto finish = [&](BoundStatus status, const std::string& message) {
    out.x = x;
    out.alpha = a;
    out.status = status;
    out.message = message;
    Describe(sys, s.omega, &out);
    if (out.status == BoundStatus::kConverged && !(out.residual <= kFeasibility)) {
      out.status = BoundStatus::kFailed;
      out.message += "; the point violates R = 0";
    }
    return out;
  };
  if (!value_and_gradient(x, a, &phi, &g, &lu)) {
    return finish(BoundStatus::kFailed, "singular Jacobian at the start");
  }
  const NewtonOptions newton;
  double step = 0.5 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300);  // first move ≤ 0.5 in α
  int quiet = 0;
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it;
    // First-order conditions on the box: the projected gradient step vanishes.
    const Eigen::VectorXd pg = (a - g).cwiseMax(-1.0).cwiseMin(1.0) - a;
    if (pg.lpNorm<Eigen::Infinity>() <= tolerance) {
      return finish(BoundStatus::kConverged, "reduced space: projected gradient vanishes (KKT)");
    }
    bool accepted = false;
    Eigen::VectorXd a_new, x_new, g_new;
    double phi_new = 0.0;
    for (int bt = 0; bt < 40 && !accepted; ++bt, step *= 0.5) {
      a_new = (a - step * g).cwiseMax(-1.0).cwiseMin(1.0);
      if ((a_new - a).lpNorm<Eigen::Infinity>() <= 1e-14) break;
      // x(α_new): chord steps with the last factorisation, kept only if every contact is in the
      // regime it had at the last accepted point (a chord step can otherwise land on another
      // branch, e.g. a lift-off the Newton path would not reach); else Newton.
      const HbmAtFrequency at(sys, s.omega, a_new);
      bool solved = false;
      x_new = x;
      if (chord && ChordSolve(at, lu, newton, &x_new)) {
        regimes_new = Regimes(sys, x_new, s.omega, a_new);
        solved =
            regimes_new == regimes && value_and_gradient(x_new, a_new, &phi_new, &g_new, &lu_new);
      }
      if (!solved) {
        x_new = x;
        if (!SolveNewton(at, newton, &x_new).IsSolutionUsable()) continue;
        if (!value_and_gradient(x_new, a_new, &phi_new, &g_new, &lu_new)) continue;
        regimes_new.clear();
      }
      accepted = phi_new <= phi - 1e-4 * g.dot(a - a_new);
    }
    if (!accepted) {
      return finish(BoundStatus::kConverged,
                    "reduced space: no descent along the projected gradient (nonsmooth "
                    "stationary point)");
    }
    const Eigen::VectorXd ds = a_new - a, dg = g_new - g;
    const double change = std::abs(phi - phi_new);
    x = x_new;
    a = a_new;
    g = g_new;
    phi = phi_new;
    std::swap(lu, lu_new);
    if (chord) regimes = regimes_new.empty() ? Regimes(sys, x, s.omega, a) : regimes_new;
    quiet = change <= tolerance * std::max(std::abs(phi), 1.0) ? quiet + 1 : 0;
    if (quiet >= 3) {
      return finish(BoundStatus::kConverged, "reduced space: objective stationary");
    }
    const double sy = ds.dot(dg);
    step =
        sy > 0.0 ? std::clamp(ds.squaredNorm() / sy, 1e-8, 1e8) : 4.0 * step;  // Barzilai-Borwein
  }
  return finish(BoundStatus::kMaxIterations, "reduced space: iteration limit");
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
  if (method != kFullSpace && method != kReducedSpace && method != kBoth) {
    *error = "BoundsOptions.method must be kFullSpace, kReducedSpace or kBoth";
    return false;
  }
  if (check_samples < 0) {
    *error = "BoundsOptions.check_samples must be >= 0, got " + std::to_string(check_samples);
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
  return seeds;
}

std::string ToString(BoundsOptions::Method method) {
  switch (method) {
    case BoundsOptions::kFullSpace:
      return "ipopt";
    case BoundsOptions::kReducedSpace:
      return "reduced";
    case BoundsOptions::kBoth:
      return "both";
  }
  return "unknown";
}

bool FromString(const std::string& name, BoundsOptions::Method* method) {
  for (BoundsOptions::Method m :
       {BoundsOptions::kFullSpace, BoundsOptions::kReducedSpace, BoundsOptions::kBoth}) {
    if (ToString(m) == name) {
      *method = m;
      return true;
    }
  }
  return false;
}

std::string ToString(BoundStatus status) {
  switch (status) {
    case BoundStatus::kConverged:
      return "converged";
    case BoundStatus::kMaxIterations:
      return "max-iterations";
    case BoundStatus::kInfeasible:
      return "infeasible";
    case BoundStatus::kFailed:
      return "failed";
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
     << max_failures << " failed max runs, " << optimizer_runs
     << " optimiser runs (the others started at a KKT point); spread of the optimum over "
     << "seeds: min " << spread_min << ", max " << spread_max
     << "; sample check: " << samples_checked << " samples (" << samples_failed << " failed), "
     << improved_by_samples << " bounds improved";
  return os.str();
}

BoundsResult OptimiseBounds(const HarmonicBalance& system, double freq_hz,
                            const BoundsOptions& options,
                            const std::vector<Eigen::VectorXd>& seeds) {
  const int nc = system.num_alpha();
  if (seeds.empty() || seeds[0].size() != nc) {
    throw std::invalid_argument("ComputeBounds: alpha seeds have " +
                                std::to_string(seeds.empty() ? 0 : seeds[0].size()) +
                                " entries, the system has " + std::to_string(nc) + " contacts");
  }
  const double omega = kTwoPi * freq_hz;

  BoundsResult result;
  result.freq_hz = freq_hz;
  result.seeds_tried = static_cast<int>(seeds.size());
  result.min.message = result.max.message = "no seed produced a starting solution";

  // Scaling: per harmonic-coefficient block of the full-stick solution.
  // Unknowns are harmonic-major: 2H+1 equal blocks (HarmonicBalance).
  const int nh = 2 * system.harmonics() + 1, n = system.num_unknowns() / nh;
  const Eigen::VectorXd x_stick = system.StickLinearSolution(omega);
  const double x_ref = std::max(x_stick.lpNorm<Eigen::Infinity>(), 1e-300);
  RunSetup setup;
  setup.system = &system;
  setup.omega = omega;
  setup.objective = options.objective;
  setup.residual_scale = system.ResidualScale();
  setup.stall_tolerance = options.tolerance;
  setup.x_scale.resize(system.num_unknowns());
  for (int j = 0; j < nh; ++j) {
    const double block = x_stick.segment(j * n, n).lpNorm<Eigen::Infinity>();
    setup.x_scale.segment(j * n, n).setConstant(std::max(block, 1e-6 * x_ref));
  }

  // No console journalist: the library never prints.
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication(false);
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetNumericValue("constr_viol_tol", 1e-8);
  app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  app->Options()->SetStringValue("mu_oracle", "loqo");
  app->Options()->SetIntegerValue("acceptable_iter", 0);  // no "acceptable" exits: see Run
  if (app->Initialize("") != Ipopt::Solve_Succeeded) {    // "": no ipopt.opt is read
    throw std::runtime_error("ComputeBounds: Ipopt failed to initialise");
  }

  Ipopt::SmartPtr<BoundsNlp> nlp = new BoundsNlp(system);
  bool first_run = true;
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
      const double eta0 = system.Energies(x0, omega, seeds[s]).loss_factor();
      setup.objective_scale = std::max(std::abs(eta0), 1e-6);
    }
    bool both = true;
    for (int dir = 0; dir < 2; ++dir) {
      const bool maximise_response = dir == 1;
      // Minimum response: min a², or max η; maximum response: max a², or min η.
      const bool amp = options.objective == BoundsOptions::kAmplitude;
      setup.sign = (maximise_response == amp) ? -1.0 : 1.0;
      BoundSolution sol;
      auto accept_start = [&](const char* why) {
        sol.x = x0;
        sol.alpha = seeds[s];
        sol.seed = s;
        sol.status = BoundStatus::kConverged;
        sol.message = why;
        Describe(system, omega, &sol);
      };
      if (nc == 0) {
        accept_start("no contacts: unique response");
      } else if (StartIsKktPoint(setup, x0, seeds[s], options.tolerance)) {
        accept_start("the start is already a KKT point (zero reduced gradient in alpha)");
      } else {
        const bool reduced = options.method != BoundsOptions::kFullSpace;
        const bool full = options.method != BoundsOptions::kReducedSpace;
        if (reduced) sol = RunReduced(setup, x0, seeds[s], s, options.max_iterations, 1e-7);
        if (full) {
          BoundSolution other = Run(*app, nlp, &first_run, setup, x0, seeds[s], s);
          const double sign = maximise_response ? 1.0 : -1.0;  // larger is better after the sign
          if (!reduced || !sol.IsUsable() ||
              (other.IsUsable() && sign * RankValue(other, options.objective) >
                                       sign * RankValue(sol, options.objective))) {
            sol = std::move(other);
          }
        }
        result.optimizer_runs += (reduced ? 1 : 0) + (full ? 1 : 0);
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
  result.spread_min = have_min ? min_hi - min_lo : std::numeric_limits<double>::quiet_NaN();
  result.spread_max = have_max ? max_hi - max_lo : std::numeric_limits<double>::quiet_NaN();
  for (BoundSolution* b : {&result.min, &result.max}) {
    if (b->IsUsable()) continue;  // a failed bound is never a number
    b->amplitude = b->loss_factor = std::numeric_limits<double>::quiet_NaN();
  }
  return result;
}

}  // namespace fricrom
