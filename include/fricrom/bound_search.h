// The bound search over α levels (coarse to fine, alpha_levels.h): what a bound run does.
//
//   level 0 (interface):  corners of its box ranked by one fixed-α solve each, the best and
//                         worst started as local runs with the default seeds; sample check
//   level l (face, pair): local runs from level l−1's optima (a coarse α is a fine α); on the
//                         finest also the single-level search's seeds (the user's --seeds, else
//                         the default set) and random seeds; sample check; level l−1's optima
//                         kept as candidates, so level l's bounds contain level l−1's
//   harmonic ladder:      every level searched at H = 1, then refined at H level by level: a
//                         level's H = 1 optimum is refined only where it went beyond the coarser
//                         level's, and each level holds the coarser level's optima at H; the
//                         user's seeds are solved at H and held too
//
// A case with one level (lumped, or α per interface) is ComputeBounds unchanged.
#pragma once

#include <string>
#include <vector>

#include "fricrom/alpha_levels.h"
#include "fricrom/bounds.h"
#include "fricrom/harmonic_balance.h"

namespace fricrom {

struct LevelSearchOptions {
  std::vector<AlphaLevel> levels;  // coarsest first (AlphaLevelsOf); at most one: ComputeBounds
  // Starts of the coarsest level: 2^k corners of its box (k ≤ log2(max_corners) parameters, the
  // k whose ±1 change the response most when more), each solved once at fixed α; the
  // corner_starts largest and smallest responses start maximum and minimum runs.
  // 256: every corner of an 8-parameter interface level (two interfaces, two directions each),
  // cheap at H = 1 against the refinement at H (docs/decisions/0001-alpha-levels.md).
  int max_corners = 256;
  int corner_starts = 2;
  bool IsValid(std::string* error) const;
};

// The levels' search at the system's own H (no harmonic ladder: options.search_harmonics is
// ignored). The result's bounds are the finest level's; `levels` holds every level's.
BoundsResult SearchLevels(const HarmonicBalance& system, double freq_hz,
                          const BoundsOptions& options, const LevelSearchOptions& search);

// The harmonic ladder's second rung for a level search: `low` (SearchLevels on the system's
// H = 1 sibling, its finest bounds maybe improved since) refined at the system's H level by level.
// Without levels in `low`: RefineBoundsAtHarmonics.
BoundsResult RefineLevelsAtHarmonics(const HarmonicBalance& system, const BoundsResult& low,
                                     const BoundsOptions& options,
                                     const LevelSearchOptions& search);

// A bound run: SearchLevels, on the harmonic ladder at H = 1 then refined at H. Throws
// std::invalid_argument on invalid options or a non-positive frequency.
BoundsResult ComputeLevelBounds(const HarmonicBalance& system, double freq_hz,
                                const BoundsOptions& options, const LevelSearchOptions& search);

}  // namespace fricrom
