#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "fricrom/solve.h"
#include "linear/dense_lapack.h"
#include "linear/gmres.h"
#include "solve/newton_preconditioned.h"

namespace fricrom {

std::string ToString(ContinuationStatus status) {
  switch (status) {
    case ContinuationStatus::kReachedEnd:
      return "reached_end";
    case ContinuationStatus::kStepTooSmall:
      return "step_too_small";
    case ContinuationStatus::kMaxPoints:
      return "max_points";
    case ContinuationStatus::kStartFailed:
      return "start_failed";
    case ContinuationStatus::kStopped:
      return "stopped";
  }
  return "unknown";
}

bool ContinuationOptions::IsValid(std::string* error) const {
  auto bad = [&](const std::string& msg) {
    *error = "ContinuationOptions." + msg;
    return false;
  };
  if (!std::isfinite(lambda_start) || !std::isfinite(lambda_end) || lambda_start == lambda_end) {
    return bad("lambda_start and lambda_end must be finite and different");
  }
  if (!(lambda_scale > 0.0) || !(x_scale > 0.0)) return bad("lambda_scale and x_scale must be > 0");
  if (!(min_step > 0.0) || !(initial_step >= min_step) || !(max_step >= initial_step)) {
    return bad("steps must satisfy 0 < min_step <= initial_step <= max_step");
  }
  if (max_points < 1) return bad("max_points must be >= 1");
  if (target_iterations < 1) return bad("target_iterations must be >= 1");
  if (!(turning_tolerance >= 0.0)) return bad("turning_tolerance must be >= 0");
  if (max_corrector_iterations < 0 || max_corrector_backtracks < -1) {
    return bad("max_corrector_iterations must be >= 0 and max_corrector_backtracks >= -1");
  }
  return corrector.IsValid(error);
}

std::string ContinuationSummary::BriefReport() const {
  std::ostringstream s;
  s << "Continuation: " << ToString(status) << ", " << points << " points, " << turning_points
    << " turning points, " << rejected_steps << " rejected steps, " << evaluations
    << " evaluations";
  if (!message.empty()) s << " [" << message << "]";
  return s.str();
}

namespace {

// The system in scaled variables z = (x / x_scale, λ / λ_scale), residual divided by its scale.
struct Scaled {
  const ParametricSystem& sys;
  double xs, ls, rs;
  int n() const { return sys.size(); }
  void Eval(const Eigen::VectorXd& z, Eigen::VectorXd* g, Eigen::MatrixXd* dg) const {
    Eigen::VectorXd r, rl;
    Eigen::MatrixXd j;
    sys.Evaluate(xs * z.head(n()), ls * z[n()], &r, dg ? &j : nullptr, dg ? &rl : nullptr);
    *g = r / rs;
    if (dg) {
      dg->resize(n(), n() + 1);
      dg->leftCols(n()) = j * (xs / rs);
      dg->col(n()) = rl * (ls / rs);
    }
  }
};

// The bordered Jacobian [G_z; rowᵀ] of the scaled system at z, applied matrix-free:
// G_z = [∂R/∂x · x_scale, ∂R/∂λ · λ_scale] / residual scale.
class BorderedOperator : public JacobianOperator {
 public:
  // nullptr where the system offers no matrix-free ∂R/∂x.
  static std::unique_ptr<BorderedOperator> At(const Scaled& s, const Eigen::VectorXd& z,
                                              const Eigen::VectorXd& row) {
    Eigen::VectorXd rl;
    std::unique_ptr<JacobianOperator> jx =
        s.sys.Linearize(s.xs * z.head(s.n()), s.ls * z[s.n()], &rl);
    if (!jx) return nullptr;
    return std::unique_ptr<BorderedOperator>(
        new BorderedOperator(std::move(jx), rl * (s.ls / s.rs), s.xs / s.rs, row));
  }
  void Apply(const Eigen::VectorXd& v, bool transposed, Eigen::VectorXd* out) const override {
    const Eigen::Index n = column_.size();
    Eigen::VectorXd head;
    jx_->Apply(v.head(n), transposed, &head);
    out->resize(n + 1);
    if (!transposed) {
      out->head(n) = x_factor_ * head + v[n] * column_;
      (*out)[n] = row_.dot(v);
    } else {
      out->head(n) = x_factor_ * head + v[n] * row_.head(n);
      (*out)[n] = column_.dot(v.head(n)) + v[n] * row_[n];
    }
  }

