// The bound search over α levels (bound_search.h): corners and runs on the coarsest level, each
// finer level from the optima of the one below, the harmonic ladder level by level.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "bound_runs.h"
#include "fricrom/bound_search.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"
#include "optimise_bounds.h"

namespace fricrom {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A level's view of `system`: the system itself for the identity level, else a borrowing
// AlphaLevelBalance held in *hold.
const HarmonicBalance& LevelView(const HarmonicBalance& system, const AlphaLevel& level,
                                 std::unique_ptr<AlphaLevelBalance>* hold) {
  if (level.IsIdentity()) return system;
  *hold = std::make_unique<AlphaLevelBalance>(system, level);
  return **hold;
}

// A coarser level's solution as a point of `level`: the same x, its fine α lifted to `level`'s
// parameters (exact: a coarse α is a fine α). Not usable where the lift or the residual fails.
BoundSolution AsCandidate(const HarmonicBalance& view, double omega, const BoundSolution& coarse,
                          const AlphaLevel& coarse_level, const AlphaLevel& level) {
  BoundSolution s;
  s.status = BoundStatus::kFailed;
  if (!coarse.IsUsable() || coarse.x.size() != view.num_unknowns()) return s;
  if (!level.Lift(coarse_level.FineAlpha(coarse.alpha), &s.alpha)) return s;
  s.x = coarse.x;
  s.status = BoundStatus::kConverged;
  s.stationary = false;
  s.seed = coarse.seed;
  s.iterations = coarse.iterations;
  s.message = "the " + coarse_level.name + " level's optimum (a coarse alpha is a fine alpha)";
  bounds_detail::Describe(view, omega, &s);
  if (!(s.residual <= bounds_detail::kFeasibility)) s.status = BoundStatus::kFailed;
  return s;
}

// Folds a candidate into the bounds where it lies beyond them; returns how many moved (0-2).
int Fold(const BoundSolution& cand, BoundsOptions::Objective objective, BoundsResult* r) {
  if (!cand.IsUsable()) return 0;
  int moved = 0;
  for (bool is_max : {false, true}) {
    BoundSolution& b = is_max ? r->max : r->min;
    if (!b.IsUsable() || bounds_detail::LiesBeyond(cand, b, objective, is_max, 1e-12)) {
      b = cand;
      ++moved;
    }
  }
  return moved;
}

struct Starts {
  std::vector<Eigen::VectorXd> alpha, x;
  std::vector<int> directions;  // 1 minimum, 2 maximum, 3 both
  void Add(const Eigen::VectorXd& a, const Eigen::VectorXd& xs, int dirs) {
    // The same α on another branch (another x) is another start.
    for (size_t i = 0; i < alpha.size(); ++i) {
      if (alpha[i] == a && x[i].size() == xs.size() && x[i] == xs) {
        directions[i] |= dirs;
        return;
      }
    }
    alpha.push_back(a);
    x.push_back(xs);
    directions.push_back(dirs);
  }
};

// The corners' routes, measured on the coarse cascade at 1098, 1100 and 1102 Hz (one thread):
// the cold corners by the α homotopy alone, at most kColdCornerPoints points (with the frequency
// continuations of a cold start too, 2000 points each, they took 197 s at 1102 Hz; without them
// 36 s, the same bounds at all three frequencies); the walk's failed Newton steps by a residual
// homotopy of at most kCornerHomotopyPoints points (40: 56 failures cost 77 s of 101 s at
// 1100 Hz; 15: the same bounds; none: y_min 1.7e-4 m instead of 3.9e-5 m at 1100 Hz). Bound
// runs at 1100/1102 Hz: 128 s/381 s before, 98 s/224 s after.
constexpr int kColdCornerPoints = 300;
constexpr int kCornerHomotopyPoints = 15;

// The coarsest level's corner starts: corners over the k most influential parameters (the rest
// 0), solved in Gray-code order each from the last, ranked by the response.
void CornerStarts(const HarmonicBalance& view, double freq_hz, const LevelSearchOptions& ls,
                  const BoundsOptions& options, Starts* starts, LevelBound* record) {
  const int n = view.num_alpha();
  int k = 0;
  while (k < n && (2 << k) <= ls.max_corners) ++k;
  if (k == 0) return;
  const double omega = RadPerS(freq_hz);
  // The influence solves and the walk: Newton from a nearby corner's solution, then the residual
  // homotopy from it; not the routes of a cold start.
  FrfOptions quick;
  quick.use_fallbacks = false;
  FrfOptions homotopy;
  homotopy.fallback_max_points = kCornerHomotopyPoints;
  auto solve = [&](const Eigen::VectorXd& c, const Eigen::VectorXd& from, FrfPoint* p) {
    *p = SolveAtFrequency(view, c, freq_hz, from, from.size() > 0 ? quick : FrfOptions{});
    if (p->status != SolverStatus::kConverged && from.size() > 0) {
      int evaluations = 0;
      Eigen::VectorXd x;
      if (SolveFromNearbyPoint(view, c, omega, from, homotopy, &x, &evaluations)) {
        p->x = x;
        p->amplitude = view.Amplitude(x);
        p->status = SolverStatus::kConverged;
      }
    }
    const bool ok = p->status == SolverStatus::kConverged;
    ++(ok ? record->corners_solved : record->corners_failed);
    return ok;
  };
  FrfPoint zero;
  if (!solve(Eigen::VectorXd::Zero(n), Eigen::VectorXd(), &zero)) return;
  // Influence of parameter i: |y(+e_i) − y(−e_i)| (a failed solve counts as none).
  std::vector<double> spread(n, 0.0);
  for (int i = 0; i < n; ++i) {
    FrfPoint lo, hi;
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
    c[i] = 1.0;
    const bool a = solve(c, zero.x, &hi);
    c[i] = -1.0;
    const bool b = solve(c, zero.x, &lo);
    if (a && b) spread[i] = std::abs(hi.amplitude - lo.amplitude);
  }
  std::vector<int> chosen(n);
  std::iota(chosen.begin(), chosen.end(), 0);
  std::stable_sort(chosen.begin(), chosen.end(),
                   [&](int a, int b) { return spread[a] > spread[b]; });
  struct Corner {
    Eigen::VectorXd c, x;
    double rank;
  };
  std::vector<Corner> corners;
  const auto add = [&](const Eigen::VectorXd& c, const FrfPoint& p) {
    const double rank = options.objective == BoundsOptions::kAmplitude
                            ? p.amplitude
                            : -view.Energies(p.x, omega, c).loss_factor();
    corners.push_back({c, p.x, rank});
  };
  // The corners over the (up to) 4 most influential parameters, the rest 0, each solved cold
  // (Newton from the stick solution, then the α homotopy from α = 0): next to the resonance they
  // reach the branches the minimum lies on (1100 Hz: without them y_min is 2.9e-4 m, not
  // 3.9e-5 m).
  const int k_cold = std::min(k, 4);
  FrfOptions cold;
  cold.fallback_max_points = kColdCornerPoints;
  cold.frequency_fallbacks = 0;
  for (int m = 0; m < (1 << k_cold); ++m) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
    for (int j = 0; j < k_cold; ++j) c[chosen[j]] = (m >> j) & 1 ? 1.0 : -1.0;
    const FrfPoint p = SolveAtFrequency(view, c, freq_hz, Eigen::VectorXd(), cold);
    ++(p.status == SolverStatus::kConverged ? record->corners_solved : record->corners_failed);
    if (p.status == SolverStatus::kConverged) add(c, p);
  }
  // Every corner (up to max_corners), cheaply: Newton and the residual homotopy from the last
  // (its Gray-code neighbour). Without the homotopy, at 1100 Hz the minimum's branch
  // (y_min 3.9e-5 m against 1.7e-4 m) was not reached. A corner neither reaches is skipped, and
  // counted.
  Eigen::VectorXd last = zero.x;
  for (int m = 0; m < (1 << k); ++m) {
    const int gray = m ^ (m >> 1);
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
    for (int j = 0; j < k; ++j) c[chosen[j]] = (gray >> j) & 1 ? 1.0 : -1.0;
    FrfPoint p;
    if (!solve(c, last, &p)) continue;
    last = p.x;
    add(c, p);
  }
  std::sort(corners.begin(), corners.end(),
            [](const Corner& a, const Corner& b) { return a.rank < b.rank; });
  const int take = std::min<int>(ls.corner_starts, static_cast<int>(corners.size()));
  for (int i = 0; i < take; ++i) {
    starts->Add(corners[i].c, corners[i].x, 1);
    starts->Add(corners[corners.size() - 1 - i].c, corners[corners.size() - 1 - i].x, 2);
  }
}

