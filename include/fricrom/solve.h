// Nonlinear solvers: globalised Newton for R(x) = 0 and pseudo-arclength continuation of
// R(x, λ) = 0 in a scalar parameter λ (frequency). They see problems only through the two small
// interfaces below, so the lumped model, reduced FE models and condensed models all plug in.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace fricrom {

enum class SolverStatus { kConverged, kMaxIterations, kSingular, kDiverged };
std::string ToString(SolverStatus status);

// Products with a Jacobian without forming it: J v, or Jᵀ v when `transposed`.
class JacobianOperator {
 public:
  virtual ~JacobianOperator() = default;
  virtual void Apply(const Eigen::VectorXd& v, bool transposed, Eigen::VectorXd* out) const = 0;
};

// R(x) = 0 with a dense Jacobian.
class SquareSystem {
 public:
  virtual ~SquareSystem() = default;
  virtual int size() const = 0;
  virtual void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* residual,
                        Eigen::MatrixXd* jacobian) const = 0;  // jacobian may be null
  virtual double ResidualScale() const { return 1.0; }         // tolerances are relative to it
  // The Jacobian at x as an operator, where the system applies it for less than it costs to
  // form (the condensed balance); nullptr, the default, where not. Newton's GMRES steps then
  // need no dense Jacobian.
  virtual std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& /*x*/) const {
    return nullptr;
  }
};

// R(x, λ) = 0: the family continuation follows.
class ParametricSystem {
 public:
  virtual ~ParametricSystem() = default;
  virtual int size() const = 0;
  virtual void Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* residual,
                        Eigen::MatrixXd* jacobian, Eigen::VectorXd* dr_dlambda) const = 0;
  virtual double ResidualScale() const { return 1.0; }
  // ∂R/∂x at (x, λ) as an operator, with ∂R/∂λ in *dr_dlambda, where the system applies it for
  // less than it costs to form (SquareSystem::Linearize); nullptr, the default, where not. The
  // continuation's corrector and tangent solves then need no dense Jacobian while GMRES with an
  // earlier LU converges.
  virtual std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& /*x*/,
                                                      double /*lambda*/,
                                                      Eigen::VectorXd* /*dr_dlambda*/) const {
    return nullptr;
  }
};

struct NewtonOptions {
  int max_iterations = 60;
  double residual_tolerance = 1e-10;  // ‖R‖ ≤ tol · ResidualScale()
  double step_tolerance = 1e-13;      // relative step that counts as stagnation
  double converged_step = 1e-12;      // relative Newton step accepted as converged when
                                      // ‖R‖ ≤ 1e3 · residual_tolerance · scale
  int max_backtracks = 30;            // Armijo backtracking steps per iteration
  double armijo = 1e-4;
  double divergence_factor = 1e8;  // ‖R‖ growing past factor·‖R0‖ → diverged
  // Stall test, off when 0: stop (kMaxIterations) once ‖R‖ has fallen by less than the fraction
  // stall_decrease over the last stall_window iterations. Newton on the piecewise-smooth contact
  // residual can crawl at one ‖R‖ for its whole iteration budget; where a failed solve is cheap
  // to replace (the bound optimiser's line search halves its step) this ends it early.
  int stall_window = 0;
  double stall_decrease = 0.01;
  // Systems of at least this many unknowns solve each Newton step first by GMRES preconditioned
  // with the LU of the last factorised Jacobian and factorise anew only when GMRES misses
  // krylov_tolerance (relative) within krylov_max_iterations products; 0 = a new LU every step.
  // Their new LUs are single precision (GMRES restores double accuracy; a double LU if it
  // misses). The default keeps small (lumped) systems on the plain LU route, bit for bit.
  // 20 products: a product costs a small fraction of a new LU
  // (docs/decisions/0009-matrix-free-newton.md).
  int krylov_min_size = 96;
  int krylov_max_iterations = 20;
  double krylov_tolerance = 1e-9;
  // No GMRES step is solved past krylov_oversolve · residual_tolerance / (‖R‖/scale) relative:
  // a linear residual far below the Newton tolerance buys nothing (Kelley 1995, §6.3, the
  // safeguard on the Eisenstat-Walker forcing term). 0 switches it off.
  double krylov_oversolve = 0.5;
  bool IsValid(std::string* error) const;
};

