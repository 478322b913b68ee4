// ImproveBounds: bound runs from harmonic-balance solutions found by other routes (time
// integration, samples, neighbouring frequencies), merged into an existing result.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "bound_runs.h"
#include "fricrom/bounds.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "fricrom/units.h"
#include "optimise_bounds.h"

namespace fricrom {
namespace {

// A bound moves outwards only by more than the solvers' noise.
constexpr double kMoveMargin = 1e-9;

bool Beats(const BoundsOptions& options, const BoundSolution& cand, const BoundSolution& bound,
           bool is_max) {
  if (!cand.IsUsable()) return false;
  if (!bound.IsUsable()) return true;
  return bounds_detail::LiesBeyond(cand, bound, options.objective, is_max, kMoveMargin);
}

// A known solution belongs to a nearby problem (another frequency, or H = 1 embedded at H):
// where Newton from it fails, the residual homotopy from it usually reaches this problem's
// solution in a few points, where StartSolution's cold routes (α homotopy, continuations in
// frequency) cost minutes near a resonance (FE cascade, H = 3 refinement at 1098.98 Hz: 300 s).
bool FromNearbyPoint(const HarmonicBalance& system, double omega, const Eigen::VectorXd& alpha,
                     const Eigen::VectorXd& x0, Eigen::VectorXd* x) {
  constexpr int kHomotopyPoints = 40;  // as a seed's fallback path (bound_common.cpp)
  FrfOptions o;
  o.fallback_max_points = kHomotopyPoints;
  int evaluations = 0;
  return SolveFromNearbyPoint(system, alpha, omega, x0, o, x, &evaluations);
}

// The objective φ of a held bound (a1² + b1², or η; NaN if it is no bound): runs that cannot
// reach it are dominated.
double HeldObjective(const BoundsOptions& options, const BoundSolution& b) {
  if (!b.IsUsable()) return std::numeric_limits<double>::quiet_NaN();
  return options.objective == BoundsOptions::kAmplitude ? b.amplitude * b.amplitude : b.loss_factor;
}

}  // namespace

int ImproveBounds(const HarmonicBalance& system, double freq_hz, const BoundsOptions& options,
                  const std::vector<KnownSolution>& known, BoundsResult* bounds) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (bounds == nullptr || bounds->freq_hz != freq_hz) {
    throw std::invalid_argument("ImproveBounds: the bounds are not those of this frequency");
  }
  for (const KnownSolution& k : known) {
    if (k.x.size() != system.num_unknowns() || k.alpha.size() != system.num_alpha()) {
      throw std::invalid_argument(
          "ImproveBounds: a known solution has " + std::to_string(k.x.size()) + " unknowns and " +
          std::to_string(k.alpha.size()) + " alpha, the system " +
          std::to_string(system.num_unknowns()) + " and " + std::to_string(system.num_alpha()));
    }
  }
  if (known.empty()) return 0;
  const double omega = RadPerS(freq_hz);
  const BoundSolution before[2] = {bounds->min, bounds->max};
  // The known solutions themselves, where Newton converges on them at this frequency.
  std::vector<Eigen::VectorXd> seeds, xs;
  std::vector<int> directions;
  std::vector<bool> short_starts;
  for (const KnownSolution& k : known) {
    Eigen::VectorXd x = k.x;
    const Eigen::VectorXd alpha = k.alpha.cwiseMax(-1.0).cwiseMin(1.0);
    const bool solved =
        SolveNewton(HbmAtFrequency(system, omega, alpha), NewtonOptions{}, &x).IsSolutionUsable() ||
        FromNearbyPoint(system, omega, alpha, k.x, &x);
    if (!solved && !k.cold_start) continue;
    seeds.push_back(alpha);
    directions.push_back((k.run_min ? 1 : 0) | (k.run_max ? 2 : 0));
    short_starts.push_back(!solved && k.start_short_of_alpha);
    if (!solved) {
      // StartSolution's usual routes only (the same Newton would fail again there).
      xs.emplace_back();
      continue;
    }
    xs.push_back(x);
    BoundSolution s;
    s.x = x;
    s.alpha = alpha;
    s.status = BoundStatus::kConverged;
    s.message = "known solution (Newton from a solution found by another route)";
    bounds_detail::Describe(system, omega, &s);
    if (!(s.residual <= bounds_detail::kFeasibility)) continue;
    for (bool is_max : {false, true}) {
      BoundSolution& b = is_max ? bounds->max : bounds->min;
      if (Beats(options, s, b, is_max)) b = s;
    }
  }
  if (seeds.empty()) return 0;  // every known solution dropped (cold_start false)
  BoundsOptions o = options;
  o.seed_groups.clear();
  o.random_seeds = 0;
  o.check_samples = 0;
  o.progress = nullptr;
  const BoundSolution kept[2] = {bounds->min, bounds->max};
  // A run from a known solution that cannot reach the bound already held here is stopped as
  // dominated (o.stop_dominated_runs), as one that cannot reach a KKT start's.
  const BoundsResult fresh = OptimiseBounds(system, freq_hz, o, seeds, xs, directions, short_starts,
                                            {HeldObjective(o, kept[0]), HeldObjective(o, kept[1])});
  MergeBounds(fresh, o.objective, bounds);
  int moved = 0;
  for (bool is_max : {false, true}) {
    BoundSolution& b = is_max ? bounds->max : bounds->min;
    // A tie on a plateau of the response over α keeps the solution held before, unless only the
    // runs' tying point is stationary (a known solution a run found to be a KKT point).
    if (!Beats(options, b, kept[is_max], is_max)) b = kept[is_max];
    const BoundSolution& run = is_max ? fresh.max : fresh.min;
    if (!b.stationary && run.stationary && !Beats(options, b, run, is_max)) b = run;
    // No run in this direction converged, but one stopped at its iteration limit beyond the bound.
    BoundSolution unfinished;
    if (bounds_detail::UsableUnfinished(system, omega, run, &unfinished) &&
        Beats(options, unfinished, b, is_max)) {
      b = std::move(unfinished);
    }
    moved += Beats(options, b, before[is_max], is_max);
  }
  return moved;
}

}  // namespace fricrom