 private:
  BorderedOperator(std::unique_ptr<JacobianOperator> jx, Eigen::VectorXd column, double x_factor,
                   const Eigen::VectorXd& row)
      : jx_(std::move(jx)), column_(std::move(column)), x_factor_(x_factor), row_(row) {}
  std::unique_ptr<JacobianOperator> jx_;
  Eigen::VectorXd column_;  // ∂G/∂z_λ
  double x_factor_;
  Eigen::VectorXd row_;
};

// Fixed λ: plain square system in x.
struct FixedLambda : SquareSystem {
  const ParametricSystem& sys;
  double lambda;
  FixedLambda(const ParametricSystem& s, double l) : sys(s), lambda(l) {}
  int size() const override { return sys.size(); }
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    sys.Evaluate(x, lambda, r, j, nullptr);
  }
  double ResidualScale() const override { return sys.ResidualScale(); }
};

// Corrector: G(z) = 0 on the hyperplane τᵀ(z − z_pred) = 0.
struct Corrector : SquareSystem {
  const Scaled& s;
  Eigen::VectorXd tau, z_pred;
  Corrector(const Scaled& sc, Eigen::VectorXd t, Eigen::VectorXd zp)
      : s(sc), tau(std::move(t)), z_pred(std::move(zp)) {}
  int size() const override { return s.n() + 1; }
  void Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override {
    Eigen::VectorXd g;
    Eigen::MatrixXd dg;
    s.Eval(z, &g, j ? &dg : nullptr);
    r->resize(s.n() + 1);
    r->head(s.n()) = g;
    (*r)[s.n()] = tau.dot(z - z_pred);
    if (j) {
      j->resize(s.n() + 1, s.n() + 1);
      j->topRows(s.n()) = dg;
      j->row(s.n()) = tau.transpose();
    }
  }
  // Newton's GMRES steps on the matrix-free bordered Jacobian where the system offers one (a
  // dense (n+1)² Jacobian per corrector iteration cost most of a continuation on the condensed
  // FE balance); the dense one only where GMRES misses and a new LU is due.
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& z) const override {
    return BorderedOperator::At(s, z, tau);
  }
};

// Unit tangent of the branch at z, oriented along `previous`. Large systems first try GMRES
// preconditioned with `near` (the corrector's last LU: the same bordered matrix [G_z; previousᵀ]
// at a nearby z), on the matrix-free bordered operator where the system offers one, else on the
// dense matrix; the dense matrix and a new LU only if that misses.
bool Tangent(const Scaled& s, const Eigen::VectorXd& z, const Eigen::VectorXd& previous,
             const dense::Lu* near, Eigen::VectorXd* tau) {
  constexpr double kTolerance = 1e-10;
  constexpr int kProducts = 20;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(s.n() + 1);
  rhs[s.n()] = 1.0;
  const bool krylov =
      near != nullptr && near->rows() == s.n() + 1 && s.n() + 1 >= dense::kLapackMinSize;
  bool solved = false;
  bool dense_krylov = krylov;  // GMRES on the dense matrix where no matrix-free one was tried
  if (krylov) {
    if (const std::unique_ptr<BorderedOperator> op = BorderedOperator::At(s, z, previous)) {
      dense_krylov = false;
      const dense::LinearMap apply = [&op](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
        op->Apply(v, false, out);
      };
      solved = dense::PreconditionedGmres(apply, *near, false, rhs, kTolerance, kProducts, tau)
                   .converged;
    }
  }
  Eigen::MatrixXd a;
  if (!solved) {
    Eigen::VectorXd g;
    Eigen::MatrixXd dg;
    s.Eval(z, &g, &dg);
    a.resize(s.n() + 1, s.n() + 1);
    a.topRows(s.n()) = dg;
    a.row(s.n()) = previous.transpose();
  }
  if (!solved && dense_krylov) {
    solved = dense::PreconditionedGmres(a, false, *near, false, rhs, kTolerance, kProducts, tau)
                 .converged;
  }
  if (!solved) {
    const dense::Lu lu(a);
    if (!(lu.rcond() > 1e-15)) return false;
    *tau = lu.Solve(rhs);
  }
  if (!tau->allFinite()) return false;
  tau->normalize();
  if (tau->dot(previous) < 0.0) *tau = -*tau;
  return true;
}