struct NewtonSummary {
  SolverStatus status = SolverStatus::kMaxIterations;
  std::string message;
  int iterations = 0;
  int evaluations = 0;
  int factorizations = 0;         // dense LUs of the Jacobian (single or double precision)
  int krylov_iterations = 0;      // GMRES products
  double initial_residual = 0.0;  // ‖R‖ / scale
  double final_residual = 0.0;
  bool IsSolutionUsable() const { return status == SolverStatus::kConverged; }
  std::string BriefReport() const;
};

// Damped Newton with Armijo backtracking on ½‖R‖². Throws std::invalid_argument on bad options
// or a start vector of the wrong size; numerical failure is reported in the summary.
NewtonSummary SolveNewton(const SquareSystem& system, const NewtonOptions& options,
                          Eigen::VectorXd* x);

struct ContinuationOptions {
  double lambda_start = 0.0;
  double lambda_end = 1.0;
  double lambda_scale = 1.0;   // λ is scaled by this in the arclength norm
  double x_scale = 1.0;        // x likewise (e.g. a reference amplitude)
  double initial_step = 1e-2;  // scaled arclength
  double min_step = 1e-6;
  double max_step = 5e-2;
  int max_points = 5000;
  int target_iterations = 4;        // corrector iterations the step control aims for
  double turning_tolerance = 1e-4;  // scaled λ retreat that counts as a turning point
  // x_scale follows |x| upwards (doubling or more): the arclength of a branch whose solution grows
  // by orders of magnitude (an FRF into a resonance) is measured against its current size.
  bool adapt_x_scale = false;
  // The predictor's direction: the secant through the last two points instead of the tangent
  // solved at the last point (one linear solve a point saved; on a branch with many kinks the
  // secant is also the better guess, the tangent of one smooth piece pointing off the next).
  bool secant_predictor = false;
  // Corrector budget: iterations (0: 3 × target_iterations + 4) and line-search backtracks per
  // iteration (−1: corrector.max_backtracks). A corrector that needs more is a step too long:
  // halving it is cheaper than a long damped Newton at a kink.
  int max_corrector_iterations = 0;
  int max_corrector_backtracks = -1;
  NewtonOptions corrector;
  bool IsValid(std::string* error) const;
};

struct ContinuationPoint {
  double lambda = 0.0;
  Eigen::VectorXd x;
  int corrector_iterations = 0;
  bool turning_point_before = false;  // λ turned back (beyond turning_tolerance) at this point
};

enum class ContinuationStatus { kReachedEnd, kStepTooSmall, kMaxPoints, kStartFailed, kStopped };
std::string ToString(ContinuationStatus status);

struct ContinuationSummary {
  ContinuationStatus status = ContinuationStatus::kMaxPoints;
  std::string message;
  int points = 0;
  int turning_points = 0;
  int rejected_steps = 0;
  int evaluations = 0;
  bool IsSolutionUsable() const { return status == ContinuationStatus::kReachedEnd; }
  std::string BriefReport() const;
};

// Called with every accepted point; return false to stop.
using ContinuationCallback = std::function<bool(const ContinuationPoint&)>;

// Follows the branch through x0 at λ_start (x0 is first corrected by Newton) until λ leaves
// [min(λ_start, λ_end), max(...)] beyond λ_end. Passes turning points.
ContinuationSummary Continue(const ParametricSystem& system, const ContinuationOptions& options,
                             const Eigen::VectorXd& x0, const ContinuationCallback& on_point);

}  // namespace fricrom
