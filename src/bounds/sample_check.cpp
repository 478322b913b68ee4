// ComputeBounds: the optimisation from the seeds, then a check of the bounds against
// fixed-α solves at random α. The response over α is nonsmooth and every optimiser run finds a
// local optimum only; a sample beyond a bound shows it, and the optimiser restarts from it.
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "bound_runs.h"
#include "fricrom/bounds.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"
#include "optimise_bounds.h"

namespace fricrom {
namespace {

// The α homotopy's points a sample of the check at H may take (CheckBoundsBySamples, refined).
constexpr int kRefinedSampleHomotopyPoints = 100;

// A sample beats a bound only by more than this relative margin (solver tolerances are ~1e-10).
constexpr double kBeatMargin = 1e-7;

// The objective a bound ranks by: larger = more response (the maximum response minimises η).
double Rank(const HarmonicBalance& system, const BoundsOptions& options, const Eigen::VectorXd& x,
            double omega, const Eigen::VectorXd& alpha) {
  if (options.objective == BoundsOptions::kAmplitude) return system.Amplitude(x);
  return -system.Energies(x, omega, alpha).loss_factor();
}

// The sample itself as a bound candidate: a converged harmonic-balance solution at its α.
BoundSolution FromSample(const HarmonicBalance& system, double omega, const FrfPoint& p,
                         const Eigen::VectorXd& alpha) {
  BoundSolution s;
  s.x = p.x;
  s.alpha = alpha;
  s.amplitude = p.amplitude;
  s.loss_factor = system.Energies(p.x, omega, alpha).loss_factor();
  s.residual = 0.0;  // converged by Newton to the harmonic-balance tolerance
  s.status = BoundStatus::kConverged;
  s.message = "alpha sample (fixed-alpha solve) beyond the optimised bound";
  s.iterations = p.iterations;
  s.regimes = p.regimes;
  return s;
}

// Newton steps the cold start gets before `warm` is tried: where it works (stuck contacts) it
// converges in 2-3 (FE cascade, 1000 Hz); on the lumped case near resonance it fails.
constexpr int kColdStartIterations = 6;

// A fixed-α solve from the better of two starts by their residual: the cold start (full stick,
// and the H = 1 solution at H > 1, as SolveAtFrequency does without a start) or `warm` (the
// minimum bound's solution). The cold start is tried briefly and without SolveAtFrequency's
// costly fallback paths, which run only from `warm`, after plain Newton from both starts failed. On
// the FE cascade random α mostly stick where the minimum lifts off: Newton from the minimum took
// 10-15 steps, the cold start 2-3; on the lumped case near resonance the minimum is the better
// start.
FrfPoint SolveSample(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double freq_hz,
                     const Eigen::VectorXd& stick, const Eigen::VectorXd& warm,
                     const FrfOptions& fallbacks) {
  FrfOptions options = fallbacks;
  if (warm.size() == 0) return SolveAtFrequency(system, alpha, freq_hz, Eigen::VectorXd(), options);
  const HbmAtFrequency at(system, RadPerS(freq_hz), alpha);
  Eigen::VectorXd r_cold, r_warm;
  at.Evaluate(stick, &r_cold, nullptr);
  at.Evaluate(warm, &r_warm, nullptr);
  int cold_iterations = 0;
  if (r_cold.norm() < r_warm.norm()) {
    options.use_fallbacks = false;
    options.newton.max_iterations = kColdStartIterations;
    const FrfPoint p = SolveAtFrequency(system, alpha, freq_hz, Eigen::VectorXd(), options);
    if (p.status == SolverStatus::kConverged) return p;
    cold_iterations = p.iterations;
    options = fallbacks;
  }
  FrfPoint p = SolveAtFrequency(system, alpha, freq_hz, warm, options);
  p.iterations += cold_iterations;
  return p;
}

struct SampleCandidates {
  bool have_low = false, have_high = false;
  FrfPoint low, high;
  Eigen::VectorXd alpha_low, alpha_high;
};

// Solves at check_samples random α; keeps the sample furthest below y_min and above y_max.
SampleCandidates SampleAlpha(const HarmonicBalance& system, double freq_hz,
                             const BoundsOptions& options, const FrfOptions& fallbacks,
                             BoundsResult* result) {
  const int nc = system.num_alpha();
  const double omega = RadPerS(freq_hz);
  std::mt19937 rng(options.sample_seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::VectorXd warm = result->min.IsUsable() ? result->min.x : Eigen::VectorXd();
  const Eigen::VectorXd stick = system.StickLinearSolution(omega);
  SampleCandidates c;
  double best_lo =
      result->min.IsUsable() ? bounds_detail::RankValue(result->min, options.objective) : 0.0;
  double best_hi =
      result->max.IsUsable() ? bounds_detail::RankValue(result->max, options.objective) : 0.0;
  for (int i = 0; i < options.check_samples; ++i) {
    Eigen::VectorXd a(nc);
    for (int k = 0; k < nc; ++k) a[k] = u(rng);
    const FrfPoint p = SolveSample(system, a, freq_hz, stick, warm, fallbacks);
    ++result->samples_checked;
    if (options.progress) options.progress("samples", i + 1, options.check_samples);
    if (p.status != SolverStatus::kConverged) {
      ++result->samples_failed;
      continue;
    }
    const double v = Rank(system, options, p.x, omega, a);
    // Only a converged bound is checked: a sample is no substitute for a failed optimisation.
    if (result->min.IsUsable() && v < best_lo - kBeatMargin * std::abs(best_lo)) {
      best_lo = v;
      c.have_low = true;
      c.low = p;
      c.alpha_low = a;
    }
    if (result->max.IsUsable() && v > best_hi + kBeatMargin * std::abs(best_hi)) {
      best_hi = v;
      c.have_high = true;
      c.high = p;
      c.alpha_high = a;
    }
  }
  return c;
}

}  // namespace

BoundsResult SearchFromSeeds(const HarmonicBalance& system, double freq_hz,
                             const BoundsOptions& options,
                             const std::vector<Eigen::VectorXd>& seeds,
                             const std::vector<Eigen::VectorXd>& known_x,
                             const std::vector<int>& directions) {
  BoundsResult result = OptimiseBounds(system, freq_hz, options, seeds, known_x, directions);
  CheckBoundsBySamples(system, freq_hz, options, static_cast<int>(seeds.size()), false, &result);
  return result;
}

void CheckBoundsBySamples(const HarmonicBalance& system, double freq_hz,
                          const BoundsOptions& options, int seeds_before, bool refined,
                          BoundsResult* out) {
  if (system.num_alpha() == 0 || options.check_samples == 0) return;
  BoundsResult& result = *out;
  // At H after the refinement a sample gets Newton and the α homotopy, not the continuations in
  // frequency: on a cyclic sector above its stick frequency those took minutes per sample
  // (every step refactorises the dense receptance), and a sample that fails is only counted.
  FrfOptions fallbacks;
  if (refined) {
    fallbacks.frequency_fallbacks = 0;
    fallbacks.fallback_max_points = kRefinedSampleHomotopyPoints;
  }
  const SampleCandidates c = SampleAlpha(system, freq_hz, options, fallbacks, &result);
  if (!c.have_low && !c.have_high) return;
  const double omega = RadPerS(freq_hz);
  std::vector<Eigen::VectorXd> restart;
  if (c.have_low) restart.push_back(c.alpha_low);
  if (c.have_high) restart.push_back(c.alpha_high);
  std::vector<Eigen::VectorXd> restart_x;
  if (refined) {
    if (c.have_low) restart_x.push_back(c.low.x);
    if (c.have_high) restart_x.push_back(c.high.x);
  }
  const BoundsResult again = OptimiseBounds(system, freq_hz, options, restart, restart_x);
  bounds_detail::AddSearchCounts(again, false, &result);
  // Each bound: the best of the first optimisation, the restart and the sample itself.
  auto improve = [&](bool is_max, bool have_sample, const FrfPoint& sample,
                     const Eigen::VectorXd& alpha, BoundSolution restarted) {
    if (!have_sample) return;
    BoundSolution& bound = is_max ? result.max : result.min;
    BoundSolution best = FromSample(system, omega, sample, alpha);
    // A restart stopped at its iteration limit still ended on a feasible point.
    if (!restarted.IsUsable())
      bounds_detail::UsableUnfinished(system, omega, restarted, &restarted);
    const double sign = is_max ? 1.0 : -1.0;
    if (restarted.IsUsable() && sign * bounds_detail::RankValue(restarted, options.objective) >=
                                    sign * bounds_detail::RankValue(best, options.objective)) {
      best = restarted;
      best.seed = seeds_before + restarted.seed;  // restart seeds come last
      best.message += " (optimiser restarted from an alpha sample beyond the first bound)";
    }
    bound = std::move(best);
    ++result.improved_by_samples;
  };
  improve(false, c.have_low, c.low, c.alpha_low, again.min);
  improve(true, c.have_high, c.high, c.alpha_high, again.max);
}

void CheckRefinedBounds(const HarmonicBalance& system, double freq_hz, const BoundsOptions& options,
                        BoundsResult* result) {
  if (!result->min.IsUsable() || !result->max.IsUsable()) return;
  // The refinement's settings (RefineBoundsAtHarmonics) for the restarts, and other α than the
  // check at H = 1 solved (its samples lay inside the bounds there).
  BoundsOptions at_h = options;
  at_h.search_harmonics = 0;
  at_h.line_search_memory = 1;
  at_h.stationary_change = options.refinement_stationary_change;
  at_h.sample_seed = options.sample_seed + 2;
  if (options.negligible_minimum > 0.0) {
    at_h.minimum_stop_m = options.negligible_minimum * result->max.amplitude;
  }
  at_h.progress = nullptr;
  if (options.progress) {
    at_h.progress = [&options](const std::string& stage, int done, int total) {
      options.progress(stage + " at H", done, total);
    };
  }
  CheckBoundsBySamples(system, freq_hz, at_h, 0, true, result);
}

namespace {

BoundsResult ComputeBoundsUntimed(const HarmonicBalance& system, double freq_hz,
                                  const BoundsOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  if (!(freq_hz > 0.0) || !std::isfinite(freq_hz)) {
    throw std::invalid_argument("ComputeBounds: freq_hz must be positive and finite, got " +
                                std::to_string(freq_hz));
  }
  SeedCounts counts;
  const std::vector<Eigen::VectorXd> seeds = AlphaSeeds(system.num_alpha(), options, &counts);
  BoundsResult result = SearchFromSeeds(system, freq_hz, options, seeds);
  result.seed_counts = counts;
  return result;
}

}  // namespace

BoundsResult ComputeBounds(const HarmonicBalance& system, double freq_hz,
                           const BoundsOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  BoundsResult result;
  if (UsesHarmonicLadder(system, options)) {
    std::string error;
    if (!options.IsValid(&error)) throw std::invalid_argument(error);
    BoundsOptions search = options;
    search.search_harmonics = 0;
    result = RefineBoundsAtHarmonics(
        system, ComputeBoundsUntimed(SearchBalance(system, options), freq_hz, search), options);
  } else {
    result = ComputeBoundsUntimed(system, freq_hz, options);
    result.search_harmonics = system.harmonics();
  }
  result.harmonics = system.harmonics();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

bool UsesHarmonicLadder(const HarmonicBalance& system, const BoundsOptions& options) {
  return options.search_harmonics == 1 && system.harmonics() > 1;
}

const HarmonicBalance& SearchBalance(const HarmonicBalance& system, const BoundsOptions& options) {
  if (!UsesHarmonicLadder(system, options)) return system;
  const HarmonicBalance* first = system.FirstHarmonicBalance();
  if (first == nullptr) {
    throw std::invalid_argument(
        "bounds: search_harmonics = 1 needs a balance that can drop its higher harmonics (this "
        "one cannot: loads above the first harmonic); use search_harmonics = 0");
  }
  return *first;
}

// Each H = 1 optimum is refined in its own direction only (one run per bound at H, where runs
// cost 3-5x those at H = 1); an optimum that is both bounds' (a unique response) in both.
BoundsResult RefineBoundsAtHarmonics(const HarmonicBalance& system, const BoundsResult& low,
                                     const BoundsOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<KnownSolution> known;
  if (low.min.IsUsable()) {
    known.push_back({system.EmbedLowerHarmonics(low.min.x, 1), low.min.alpha, true, false});
  }
  if (low.max.IsUsable()) {
    if (!known.empty() && known.front().alpha == low.max.alpha) {
      known.front().run_max = true;
    } else {
      known.push_back({system.EmbedLowerHarmonics(low.max.x, 1), low.max.alpha, false, true});
    }
  }
  // An optimum Newton and the residual homotopy cannot carry to H starts its run short of its α
  // on the α homotopy, not from the continuations in frequency (minutes next to a resonance);
  // a bound still lost falls back on the full search at H below.
  for (KnownSolution& k : known) k.start_short_of_alpha = true;
  BoundsResult result;
  result.freq_hz = low.freq_hz;
  result.min.message = result.max.message = "refinement at H: no run converged";
  BoundsOptions at_h = options;
  at_h.progress = nullptr;
  at_h.search_harmonics = 0;
  // From an optimum next to the one at H a monotone search suffices (nonmonotone here doubled
  // the refinement's time on the 50-point FE curve and found nothing the search at H = 1 had
  // not; BoundsOptions::line_search_memory).
  at_h.line_search_memory = 1;
  at_h.stationary_change = options.refinement_stationary_change;
  if (options.negligible_minimum > 0.0 && low.max.IsUsable()) {
    at_h.minimum_stop_m = options.negligible_minimum * low.max.amplitude;
  }
  // Near a resonance the refinement is most of a bound's time: its stage shows (0 of 1, then 1).
  if (options.progress) options.progress("harmonic refinement", 0, 1);
  ImproveBounds(system, low.freq_hz, at_h, known, &result);
  // The search's own counts (at H = 1) and the refinement's runs.
  bounds_detail::AddSearchCounts(low, false, &result);
  result.seed_counts = low.seed_counts;
  result.samples_checked = low.samples_checked;
  result.samples_failed = low.samples_failed;
  result.improved_by_samples = low.improved_by_samples;
  CheckRefinedBounds(system, low.freq_hz, options, &result);
  if (!result.min.IsUsable() || !result.max.IsUsable()) {
    // Newton or the runs at H failed from the H = 1 optimum: the full search at H, merged, so
    // that no bound is lost to the ladder.
    result.refinement_fallbacks = (result.min.IsUsable() ? 0 : 1) + (result.max.IsUsable() ? 0 : 1);
    MergeBounds(ComputeBoundsUntimed(system, low.freq_hz, at_h), options.objective, &result);
  }
  for (BoundSolution* b : {&result.min, &result.max}) {
    if (b->IsUsable()) continue;  // a failed bound is never a number
    b->amplitude = b->loss_factor = std::numeric_limits<double>::quiet_NaN();
  }
  result.search_harmonics = 1;
  result.harmonics = system.harmonics();
  if (options.progress) options.progress("harmonic refinement", 1, 1);
  result.wall_s =
      low.wall_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace fricrom
