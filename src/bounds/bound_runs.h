// Private to src/bounds: what the bound driver (bounds.cpp), the reduced-space method
// (reduced_bounds.cpp) and the Ipopt method (ipopt_bounds.cpp) share: the setup of one run,
// its objective, the description of a returned point, and the two optimisers.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "fricrom/bounds.h"
#include "fricrom/harmonic_balance.h"
#include "linear/dense_lapack.h"

namespace fricrom::bounds_detail {

// A returned point counts as a solution only if ‖R‖ ≤ kFeasibility · ResidualScale().
inline constexpr double kFeasibility = 1e-6;

struct RunSetup {
  const HarmonicBalance* system = nullptr;
  double omega = 0.0;
  BoundsOptions::Objective objective = BoundsOptions::kAmplitude;
  double sign = 1.0;              // +1 minimises the objective, −1 maximises it
  double objective_scale = 1.0;   // objective divided by this
  double stall_tolerance = 1e-9;  // relative objective change that counts as no change
  Eigen::VectorXd x_scale;        // x = x_scale ∘ z
  double residual_scale = 1.0;    // constraints g = R / residual_scale
  // The best objective (same units: sign·φ/objective_scale) a KKT start or the bound the caller
  // holds already gives in this run's direction, NaN if none or not to be used: the
  // reduced-space run stops once it cannot reach it (BoundsOptions::stop_dominated_runs).
  double incumbent = std::numeric_limits<double>::quiet_NaN();
  int line_search_memory = 1;  // BoundsOptions::line_search_memory
  // A run stops once its objective is at or below this (BoundsOptions::minimum_stop_m).
  double stop_below = -std::numeric_limits<double>::infinity();
  // A reduced-space run is stationary once its objective changes by at most this (relative)
  // in 3 accepted iterations in a row (BoundsOptions::stationary_change).
  double stationary_change = 1e-7;
  // ... or once its best objective improved by at most stall_change (relative) over the last
  // stall_window accepted iterations (BoundsOptions::stall_change; window 0: never).
  double stall_change = 1e-4;
  int stall_window = 20;
  // Minimum runs of the amplitude objective try Gauss-Newton steps towards y = 0
  // (BoundsOptions::gauss_newton_minimum).
  bool gauss_newton = false;
  // Reduced-space runs step along limited-memory BFGS directions built from this many accepted
  // steps instead of the projected gradient (BoundsOptions::maximum_bfgs_memory; 0: gradient).
  int bfgs_memory = 0;
};

// The run's objective sign·φ(x, α)/objective_scale (φ = a1² + b1² of the response DOF, or η) and,
// when grad_x is given, its gradient in the unscaled variables. `e` must hold R at (x, α) for the
// loss factor, and the Jacobians as well for its gradient.
double Objective(const RunSetup& s, const Eigen::VectorXd& x, const Eigen::VectorXd& alpha,
                 const HbmEvaluation& e, Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_alpha);

// The reduced gradient of +φ/objective_scale at a start, its adjoint λ and the factorised
// (∂R/∂x)ᵀ that solved for λ: what a run from that start needs first (times its sign), so the
// KKT check's factorisation serves both runs instead of being made twice more.
struct StartGradient {
  Eigen::VectorXd g, lambda;
  std::shared_ptr<const dense::Lu> lu;  // null: none (the run computes its own)
};

// Whether the feasible start (x0, α0) already satisfies the first-order conditions on the box;
// `gradient` (if not null) receives what it computed, or keeps a null LU if it failed.
std::array<bool, 2> StartIsKktPoint(const RunSetup& s, const Eigen::VectorXd& x0,
                                    const Eigen::VectorXd& alpha0, double tolerance,
                                    const std::array<double, 2>& signs,
                                    StartGradient* gradient = nullptr);

std::vector<ContactRegime> Regimes(const HarmonicBalance& sys, const Eigen::VectorXd& x,
                                   double omega, const Eigen::VectorXd& alpha);

// The value bounds are ranked by: larger = more response (the maximum response minimises η).
inline double RankValue(const BoundSolution& s, BoundsOptions::Objective objective) {
  return objective == BoundsOptions::kAmplitude ? s.amplitude : -s.loss_factor;
}

// Whether `a` lies beyond `b` in the direction of the bound (more response for the maximum) by
// more than margin times |b|'s rank value.
inline bool LiesBeyond(const BoundSolution& a, const BoundSolution& b,
                       BoundsOptions::Objective objective, bool maximise_response, double margin) {
  const double va = RankValue(a, objective), vb = RankValue(b, objective);
  return (maximise_response ? va - vb : vb - va) > margin * std::abs(vb);
}

// Adds the run counts of `from` (seeds, failures, runs) to `into`, and with `checks` also its
// sample check's and refinement's counts.
inline void AddSearchCounts(const BoundsResult& from, bool checks, BoundsResult* into) {
  into->seeds_tried += from.seeds_tried;
  into->seeds_converged += from.seeds_converged;
  into->start_failures += from.start_failures;
  into->min_failures += from.min_failures;
  into->max_failures += from.max_failures;
  into->optimizer_runs += from.optimizer_runs;
  into->runs_abandoned += from.runs_abandoned;
  if (!checks) return;
  into->samples_checked += from.samples_checked;
  into->samples_failed += from.samples_failed;
  into->improved_by_samples += from.improved_by_samples;
  into->refinement_fallbacks += from.refinement_fallbacks;
}

// Fills the derived fields of a solution (x, α set).
void Describe(const HarmonicBalance& sys, double omega, BoundSolution* s);

// The last iterate of a run stopped at its iteration limit, made a (non-stationary) bound.
void MarkUnfinishedAsBound(BoundSolution* s);

// A failed bound of an OptimiseBounds result that is the feasible last iterate of a run stopped
// at its iteration limit (kept on record where no run in its direction converged), as a usable
// non-stationary bound in *out; false if it is none.
bool UsableUnfinished(const HarmonicBalance& sys, double omega, const BoundSolution& failed,
                      BoundSolution* out);

// A converged harmonic-balance solution at α to start from (see bound_common.cpp); `known`, if
// not empty, is tried first (a solution known from elsewhere: Newton keeps its branch). With
// `alpha_start` the start may lie short of α on the α homotopy from 0 (*alpha_start its α);
// without, it is at α or there is none.
bool StartSolution(const HarmonicBalance& sys, double freq_hz, const Eigen::VectorXd& alpha,
                   const std::vector<Eigen::VectorXd>& other_starts, Eigen::VectorXd* x,
                   const Eigen::VectorXd& known = Eigen::VectorXd(),
                   Eigen::VectorXd* alpha_start = nullptr);

// Reduced-space run over α (reduced_bounds.cpp); `start`, if not null and set, is the gradient
// at (x0, a0) from StartIsKktPoint with the same setup but the sign.
BoundSolution RunReduced(const RunSetup& s, const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                         int seed, int max_iterations, double tolerance,
                         const StartGradient* start = nullptr);

// Full-space runs over [x, α] by Ipopt (ipopt_bounds.cpp); one application and NLP reused over
// the runs of a bound computation. Ipopt's types stay in that file.
class IpoptBounds {
 public:
  IpoptBounds(const HarmonicBalance& system, const BoundsOptions& options);  // throws on failure
  ~IpoptBounds();
  IpoptBounds(const IpoptBounds&) = delete;
  IpoptBounds& operator=(const IpoptBounds&) = delete;
  BoundSolution Run(const RunSetup& setup, const Eigen::VectorXd& x0, const Eigen::VectorXd& alpha0,
                    int seed);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fricrom::bounds_detail