// One level's search at the view's H: its starts, the runs and the sample check, then the
// coarser level's optima as candidates.
BoundsResult SearchOneLevel(const HarmonicBalance& view, double freq_hz,
                            const BoundsOptions& options, const LevelSearchOptions& ls, int l,
                            const BoundsResult* coarser, LevelBound* record) {
  const int n = view.num_alpha();
  const bool finest = l + 1 == static_cast<int>(ls.levels.size());
  BoundsOptions lo = options;
  lo.search_harmonics = 0;
  lo.seed_groups.clear();
  lo.alpha_seeds.clear();
  lo.random_seeds = 0;
  const std::string prefix = ls.levels[l].name + " level: ";
  if (options.progress) {
    lo.progress = [&options, prefix](const std::string& stage, int done, int total) {
      options.progress(prefix + stage, done, total);
    };
  }
  Starts starts;
  if (coarser == nullptr) {
    for (const Eigen::VectorXd& a : DefaultAlphaSeeds(n)) starts.Add(a, Eigen::VectorXd(), 3);
    const auto tc = Clock::now();
    CornerStarts(view, freq_hz, ls, options, &starts, record);
    record->corners_s = Since(tc);
  } else {
    const AlphaLevel& from = ls.levels[l - 1];
    Eigen::VectorXd c;
    for (bool is_max : {false, true}) {
      const BoundSolution& b = is_max ? coarser->max : coarser->min;
      if (b.IsUsable() && ls.levels[l].Lift(from.FineAlpha(b.alpha), &c)) {
        starts.Add(c, b.x, is_max ? 2 : 1);
      }
    }
  }
  if (starts.alpha.empty()) starts.Add(Eigen::VectorXd::Zero(n), Eigen::VectorXd(), 3);
  BoundsResult r = SearchFromSeeds(view, freq_hz, lo, starts.alpha, starts.x, starts.directions);
  r.seed_counts.base = static_cast<int>(starts.alpha.size());
  if (finest && coarser != nullptr) {
    // The single-level search itself (its seeds: --seeds, else the default set; random seeds),
    // on its own, merged: its runs are not stopped by the coarser optima's bounds, so the levels
    // never lose what it finds (1102 Hz: y_min 1.3e-6 m where the levels' runs stopped at
    // 1.9e-5; 1106 Hz: 3.8e-6 against 4.3e-6 with its seeds after the coarser optima).
    BoundsOptions single = lo;
    single.alpha_seeds = options.alpha_seeds;
    single.random_seeds = options.random_seeds;
    const BoundsResult own = SearchFromSeeds(view, freq_hz, single, AlphaSeeds(n, single));
    record->single_min = own.min;
    record->single_max = own.max;
    MergeBounds(own, options.objective, &r);
  }
  if (coarser != nullptr) {
    const double omega = RadPerS(freq_hz);
    for (const BoundSolution* b : {&coarser->min, &coarser->max}) {
      record->raised_by_coarser +=
          Fold(AsCandidate(view, omega, *b, ls.levels[l - 1], ls.levels[l]), options.objective, &r);
    }
  }
  return r;
}