// Folds in λ: a fold counts once λ has come back from its running extreme by more than the
// tolerance (the sampled contact law makes the branch piecewise smooth, with sub-tolerance
// zig-zags).
struct FoldTracker {
  double travel;   // +1 while λ grows, −1 while it falls
  double extreme;  // the running extreme of λ in the direction of travel
  // True if the new λ completes a fold.
  bool Turned(double lambda, double tolerance) {
    if ((lambda - extreme) * travel > 0.0) {
      extreme = lambda;
      return false;
    }
    if (std::abs(lambda - extreme) <= tolerance) return false;
    travel = -travel;
    extreme = lambda;
    return true;
  }
};

// The point at λ_end: interpolated between z and z_new (which straddle it), corrected by Newton
// at fixed λ; *z_end is meaningful when the returned solve is usable.
NewtonSummary SolveAtEnd(const ParametricSystem& system, const ContinuationOptions& options,
                         const Scaled& s, const Eigen::VectorXd& z, const Eigen::VectorXd& z_new,
                         Eigen::VectorXd* z_end) {
  const int n = s.n();
  const double lambda_end_scaled = options.lambda_end / s.ls;
  const double f = (lambda_end_scaled - z[n]) / (z_new[n] - z[n]);
  Eigen::VectorXd x_end = s.xs * (z.head(n) + f * (z_new.head(n) - z.head(n)));
  NewtonSummary es =
      SolveNewton(FixedLambda(system, options.lambda_end), options.corrector, &x_end);
  z_end->resize(n + 1);
  *z_end << x_end / s.xs, lambda_end_scaled;
  return es;
}

// The next arc-length step: doubled at no corrector iterations, halved at twice the target.
double NextStep(const ContinuationOptions& options, double ds, int corrector_iterations) {
  const double factor =
      std::pow(2.0, static_cast<double>(options.target_iterations - corrector_iterations) /
                        options.target_iterations);
  return std::clamp(ds * std::clamp(factor, 0.5, 2.0), options.min_step, options.max_step);
}

}  // namespace

