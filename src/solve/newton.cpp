#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "fricrom/solve.h"
#include "linear/dense_lapack.h"
#include "linear/gmres.h"
#include "solve/newton_preconditioned.h"

namespace fricrom {

std::string ToString(SolverStatus status) {
  switch (status) {
    case SolverStatus::kConverged:
      return "converged";
    case SolverStatus::kMaxIterations:
      return "max_iterations";
    case SolverStatus::kSingular:
      return "singular";
    case SolverStatus::kDiverged:
      return "diverged";
  }
  return "unknown";
}

bool NewtonOptions::IsValid(std::string* error) const {
  auto bad = [&](const std::string& msg) {
    *error = "NewtonOptions." + msg;
    return false;
  };
  if (max_iterations < 1) return bad("max_iterations must be >= 1");
  if (!(residual_tolerance > 0.0)) return bad("residual_tolerance must be > 0");
  if (!(step_tolerance >= 0.0)) return bad("step_tolerance must be >= 0");
  if (!(converged_step >= 0.0)) return bad("converged_step must be >= 0");
  if (max_backtracks < 0) return bad("max_backtracks must be >= 0");
  if (!(armijo > 0.0 && armijo < 0.5)) return bad("armijo must lie in (0, 0.5)");
  if (!(divergence_factor > 1.0)) return bad("divergence_factor must be > 1");
  if (stall_window < 0) return bad("stall_window must be >= 0");
  if (!(stall_decrease > 0.0 && stall_decrease < 1.0)) {
    return bad("stall_decrease must lie in (0, 1)");
  }
  if (krylov_min_size < 0) return bad("krylov_min_size must be >= 0");
  if (krylov_max_iterations < 1) return bad("krylov_max_iterations must be >= 1");
  if (!(krylov_tolerance > 0.0 && krylov_tolerance < 1.0)) {
    return bad("krylov_tolerance must lie in (0, 1)");
  }
  if (!(krylov_oversolve >= 0.0 && std::isfinite(krylov_oversolve))) {
    return bad("krylov_oversolve must be finite and >= 0");
  }
  return true;
}

std::string NewtonSummary::BriefReport() const {
  std::ostringstream s;
  s << "Newton: " << ToString(status) << " after " << iterations << " iterations (" << evaluations
    << " evaluations, " << factorizations << " LU, " << krylov_iterations
    << " GMRES products), |R|/scale " << initial_residual << " -> " << final_residual;
  if (!message.empty()) s << " [" << message << "]";
  return s.str();
}

namespace {

bool KrylovAllowed(const NewtonOptions& options, const NewtonPreconditioner& m, int n) {
  return m.lu != nullptr && m.lu->rows() == n && options.krylov_min_size > 0 &&
         n >= options.krylov_min_size;
}

// The Newton step J dx = −r by GMRES preconditioned with an earlier Jacobian's LU, J given by
// `apply`; false when a new factorisation is needed.
bool KrylovStep(const dense::LinearMap& apply, const Eigen::VectorXd& r,
                const NewtonOptions& options, const NewtonPreconditioner& m, double forcing,
                Eigen::VectorXd* dx, NewtonSummary* summary) {
  const dense::GmresResult g = dense::PreconditionedGmres(apply, *m.lu, m.transposed, -r, forcing,
                                                          options.krylov_max_iterations, dx);
  summary->krylov_iterations += g.iterations;
  return g.converged;
}

// The linear part of a Newton iteration: J dx = −r by GMRES with a reused LU where allowed (on
// the system's matrix-free Jacobian if it offers one), else by a new LU, which then becomes the
// preconditioner. Holds the last Jacobian and LU between iterations.
class NewtonStepper {
 public:
  NewtonStepper(const SquareSystem& system, const NewtonOptions& options,
                NewtonPreconditioner initial)
      : system_(system), options_(options), preconditioner_(initial) {}

  // x moved: the Jacobian held is stale.
  void Moved() {
    jacobian_current_ = false;
    operator_.reset();
  }

