// Response bounds at one frequency (paper §2.3, Table 1): the minimum and the maximum forced
// response over all admissible initial tangential force coefficients α ∈ [−1, 1]^Ncont,
//   min / max  objective(x̂, α)   over [x̂, α]   subject to  R(x̂; ω, α) = 0,
// solved as a smooth NLP by an interior-point method from several α seeds. Each seed starts from
// a converged harmonic-balance solution at that α, so every start is feasible.
//
// The residual is only piecewise smooth in (x̂, α) (stick/slip switches, saturation of the first
// period), and the response is flat in α wherever a contact slips or the first-period force
// saturates: each run finds a local optimum, and the bounds are the best converged local optima
// over the seeds. Seeds at the corners of the α box help; more seeds cost more time.
//
// A run whose start already satisfies the first-order conditions (zero reduced gradient in α, as
// on the plateaus of the response) is accepted without calling the optimiser. At a kink, where no
// KKT point exists, a run whose objective stays constant over 10 feasible iterations is accepted
// as converged (its message says so); one that crawls without progress is stopped as failed.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fricrom/contact_law.h"
#include "fricrom/harmonic_balance.h"

namespace fricrom {

struct BoundsOptions {
  // Fixed underlying types: any int is a representable value, so IsValid can reject it.
  enum Objective : int {
    // Squared first-harmonic amplitude a1² + b1² of the response DOF (smooth): min/max response.
    kAmplitude,
    // Loss factor η (paper Eq. 6/Table 1): the minimum response maximises η, the maximum
    // response minimises η.
    kLossFactor,
  };

  enum Method : int {
    // Ipopt over [x̂, α] with the equality constraints R = 0 (exact Jacobian, L-BFGS Hessian).
    kFullSpace,
    // Projected gradient over α only: every iterate solves R(x, α) = 0 by Newton and the
    // gradient comes from the adjoint of ∂R/∂x. 3-20x cheaper on the lumped case (the
    // interior-point iterations crawl along the kinks of the response) and, there, never worse.
    kReducedSpace,
    // Both optimisers from every seed, the better result kept (the most thorough, the slowest).
    kBoth,
  };