void Record(const BoundsResult& r, LevelBound* record) {
  record->min = r.min;
  record->max = r.max;
  record->optimizer_runs += r.optimizer_runs;
  record->samples_checked += r.samples_checked;
  record->improved_by_samples += r.improved_by_samples;
}

// The user's own starts solved at H and kept as candidates: a bound is never worse than its
// starts.
void FoldSeedsAtH(const HarmonicBalance& view, double freq_hz, const BoundsOptions& options,
                  BoundsResult* r) {
  const double omega = RadPerS(freq_hz);
  for (const Eigen::VectorXd& a : options.alpha_seeds) {
    const FrfPoint p = SolveAtFrequency(view, a, freq_hz, Eigen::VectorXd(), FrfOptions{});
    if (p.status != SolverStatus::kConverged) continue;
    BoundSolution s;
    s.x = p.x;
    s.alpha = a;
    s.status = BoundStatus::kConverged;
    s.message = "a given alpha seed solved at H";
    bounds_detail::Describe(view, omega, &s);
    if (s.residual <= bounds_detail::kFeasibility) Fold(s, options.objective, r);
  }
}

// A finer level's H = 1 optimum is refined at H only where it lies beyond the coarser level's by
// more than this (relative): H itself moves the bounds by ~1 % next to the resonance (the
// ladder's premise, docs/lumped-vs-fe.md), and at 1102 Hz moves of 4e-5 made two extra
// refinements of a minute each. Below it the coarser level's optimum at H stands (held).
constexpr double kRefineMargin = 1e-3;