  // The step at x (residual *r, which a Jacobian evaluation refreshes); false with the
  // summary's status set when the Jacobian is singular.
  bool Step(const Eigen::VectorXd& x, double forcing, Eigen::VectorXd* r, Eigen::VectorXd* dx,
            NewtonSummary* summary) {
    const bool large = options_.krylov_min_size > 0 && system_.size() >= options_.krylov_min_size;
    if (large && KrylovAllowed(options_, preconditioner_, system_.size())) {
      // Matrix-free products where the system offers them: no dense Jacobian unless GMRES misses.
      if (!jacobian_current_ && !operator_) operator_ = system_.Linearize(x);
      if (!operator_) EvaluateJacobian(x, r, summary);
      if (Krylov(*r, forcing, dx, summary)) return true;
    }
    EvaluateJacobian(x, r, summary);
    // Large systems factorise in single precision (half the time and memory) and solve by GMRES
    // with it, which restores double accuracy in a few products; a double LU if that misses.
    if (large && Factorize(dense::LuPrecision::kSingle, summary) &&
        lu_->rcond() > kSinglePrecisionRcond && Krylov(*r, forcing, dx, summary)) {
      return true;
    }
    if (!Factorize(dense::LuPrecision::kDouble, summary)) {
      summary->status = SolverStatus::kSingular;
      summary->message = "Jacobian reciprocal condition " + std::to_string(lu_->rcond());
      return false;
    }
    *dx = -lu_->Solve(*r);
    return true;
  }

 public:
  // The last factorisation made here (null if none).
  std::shared_ptr<const dense::Lu> factorization() const { return lu_; }

 private:
  // Below this reciprocal condition a single-precision LU preconditions poorly.
  static constexpr double kSinglePrecisionRcond = 1e-5;

  void EvaluateJacobian(const Eigen::VectorXd& x, Eigen::VectorXd* r, NewtonSummary* summary) {
    if (jacobian_current_) return;
    system_.Evaluate(x, r, &j_);
    ++summary->evaluations;
    jacobian_current_ = true;
  }

  // J dx = −r by GMRES preconditioned with the held LU, J applied matrix-free if offered.
  bool Krylov(const Eigen::VectorXd& r, double forcing, Eigen::VectorXd* dx,
              NewtonSummary* summary) {
    const dense::LinearMap apply = [this](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
      if (operator_) {
        operator_->Apply(v, false, out);
      } else {
        out->noalias() = j_ * v;
      }
    };
    return KrylovStep(apply, r, options_, preconditioner_, forcing, dx, summary);
  }

  // LU of j_ becomes the preconditioner; false if singular.
  bool Factorize(dense::LuPrecision precision, NewtonSummary* summary) {
    lu_ = std::make_shared<dense::Lu>(j_, precision);
    preconditioner_ = NewtonPreconditioner{lu_.get(), false};
    ++summary->factorizations;
    return lu_->rcond() > 1e-15;
  }