  // α vectors the optimisations start from (one entry per contact, each in [−1, 1]). Empty: the
  // default set DefaultAlphaSeeds(num_contacts).
  std::vector<Eigen::VectorXd> alpha_seeds;
  // Seeds added to those, so that their number grows with the interfaces, never as 2^nα:
  // seed_groups[a] is the group (an FE interface) of α entry a; for each group g the two
  // patterns "+1 on g, −1 elsewhere" and "−1 on g, +1 elsewhere". Empty: none.
  std::vector<int> seed_groups;
  // Random seeds, uniform in [−1, 1]^nα (generator seeded with sample_seed + 1).
  int random_seeds = 0;
  Method method = kReducedSpace;
  int max_iterations = 200;  // optimiser iterations per run
  // Nonmonotone line search of the reduced-space runs (Grippo, Lampariello & Lucidi 1986; the
  // spectral projected gradient of Birgin, Martinez & Raydan 2000): a trial α is accepted when
  // its objective is below the largest of the last `line_search_memory` iterates' (minus the
  // Armijo term), so the Barzilai-Borwein steps are cut less often and a run can cross a kink of
  // the response a monotone search stops at. Each run still ends on its best iterate (from
  // which it goes on monotonically if a stopping test held elsewhere). 1: monotone Armijo. The
  // harmonic ladder's refinement at H runs monotonically from its H = 1 optimum, which it only
  // carries to its neighbour at H (docs/decisions/0015-bound-runs-steps-and-stops.md).
  int line_search_memory = 10;
  // A reduced-space run is stopped (BoundStatus::kAbandoned, BoundsResult::runs_abandoned) once,
  // after at least 10 iterations, it would need more than 10x its best progress per iteration
  // over the last 10 to reach, within its remaining iterations, the bound that a seed's start
  // already gives as a KKT point. Such runs crawl along kinks of the response for hundreds of
  // iterations towards a local optimum that cannot be the bound. ImproveBounds (the curve's
  // neighbour starts) also compares with the bounds it was given: its runs from known solutions
  // that cannot reach them are stopped likewise.
  bool stop_dominated_runs = true;
  // With stop_dominated_runs: each run is also measured against the best bound the runs before
  // it at this point reached (in seed order, per direction; CLI --dominance runs), not only
  // against the KKT starts (--dominance starts), so a seed's run that crawls towards a lower
  // local optimum than an earlier seed's is stopped too. The result then depends on the (fixed)
  // order of the seeds.
  bool dominated_by_earlier_runs = true;
  double tolerance = 1e-9;  // optimality tolerance of the scaled problem
  // A reduced-space run is stationary once its objective (scaled by its start's) changes by at
  // most this relative amount in 3 accepted iterations in a row.
  double stationary_change = 1e-7;
  // The same test for the harmonic ladder's refinement at H (search_harmonics = 1), which only
  // carries an H = 1 optimum to its neighbour at H: there a change of 1e-5 per iteration is far
  // below what the truncation at H itself changes the bounds by (docs/lumped-vs-fe.md).
  double refinement_stationary_change = 1e-5;
  // The nonmonotone search's own stationarity: a reduced-space run stops (converged, on its best
  // iterate) once its best objective improved by at most stall_change (relative) over the last
  // stall_window accepted iterations. Its iterates may go up and down along the kinks of the
  // response for the whole iteration limit without three quiet iterations in a row.
  // stall_window 0: no such test.
  double stall_change = 1e-4;
  int stall_window = 20;
  // Minimum runs of the amplitude objective try a Gauss-Newton step for the response phasor
  // y(α) = (a1, b1) → 0 before each projected-gradient step: the least-norm δα with
  // J δα = −y on the α box (J = ∂y/∂α, its second row by one more adjoint solve), accepted
  // where it halves φ = |y|². Where some α bring the response DOF to rest (next to its
  // anti-resonances) the projected gradient stops at kinks of the response or crawls; the
  // Gauss-Newton steps cross them to y ≈ 0 in a few iterations. After a failed
  // step the next waits 2, 4, ... 64 iterations, so that runs towards a minimum y ≠ 0 lose
  // little. False: projected gradient only.
  bool gauss_newton_minimum = true;
  // > 0: maximum runs (reduced space) step along a limited-memory BFGS direction on the free α
  // (those the gradient does not hold at a bound; the two-loop recursion of Nocedal 1980 over
  // the last maximum_bfgs_memory accepted steps with positive curvature), backtracking from the
  // full step, instead of the projected gradient with Barzilai-Borwein steps. Another path to
  // other local maxima, higher at some points and lower at others: a second opinion on a
  // maximum (CLI --max-bfgs-memory 5; docs/decisions/0015-bound-runs-steps-and-stops.md). Minimum
  // runs always take the gradient (with BFGS they lost the deep minima the Gauss-Newton steps
  // find). 0 (default): the gradient only.
  int maximum_bfgs_memory = 0;
  Objective objective = kAmplitude;
  // Sample check: after the optimisation, the response is solved at this many random α (fixed
  // seed below). A sample beyond a bound proves that bound a local optimum only: the optimiser
  // restarts from the best such sample and the bound becomes the better of the two (reported in
  // BoundsResult::improved_by_samples). 0 switches the check off.
  int check_samples = 16;
  unsigned sample_seed = 20241;
  // Harmonic ladder: 0 (default) searches at the system's own H. 1 runs the whole search above
  // (seeds, runs, sample check) on the system's H = 1 sibling (FirstHarmonicBalance), then
  // re-optimises each bound at the system's H from its H = 1 optimum (higher harmonics zero,
  // ImproveBounds); a bound whose refinement fails is searched again at H in full. The bounds
  // are solutions at H. Where contacts slip the H = 1 optimum lies next to the H = 3 one, and
  // the multi-start costs a fraction of its price at H (docs/decisions/0004-harmonic-ladder.md).
  // Ignored when the system has H = 1; an error where the system cannot drop harmonics (loads above
  // H = 1).
  int search_harmonics = 0;
  // Minima that start nothing else stop at a negligible response: the harmonic ladder's
  // refinement at H of the minimum, and a curve's pass 2 (runs from the neighbours' optima,
  // RefineFromNeighbours), stop a minimum run once the response falls to negligible_minimum times
  // the point's maximum found so far (the H = 1 search's, pass 1's), and pass 2 makes no minimum
  // runs where pass 1's minimum is below that already. R is then below this ratio, which is all
  // the robustness needs, and the bound is that feasible point (BoundSolution::stationary false).
  // Next to an anti-resonance of the response DOF the runs otherwise drive y_min down by decades
  // at R ~ 0. Not the search's own runs: a curve's pass 1 minima start the neighbours' runs,
  // where stopping them early costs more than it saves. 0: every run goes on to its stopping
  // tests.
  double negligible_minimum = 1e-3;
  // A minimising run of the amplitude objective stops at a response at or below this [m]; 0:
  // never. The harmonic ladder sets it from negligible_minimum for its refinement.
  double minimum_stop_m = 0.0;
  // Progress inside one bound computation, on the caller's thread: (stage, done, total) with
  // stage "seeds" (after each seed's min and max runs) and "samples" (after each check sample),
  // on the harmonic ladder then "harmonic refinement" (0 of 1 at its start, 1 at its end).
  std::function<void(const std::string& stage, int done, int total)> progress;

