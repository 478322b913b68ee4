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

}  // namespace fricrom