  const SquareSystem& system_;
  const NewtonOptions& options_;
  NewtonPreconditioner preconditioner_;
  Eigen::MatrixXd j_;
  bool jacobian_current_ = false;
  std::unique_ptr<JacobianOperator> operator_;  // the matrix-free Jacobian at x, if offered
  std::shared_ptr<dense::Lu> lu_;               // the last Jacobian factorised here
};

}  // namespace

NewtonSummary SolveNewton(const SquareSystem& system, const NewtonOptions& options,
                          Eigen::VectorXd* x) {
  return SolveNewtonPreconditioned(system, options, NewtonPreconditioner{}, x);
}

namespace {

// Armijo backtracking on ½‖R‖² along dx from x (‖R(x)‖/scale = norm). The residual has kinks
// (stick/slip switches), so the smallest trial that still decreases ‖R‖ is kept when the
// sufficient decrease is not met. Returns the step length with x_trial = x + t dx and r_trial
// its residual, or 0 when no trial decreased ‖R‖.
double LineSearch(const SquareSystem& system, const NewtonOptions& options,
                  const Eigen::VectorXd& x, const Eigen::VectorXd& dx, double norm, double scale,
                  Eigen::VectorXd* x_trial, Eigen::VectorXd* r_trial, NewtonSummary* summary) {
  double t = 1.0;
  double best_norm = norm, best_t = 0.0;
  Eigen::VectorXd r_best;
  for (int bt = 0; bt <= options.max_backtracks; ++bt, t *= 0.5) {
    *x_trial = x + t * dx;
    system.Evaluate(*x_trial, r_trial, nullptr);
    ++summary->evaluations;
    const double trial = r_trial->norm() / scale;
    if (std::isfinite(trial) && trial < best_norm) {
      best_norm = trial;
      best_t = t;
      r_best = *r_trial;
    }
    if (std::isfinite(trial) && trial * trial <= (1.0 - 2.0 * options.armijo * t) * norm * norm) {
      return t;
    }
  }
  if (best_t == 0.0) return 0.0;
  *x_trial = x + best_t * dx;
  r_trial->swap(r_best);
  return best_t;
}

NewtonSummary RunNewton(const SquareSystem& system, const NewtonOptions& options,
                        NewtonStepper& stepper, Eigen::VectorXd* x,
                        const Eigen::VectorXd* residual_at_start) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (x == nullptr || x->size() != system.size()) {
    throw std::invalid_argument("SolveNewton: start vector must have size " +
                                std::to_string(system.size()));
  }
  NewtonSummary summary;
  const double scale = system.ResidualScale();
  Eigen::VectorXd r, r_trial, x_trial;
  // The Jacobian is evaluated only where a step is taken: a solve that starts or lands within
  // the tolerance pays no Jacobian there (warm-started solves of the bound optimiser).
  double previous_norm = 0.0;
  std::vector<double> norms;  // ‖R‖/scale after each iteration, for the stall test
  if (residual_at_start != nullptr) {
    if (residual_at_start->size() != system.size()) {
      throw std::invalid_argument("SolveNewton: residual at the start must have size " +
                                  std::to_string(system.size()));
    }
    r = *residual_at_start;
  } else {
    system.Evaluate(*x, &r, nullptr);
    ++summary.evaluations;
  }
  double norm = r.norm() / scale;
  summary.initial_residual = summary.final_residual = norm;
  if (!std::isfinite(norm)) {
    summary.status = SolverStatus::kDiverged;
    summary.message = "non-finite residual at the start point";
    return summary;
  }
  for (;;) {
    if (norm <= options.residual_tolerance) {
      summary.status = SolverStatus::kConverged;
      return summary;
    }
    if (summary.iterations >= options.max_iterations) {
      summary.status = SolverStatus::kMaxIterations;
      return summary;
    }
    ++summary.iterations;
    Eigen::VectorXd dx;
    // Inexact Newton (Eisenstat & Walker's second forcing term): a loose linear solve while
    // ‖R‖ falls slowly, down to krylov_tolerance as the iteration closes in, but never past
    // what the residual tolerance needs (krylov_oversolve).
    const double ratio = previous_norm > 0.0 ? norm / previous_norm : 1.0;
    const double enough = options.krylov_oversolve * options.residual_tolerance / norm;
    const double forcing =
        std::clamp(std::max(0.9 * ratio * ratio, enough), options.krylov_tolerance, 0.1);
    if (!stepper.Step(*x, forcing, &r, &dx, &summary)) return summary;
    if (!dx.allFinite()) {
      summary.status = SolverStatus::kSingular;
      summary.message = "non-finite Newton step";
      return summary;
    }
    // Round-off floor: the full Newton correction is negligible and the residual is within
    // a thousand times the tolerance (sums of large, cancelling contact forces).
    if (dx.norm() <= options.converged_step * x->norm() &&
        norm <= 1e3 * options.residual_tolerance) {
      summary.status = SolverStatus::kConverged;
      summary.message = "converged on the step size at the round-off floor";
      return summary;
    }
    const double t = LineSearch(system, options, *x, dx, norm, scale, &x_trial, &r_trial, &summary);
    if (t == 0.0) {
      summary.status = SolverStatus::kDiverged;
      summary.message = "line search found no decrease of |R|";
      return summary;
    }
    previous_norm = norm;
    const double step = t * dx.norm();
    x->swap(x_trial);  // x + t dx, whose residual the line search evaluated
    r.swap(r_trial);
    stepper.Moved();
    norm = r.norm() / scale;
    summary.final_residual = norm;
    if (!std::isfinite(norm) || norm > options.divergence_factor * summary.initial_residual) {
      summary.status = SolverStatus::kDiverged;
      summary.message = "residual grew past divergence_factor";
      return summary;
    }
    if (norm > options.residual_tolerance &&
        step <= options.step_tolerance * (x->norm() + 1e-300)) {
      summary.status = SolverStatus::kMaxIterations;
      summary.message = "stagnated: step below step_tolerance";
      return summary;
    }
    if (options.stall_window > 0) {
      norms.push_back(norm);
      const std::ptrdiff_t w = options.stall_window, n = std::ssize(norms);
      const double before = n > w ? norms[n - 1 - w] : summary.initial_residual;
      if (n >= w && norm > options.residual_tolerance &&
          norm > (1.0 - options.stall_decrease) * before) {
        summary.status = SolverStatus::kMaxIterations;
        summary.message = "stalled: |R| fell by less than stall_decrease over stall_window steps";
        return summary;
      }
    }
  }
}

}  // namespace

NewtonSummary SolveNewtonPreconditioned(const SquareSystem& system, const NewtonOptions& options,
                                        NewtonPreconditioner preconditioner, Eigen::VectorXd* x,
                                        std::shared_ptr<const dense::Lu>* factorization,
                                        const Eigen::VectorXd* residual_at_start) {
  NewtonStepper stepper(system, options, preconditioner);
  const NewtonSummary summary = RunNewton(system, options, stepper, x, residual_at_start);
  if (factorization != nullptr && stepper.factorization()) *factorization = stepper.factorization();
  return summary;
}

}  // namespace fricrom