  bool IsValid(std::string* error) const;
};

// "ipopt" | "reduced" | "both" and back; FromString returns false on an unknown name.
std::string ToString(BoundsOptions::Method method);
bool FromString(const std::string& name, BoundsOptions::Method* method);

// 0, +½·1, −½·1 and the two alternating patterns (+1, −1, +1, ...), (−1, +1, −1, ...)
// (duplicates removed). The alternating corners matter: on the lumped benchmark near resonance
// the minimum response is only reached from one of them.
std::vector<Eigen::VectorXd> DefaultAlphaSeeds(int num_contacts);

// Where the seeds of a bound computation came from (BoundsResult::seed_counts).
struct SeedCounts {
  int base = 0;            // options.alpha_seeds, or the default set
  int group_patterns = 0;  // two per seed group
  int random = 0;
};
// Every seed of a computation with num_alpha α: base, group patterns, random (duplicates
// removed). Throws std::invalid_argument when seed_groups has the wrong size or a negative entry.
std::vector<Eigen::VectorXd> AlphaSeeds(int num_alpha, const BoundsOptions& options,
                                        SeedCounts* counts = nullptr);

enum class BoundStatus {
  // A usable bound: a point satisfying R = 0 where the optimiser met its tolerances, or a
  // feasible point beyond every such point found (BoundSolution::stationary false).
  kConverged,
  kMaxIterations,  // iteration limit
  kInfeasible,     // the optimiser found no point satisfying R = 0
  kFailed,         // anything else (restoration failure, tiny steps, evaluation errors, ...)
  // Stopped because it could not reach the bound a KKT start (or, in ImproveBounds, the bound
  // held) already gives (BoundsOptions::stop_dominated_runs); never the status of a bound.
  kAbandoned,
};
std::string ToString(BoundStatus status);

struct BoundSolution {
  Eigen::VectorXd x;      // harmonic coefficients (see hbm.h)
  Eigen::VectorXd alpha;  // one per contact
  // Failed runs keep NaN here: a bound that did not converge is never a number.
  double amplitude = std::numeric_limits<double>::quiet_NaN();    // first-harmonic amplitude [m]
  double loss_factor = std::numeric_limits<double>::quiet_NaN();  // η at (x, α)
  double residual = std::numeric_limits<double>::quiet_NaN();  // ‖R(x, α)‖ / ResidualScale()
  BoundStatus status = BoundStatus::kFailed;
  std::string message;
  int iterations = 0;  // interior-point iterations of the run that produced this solution
  int seed = -1;       // index of the α seed it came from
  std::vector<ContactRegime> regimes;
  // True where a run's stopping test held (a KKT or stationary point, or a start that passed the
  // KKT test); false for a feasible point taken because it goes beyond those: an α sample, a
  // known solution, or the last iterate of a run stopped at its iteration limit. A bound encloses
  // every feasible point its runs reached, finished or not.
  bool stationary = false;
  // Hill stability of the solution (stability.h, AssessBoundStability); not computed: the note
  // says why, stable and max_floquet_real stay false / NaN.
  struct Stability {
    bool computed = false;
    bool stable = false;
    double max_floquet_real = std::numeric_limits<double>::quiet_NaN();  // [1/s]
    std::string note;
  } stability;
  bool IsUsable() const { return status == BoundStatus::kConverged; }
};

// One α level's bounds in a coarse-to-fine search (bound_search.h), at its result's H. Each
// level started from the optima of the level below and kept them as candidates, so every level's
// bounds contain the coarser levels'.
struct LevelBound {
  std::string level;       // AlphaLevel::name: "interface", "face", "pair"
  int parameters = 0;      // the level's α parameters
  BoundSolution min, max;  // α: the level's parameters c (fine α = clamp(P c))
  int corners_solved = 0;  // corners of the level's box solved to rank its starts
  int corners_failed = 0;
  int optimizer_runs = 0;
  int samples_checked = 0;
  int improved_by_samples = 0;
  // Bounds of this level that a coarser level's optimum went beyond (0-2): evidence that the
  // level's own runs fell short where the hierarchy holds them.
  int raised_by_coarser = 0;
  // The finest level only: the single-level search's own optima at the search's H, refined at H
  // beside the level's (their order at H = 1 need not hold at H: 1106 Hz).
  BoundSolution single_min, single_max;
  double wall_s = 0.0;     // the level's search and (on the harmonic ladder) refinement
  double refine_s = 0.0;   // of which the refinement at H
  double corners_s = 0.0;  // of which the corners' solves
  double robustness() const;
};

// Bounds over the stable solutions among candidates (stability.h, BoundsOverStableSolutions):
// the bounds' own solutions and fixed-α solves at samples of the α box, each judged by Hill. Not
// an optimisation over the stable set: where a bound's own solution is stable it is also the
// stable bound (exact); otherwise the most extreme stable candidate, an inner estimate of the
// stable range. candidates = 0: not computed.
struct StableBounds {
  BoundSolution min, max;  // NaN amplitude where no candidate is stable
  bool exact_min = false, exact_max = false;
  int candidates = 0;     // converged candidates judged by Hill
  int stable = 0;         // of which stable
  int approximate = 0;    // of which judged with contacts switching between stick and slip
  int failed = 0;         // samples whose solve did not converge, or Hill not computed
  int beyond_bounds = 0;  // samples (stable or not) outside [min, max]: the search missed them
  // 1 − (y_max − y_min) / y_max over the stable bounds; NaN unless both exist.
  double robustness() const;
};

struct BoundsResult {
  double freq_hz = 0.0;
  // The α levels of a coarse-to-fine search, coarsest first, the last this result's own bounds;
  // empty for a search on one level (lumped cases, α per interface).
  std::vector<LevelBound> levels;
  BoundSolution min, max;  // minimum and maximum response (best converged seed of each)
  // Spread of the objective over the seeds whose run converged (amplitude [m] for kAmplitude,
  // η for kLossFactor): 0 when every seed reached the same optimum.
  double spread_min = 0.0, spread_max = 0.0;
  int seeds_tried = 0;
  SeedCounts seed_counts;   // the first optimisation's seeds by origin
  int seeds_converged = 0;  // seeds whose start solve and both runs converged
  int start_failures = 0;   // seeds whose starting harmonic-balance solve failed (skipped)
  int min_failures = 0;     // runs that did not converge (never used as a bound)
  int max_failures = 0;
  int optimizer_runs = 0;  // runs that needed the optimiser; the others started at a KKT point
  int runs_abandoned = 0;  // of those, stopped as dominated (BoundsOptions::stop_dominated_runs)
  // Sample check (BoundsOptions::check_samples): samples solved, failed, and the bounds (0-2)
  // that a sample beat, so that the optimiser was restarted from it.
  int samples_checked = 0;
  int samples_failed = 0;
  int improved_by_samples = 0;
  // The H of the seeds' search and sample check (BoundsOptions::search_harmonics): the system's
  // own H, or 1 when the bounds were refined from H = 1 optima; refinement_fallbacks counts the
  // bounds that had to be searched again at H because their refinement failed.
  int search_harmonics = 0;
  int refinement_fallbacks = 0;
  int harmonics = 0;  // the H of the bounds' solutions: the system's

