// Full-space bound runs by Ipopt over [x̂, α] subject to R = 0 (the paper's formulation).
// Ipopt stays inside this file.
#include <algorithm>
#include <cmath>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpIpoptCalculatedQuantities.hpp>
#include <coin/IpSolveStatistics.hpp>
#include <coin/IpTNLP.hpp>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bound_runs.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"

namespace fricrom::bounds_detail {
namespace {

// Stall test: scaled constraint violation (max-norm of R / ResidualScale()) and iteration count.
constexpr double kStallFeasibility = 1e-8;
constexpr int kStallIterations = 10;
constexpr int kSlowIterations = 10;
constexpr double kSlowProgress = 1e-5;

// The NLP in scaled variables z = [x ⊘ x_scale, α], constraints g = R / residual_scale, dense
// Jacobian, quasi-Newton Hessian.
class BoundsNlp : public Ipopt::TNLP {
 public:
  explicit BoundsNlp(const HarmonicBalance& system)
      : nx_(system.num_unknowns()), nc_(system.num_alpha()), pattern_(system.StructuralPattern()) {}

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
    nnz_jac_g = pattern_.nnz();
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
    if (values == nullptr) {  // the balance's structural pattern (dense for condensed ones)
      std::copy(pattern_.rows.begin(), pattern_.rows.end(), rows);
      std::copy(pattern_.cols.begin(), pattern_.cols.end(), cols);
      return true;
    }
    if (!Update(z, new_z, true)) return false;
    for (int k = 0; k < pattern_.nnz(); ++k) {
      const int i = pattern_.rows[static_cast<size_t>(k)],
                j = pattern_.cols[static_cast<size_t>(k)];
      values[k] =
          (j < nx_ ? eval_.jacobian(i, j) * s_.x_scale[j] : eval_.alpha_jacobian(i, j - nx_)) /
          s_.residual_scale;
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
  JacobianPattern pattern_;  // fixed structure of [∂R/∂x | ∂R/∂α]
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

// One optimisation run from a feasible start; the result is verified (and polished by Newton at
// the final α so that R = 0 holds to the harmonic-balance tolerance).
BoundSolution RunIpopt(Ipopt::IpoptApplication& app, const Ipopt::SmartPtr<BoundsNlp>& nlp,
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
  out.stationary = out.status == BoundStatus::kConverged;
  return out;
}

}  // namespace

struct IpoptBounds::Impl {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  Ipopt::SmartPtr<BoundsNlp> nlp;
  bool first_run = true;
};

IpoptBounds::IpoptBounds(const HarmonicBalance& system, const BoundsOptions& options)
    : impl_(std::make_unique<Impl>()) {
  // No console journalist: the library never prints.
  impl_->app = new Ipopt::IpoptApplication(false);
  Ipopt::SmartPtr<Ipopt::IpoptApplication>& app = impl_->app;
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

  impl_->nlp = new BoundsNlp(system);
}

IpoptBounds::~IpoptBounds() = default;

BoundSolution IpoptBounds::Run(const RunSetup& setup, const Eigen::VectorXd& x0,
                               const Eigen::VectorXd& alpha0, int seed) {
  return RunIpopt(*impl_->app, impl_->nlp, &impl_->first_run, setup, x0, alpha0, seed);
}

}  // namespace fricrom::bounds_detail