ContinuationSummary Continue(const ParametricSystem& system, const ContinuationOptions& options,
                             const Eigen::VectorXd& x0, const ContinuationCallback& on_point) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (x0.size() != system.size()) {
    throw std::invalid_argument("Continue: x0 must have size " + std::to_string(system.size()));
  }
  ContinuationSummary summary;
  const int n = system.size();
  const double dir = options.lambda_end > options.lambda_start ? 1.0 : -1.0;
  Scaled s{system, options.x_scale, options.lambda_scale, system.ResidualScale()};

  // Starting point.
  Eigen::VectorXd x = x0;
  NewtonSummary start =
      SolveNewton(FixedLambda(system, options.lambda_start), options.corrector, &x);
  summary.evaluations += start.evaluations;
  if (!start.IsSolutionUsable()) {
    summary.status = ContinuationStatus::kStartFailed;
    summary.message = start.BriefReport();
    return summary;
  }
  Eigen::VectorXd z(n + 1);
  z << x / s.xs, options.lambda_start / s.ls;
  auto emit = [&](const Eigen::VectorXd& zz, int iters, bool turned) {
    ContinuationPoint p;
    p.lambda = zz[n] * s.ls;
    p.x = zz.head(n) * s.xs;
    p.corrector_iterations = iters;
    p.turning_point_before = turned;
    ++summary.points;
    return on_point ? on_point(p) : true;
  };
  if (!emit(z, start.iterations, false)) {
    summary.status = ContinuationStatus::kStopped;
    return summary;
  }
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(n + 1);
  tau[n] = dir;
  if (!Tangent(s, z, tau, nullptr, &tau)) {
    summary.status = ContinuationStatus::kStartFailed;
    summary.message = "singular tangent system at the start point";
    return summary;
  }
  const double lambda_end_scaled = options.lambda_end / s.ls;
  std::shared_ptr<const dense::Lu> lu;  // the last factorised bordered Jacobian
  double ds = options.initial_step;
  FoldTracker folds{dir, z[n]};
  while (summary.points < options.max_points) {
    Eigen::VectorXd z_new = z + ds * tau;
    Corrector corr(s, tau, z_new);
    NewtonOptions copts = options.corrector;
    copts.max_iterations = std::min(copts.max_iterations, options.max_corrector_iterations > 0
                                                              ? options.max_corrector_iterations
                                                              : 3 * options.target_iterations + 4);
    if (options.max_corrector_backtracks >= 0) {
      copts.max_backtracks = options.max_corrector_backtracks;
    }
    // The last bordered LU preconditions the corrector's GMRES steps (large systems), and the
    // corrector's own LU the tangent solve: consecutive points differ little.
    std::shared_ptr<const dense::Lu> lu_new;
    NewtonSummary cs = SolveNewtonPreconditioned(corr, copts, NewtonPreconditioner{lu.get(), false},
                                                 &z_new, &lu_new);
    summary.evaluations += cs.evaluations;
    if (lu_new) lu = lu_new;
    Eigen::VectorXd tau_new;
    const bool usable = cs.IsSolutionUsable();
    if (usable && options.secant_predictor) {
      tau_new = z_new - z;
      if (!(tau_new.norm() > 0.0) || !tau_new.allFinite()) {
        if (!Tangent(s, z_new, tau, lu.get(), &tau_new)) tau_new.resize(0);
      } else {
        tau_new.normalize();
      }
    }
    if (!usable || (options.secant_predictor ? tau_new.size() == 0
                                             : !Tangent(s, z_new, tau, lu.get(), &tau_new))) {
      ++summary.rejected_steps;
      ds *= 0.5;
      if (ds < options.min_step) {
        summary.status = ContinuationStatus::kStepTooSmall;
        summary.message = "at lambda = " + std::to_string(z[n] * s.ls) + ": " + cs.BriefReport();
        return summary;
      }
      continue;
    }
    // Past the end: land exactly on λ_end from the interpolated state, then stop.
    if (dir * (z_new[n] - lambda_end_scaled) >= 0.0) {
      Eigen::VectorXd z_end;
      const NewtonSummary es = SolveAtEnd(system, options, s, z, z_new, &z_end);
      summary.evaluations += es.evaluations;
      if (es.IsSolutionUsable()) emit(z_end, es.iterations, false);
      summary.status = ContinuationStatus::kReachedEnd;
      return summary;
    }
    const bool turned = folds.Turned(z_new[n], options.turning_tolerance);
    if (turned) ++summary.turning_points;
    z = z_new;
    tau = tau_new;
    if (!emit(z, cs.iterations, turned)) {
      summary.status = ContinuationStatus::kStopped;
      return summary;
    }
    ds = NextStep(options, ds, cs.iterations);
    // The arclength measures x against x_scale: where the solution has grown well beyond it (a
    // resonance of a response that started small), steps of max_step crawl in λ. The scale
    // follows the solution's size upwards, the state and tangent rescaled with it.
    const double size = s.xs * z.head(n).norm();
    if (options.adapt_x_scale && size > 2.0 * s.xs) {
      const double shrink = s.xs / size;
      z.head(n) *= shrink;
      tau.head(n) *= shrink;
      tau.normalize();
      s.xs = size;
      lu.reset();
    }
  }
  summary.status = ContinuationStatus::kMaxPoints;
  return summary;
}

}  // namespace fricrom