  double wall_s = 0.0;  // wall time of ComputeBounds [s]
  StableBounds stable;  // on request (bounds --stable-only)
  // Paper Eq. 10: 1 − (y_max − y_min) / y_max; NaN unless both bounds converged.
  double robustness() const;
  bool IsUsable() const { return min.IsUsable() && max.IsUsable(); }
  std::string BriefReport() const;
};

// Response bounds of `system` at freq_hz. Throws std::invalid_argument on invalid options, a
// non-positive frequency, or seeds whose size differs from the number of contacts; numerical
// failures are reported through the statuses.
BoundsResult ComputeBounds(const HarmonicBalance& system, double freq_hz,
                           const BoundsOptions& options);

// True when bounds of `system` take the harmonic ladder: options.search_harmonics = 1 and H > 1.
bool UsesHarmonicLadder(const HarmonicBalance& system, const BoundsOptions& options);
// The balance the search runs on: system.FirstHarmonicBalance() on the ladder, else `system`.
// Throws std::invalid_argument where the ladder is asked of a balance that cannot drop its
// higher harmonics (loads above the first harmonic).
const HarmonicBalance& SearchBalance(const HarmonicBalance& system, const BoundsOptions& options);

// The second rung of the harmonic ladder (BoundsOptions::search_harmonics = 1): the bounds of
// `system` at its own H, re-optimised from the optima of `low`, bounds of the same frequency
// computed on system.FirstHarmonicBalance() (higher harmonics zero at the start). A bound lost
// in the refinement is searched again at H in full (counted in refinement_fallbacks). The result
// carries low's seed and sample counts plus the refinement's runs; wall_s is low's plus the
// refinement's. Throws std::invalid_argument on invalid options.
BoundsResult RefineBoundsAtHarmonics(const HarmonicBalance& system, const BoundsResult& low,
                                     const BoundsOptions& options);

// A harmonic-balance solution known from elsewhere: a time integration's state refined by Newton,
// a sample beyond a bound, the optimum at a neighbouring frequency. x is a Newton start at α (it
// may belong to another frequency); near a resonance several periodic solutions coexist at one α
// and a start from x keeps the one that was found, where the bounds' own starts may not reach it.
struct KnownSolution {
  Eigen::VectorXd x;      // harmonic coefficients (HarmonicBalance layout)
  Eigen::VectorXd alpha;  // one per α entry, each in [−1, 1]
  // Optimiser runs from it towards the minimum and the maximum response (a minimum's optimum
  // tracked in frequency needs only the first).
  bool run_min = true, run_max = true;
  // Where neither Newton nor the residual homotopy from x reaches a solution at this frequency:
  // true, the runs start from a solution at α found by the seeds' cold routes (StartSolution;
  // minutes per start next to a resonance); false, the known solution is dropped — for one that
  // matters for its branch (a neighbouring frequency's optimum), which a cold start at its α
  // need not find.
  bool cold_start = true;
  // With cold_start: the start may lie short of α, where the α homotopy from 0 stops (a kink of
  // the contact laws it cannot pass) — the run needs a solution near α, not at it — instead of the
  // continuations in frequency, which take minutes next to a resonance. Seeds keep the
  // continuations: they find branches the α path does not.
  bool start_short_of_alpha = false;
};

// Bound runs (both directions) started from known solutions, folded into `bounds` with
// MergeBounds; a known solution that Newton converges on at freq_hz is itself a candidate. The
// options' seed sets, random seeds and sample check are not used. Returns how many of the two
// bounds moved outwards (0-2). Throws std::invalid_argument on invalid options, a size mismatch
// or a bounds result of another frequency.
int ImproveBounds(const HarmonicBalance& system, double freq_hz, const BoundsOptions& options,
                  const std::vector<KnownSolution>& known, BoundsResult* bounds);

// Folds a second computation of the same frequency (other starts) into `into`: per bound the
// better converged solution by `objective` (a failed one never replaces a converged one), the
// counts and wall times summed, the spreads widened to cover both best values. Throws
// std::invalid_argument when the frequencies differ.
void MergeBounds(const BoundsResult& other, BoundsOptions::Objective objective, BoundsResult* into);

}  // namespace fricrom