// One level's rung of the harmonic ladder: its H = 1 optima (`from`) refined at H, in the
// directions where they lie beyond the coarser level's H = 1 bounds (`coarser`; null: both).
// Where a level's H = 1 optimum is the coarser level's, the coarser level's optimum at H (folded
// in by the caller) stands for it, and the refinement is not made twice.
void RefineLevel(const HarmonicBalance& view, const BoundsResult& from, const LevelBound* coarser,
                 const BoundsOptions& options, BoundsResult* r) {
  std::vector<KnownSolution> known;
  for (bool is_max : {false, true}) {
    const BoundSolution& b = is_max ? from.max : from.min;
    if (!b.IsUsable()) continue;
    const BoundSolution* c = coarser ? (is_max ? &coarser->max : &coarser->min) : nullptr;
    if (c && c->IsUsable() &&
        !bounds_detail::LiesBeyond(b, *c, options.objective, is_max, kRefineMargin)) {
      continue;
    }
    known.push_back({view.EmbedLowerHarmonics(b.x, 1), b.alpha, !is_max, is_max, true, true});
  }
  if (known.empty()) return;
  // The rung's settings (RefineBoundsAtHarmonics): monotone runs from a nearby optimum, the
  // looser stationarity, minima stopped at a negligible response.
  BoundsOptions at_h = options;
  at_h.progress = nullptr;
  at_h.search_harmonics = 0;
  at_h.line_search_memory = 1;
  at_h.stationary_change = options.refinement_stationary_change;
  if (options.negligible_minimum > 0.0 && from.max.IsUsable()) {
    at_h.minimum_stop_m = options.negligible_minimum * from.max.amplitude;
  }
  ImproveBounds(view, from.freq_hz, at_h, known, r);
}

}  // namespace

