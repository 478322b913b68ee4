// The optimisation stage of ComputeBounds, shared with its sample check (sample_check.cpp).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <limits>
#include <vector>

#include "fricrom/bounds.h"

namespace fricrom {

// Bounds from the given α seeds only (no sample check); options must be valid, seeds non-empty.
// known_x: empty, or per seed a solution (maybe empty) that Newton starts from first.
// directions: empty (both), or per seed a mask of the runs to make: 1 minimum, 2 maximum response.
// short_starts: empty (none), or per seed whether its start may lie short of its α on the α
// homotopy (KnownSolution::start_short_of_alpha).
// held: the objective φ (a1² + b1², or η) of the [minimum, maximum] bound the caller already
// holds at this frequency and harmonic count (NaN: none). With the starts' KKT points it is what
// a run must be able to reach not to be stopped as dominated (BoundsOptions::stop_dominated_runs).
BoundsResult OptimiseBounds(
    const HarmonicBalance& system, double freq_hz, const BoundsOptions& options,
    const std::vector<Eigen::VectorXd>& seeds, const std::vector<Eigen::VectorXd>& known_x = {},
    const std::vector<int>& directions = {}, const std::vector<bool>& short_starts = {},
    std::array<double, 2> held = {std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::quiet_NaN()});

// OptimiseBounds from the given seeds, then the sample check (BoundsOptions::check_samples) with
// its restarts: ComputeBounds' search at one H, for callers that choose the seeds themselves (the
// α levels, level_search.cpp). Options must be valid.
BoundsResult SearchFromSeeds(const HarmonicBalance& system, double freq_hz,
                             const BoundsOptions& options,
                             const std::vector<Eigen::VectorXd>& seeds,
                             const std::vector<Eigen::VectorXd>& known_x = {},
                             const std::vector<int>& directions = {});

// The sample check of *result at `system`'s own H (BoundsOptions::check_samples random α with
// sample_seed): a sample beyond a bound restarts the optimiser from it, and the bound becomes the
// best of the bound, the restart and the sample. seeds_before numbers the restart's seeds after
// the search's own. refined (the check after the ladder's refinement at H): the samples are
// solved without the continuations in frequency and the restart starts on the sample's solution
// (else: the search's check, every fallback, the restart cold at the sample's α). Does nothing
// without α or with check_samples = 0.
void CheckBoundsBySamples(const HarmonicBalance& system, double freq_hz,
                          const BoundsOptions& options, int seeds_before, bool refined,
                          BoundsResult* result);

// The harmonic ladder's sample check at the system's H, after the refinement of the H = 1 optima
// (both bounds usable; else nothing): the H = 1 optima are local at H where α moves the response
// by less than the truncation of the harmonics does (disk24 at its peak: the H = 1 maximum
// 3e-5 below the one at H = 3, a uniform α per interface that no refinement run reached). The
// restarts take the refinement's settings and start on the samples' solutions.
void CheckRefinedBounds(const HarmonicBalance& system, double freq_hz, const BoundsOptions& options,
                        BoundsResult* result);

}  // namespace fricrom