double LevelBound::robustness() const {
  if (!min.IsUsable() || !max.IsUsable() || !(max.amplitude > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return min.amplitude / max.amplitude;
}

bool LevelSearchOptions::IsValid(std::string* error) const {
  if (max_corners < 0 || max_corners > (1 << 16)) {
    *error =
        "LevelSearchOptions.max_corners must lie in [0, 65536], got " + std::to_string(max_corners);
    return false;
  }
  if (corner_starts < 0) {
    *error = "LevelSearchOptions.corner_starts must be >= 0, got " + std::to_string(corner_starts);
    return false;
  }
  for (size_t l = 1; l < levels.size(); ++l) {
    if (levels[l].map.rows() != levels[0].map.rows()) {
      *error =
          "LevelSearchOptions.levels[" + std::to_string(l) + "] maps to another number of alpha";
      return false;
    }
  }
  if (!levels.empty() && !levels.back().IsIdentity()) {
    *error = "LevelSearchOptions.levels: the finest level must be one parameter per alpha";
    return false;
  }
  return true;
}

BoundsResult SearchLevels(const HarmonicBalance& system, double freq_hz,
                          const BoundsOptions& options, const LevelSearchOptions& ls) {
  BoundsOptions at_h = options;
  at_h.search_harmonics = 0;
  if (ls.levels.size() <= 1) return ComputeBounds(system, freq_hz, at_h);
  std::string error;
  if (!options.IsValid(&error) || !ls.IsValid(&error)) throw std::invalid_argument(error);
  if (ls.levels.back().map.rows() != system.num_alpha()) {
    throw std::invalid_argument("SearchLevels: the levels map to " +
                                std::to_string(ls.levels.back().map.rows()) +
                                " alpha, the system has " + std::to_string(system.num_alpha()));
  }
  const auto t0 = Clock::now();
  BoundsResult coarser, result;
  for (size_t l = 0; l < ls.levels.size(); ++l) {
    const auto tl = Clock::now();
    std::unique_ptr<AlphaLevelBalance> hold;
    const HarmonicBalance& view = LevelView(system, ls.levels[l], &hold);
    LevelBound record;
    record.level = ls.levels[l].name;
    record.parameters = ls.levels[l].num_parameters();
    BoundsResult r = SearchOneLevel(view, freq_hz, options, ls, static_cast<int>(l),
                                    l == 0 ? nullptr : &coarser, &record);
    Record(r, &record);
    record.wall_s = Since(tl);
    bounds_detail::AddSearchCounts(r, true, &result);
    result.levels.push_back(record);
    coarser = std::move(r);
  }
  const std::vector<LevelBound> levels = std::move(result.levels);
  BoundsResult counts = result;
  result = std::move(coarser);
  result.levels = levels;
  result.seeds_tried = counts.seeds_tried;
  result.seeds_converged = counts.seeds_converged;
  result.start_failures = counts.start_failures;
  result.min_failures = counts.min_failures;
  result.max_failures = counts.max_failures;
  result.optimizer_runs = counts.optimizer_runs;
  result.runs_abandoned = counts.runs_abandoned;
  result.samples_checked = counts.samples_checked;
  result.samples_failed = counts.samples_failed;
  result.improved_by_samples = counts.improved_by_samples;
  result.search_harmonics = system.harmonics();
  result.harmonics = system.harmonics();
  result.wall_s = Since(t0);
  return result;
}

BoundsResult RefineLevelsAtHarmonics(const HarmonicBalance& system, const BoundsResult& low,
                                     const BoundsOptions& options, const LevelSearchOptions& ls) {
  if (low.levels.empty() || ls.levels.size() != low.levels.size()) {
    return RefineBoundsAtHarmonics(system, low, options);
  }
  const auto t0 = Clock::now();
  const double omega = RadPerS(low.freq_hz);
  const int nl = static_cast<int>(ls.levels.size());
  BoundsResult coarser, counts;
  std::vector<LevelBound> records;
  for (int l = 0; l < nl; ++l) {
    const auto tl = Clock::now();
    std::unique_ptr<AlphaLevelBalance> hold;
    const HarmonicBalance& view = LevelView(system, ls.levels[l], &hold);
    BoundsResult from;
    from.freq_hz = low.freq_hz;
    from.min = l + 1 == nl ? low.min : low.levels[l].min;
    from.max = l + 1 == nl ? low.max : low.levels[l].max;
    LevelBound record = low.levels[l];
    // The coarser level's optima at H first: they are this level's points, and runs that
    // cannot reach them stop early (BoundsOptions::stop_dominated_runs).
    BoundsResult r;
    r.freq_hz = low.freq_hz;
    r.min.message = r.max.message = "refinement at H: no run converged";
    if (l > 0) {
      for (const BoundSolution* b : {&coarser.min, &coarser.max}) {
        Fold(AsCandidate(view, omega, *b, ls.levels[l - 1], ls.levels[l]), options.objective, &r);
      }
    }
    RefineLevel(view, from, l == 0 ? nullptr : &low.levels[l - 1], options, &r);
    if (l + 1 == nl) {
      // The single-level search's optima too, where they are not the level's own.
      BoundsResult single;
      single.freq_hz = low.freq_hz;
      single.min = low.levels[l].single_min;
      single.max = low.levels[l].single_max;
      for (bool is_max : {false, true}) {
        BoundSolution& s = is_max ? single.max : single.min;
        const BoundSolution& own = is_max ? from.max : from.min;
        if (s.IsUsable() && own.IsUsable() && s.alpha == own.alpha) s.status = BoundStatus::kFailed;
      }
      RefineLevel(view, single, nullptr, options, &r);
    }
    if (!r.min.IsUsable() || !r.max.IsUsable()) {
      // Lost at H with nothing held: the whole rung (with its own fallback, the search at H).
      MergeBounds(RefineBoundsAtHarmonics(view, from, options), options.objective, &r);
    }
    // Each level's own sample check at H: a coarse level's few parameters are where samples
    // find what the H = 1 optima miss (disk24 at its peak: a uniform α per interface).
    CheckRefinedBounds(view, low.freq_hz, options, &r);
    if (l + 1 == nl) FoldSeedsAtH(view, low.freq_hz, options, &r);
    record.min = r.min;
    record.max = r.max;
    record.optimizer_runs += r.optimizer_runs;
    record.samples_checked += r.samples_checked;
    record.improved_by_samples += r.improved_by_samples;
    record.refine_s = Since(tl);
    record.wall_s += record.refine_s;
    bounds_detail::AddSearchCounts(r, true, &counts);
    records.push_back(record);
    if (options.progress) options.progress("harmonic refinement", l + 1, nl);
    coarser = std::move(r);
  }
  BoundsResult result = low;
  result.min = coarser.min;
  result.max = coarser.max;
  result.levels = records;
  result.optimizer_runs += counts.optimizer_runs;
  result.runs_abandoned += counts.runs_abandoned;
  result.min_failures += counts.min_failures;
  result.max_failures += counts.max_failures;
  result.refinement_fallbacks = counts.refinement_fallbacks;
  result.samples_checked += counts.samples_checked;
  result.samples_failed += counts.samples_failed;
  result.improved_by_samples += counts.improved_by_samples;
  for (BoundSolution* b : {&result.min, &result.max}) {
    if (b->IsUsable()) continue;  // a failed bound is never a number
    b->amplitude = b->loss_factor = std::numeric_limits<double>::quiet_NaN();
  }
  result.search_harmonics = 1;
  result.harmonics = system.harmonics();
  result.wall_s = low.wall_s + Since(t0);
  return result;
}

BoundsResult ComputeLevelBounds(const HarmonicBalance& system, double freq_hz,
                                const BoundsOptions& options, const LevelSearchOptions& ls) {
  if (ls.levels.size() <= 1) return ComputeBounds(system, freq_hz, options);
  std::string error;
  if (!options.IsValid(&error) || !ls.IsValid(&error)) throw std::invalid_argument(error);
  if (!(freq_hz > 0.0) || !std::isfinite(freq_hz)) {
    throw std::invalid_argument("ComputeLevelBounds: freq_hz must be positive and finite, got " +
                                std::to_string(freq_hz));
  }
  const auto t0 = Clock::now();
  BoundsResult result;
  if (UsesHarmonicLadder(system, options)) {
    result = RefineLevelsAtHarmonics(
        system, SearchLevels(SearchBalance(system, options), freq_hz, options, ls), options, ls);
  } else {
    result = SearchLevels(system, freq_hz, options, ls);
  }
  result.wall_s = Since(t0);
  return result;
}

}  // namespace fricrom
