// Robust design (paper §3): robustness R = 1 − δ/y_max of the response bounds at the resonance,
// a manual sweep of a design parameter, and the nested optimisation (NOA) that finds the most
// robust parameter value. The model at a parameter value comes from a caller-supplied factory
// (the CLI rebuilds the case with `--set name=value`), so any named parameter can be designed.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fricrom/bound_search.h"
#include "fricrom/bounds.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

// The harmonic-balance problem at a parameter value (full or condensed, see balance.h).
using BalanceFactory = std::function<std::unique_ptr<HarmonicBalance>(double parameter)>;

// Frequency of the peak of the maximum-response bound y_max(f) in [lo, hi]: a coarse scan of
// `scan_points` bound solves, then golden-section refinement to `tolerance_hz`.
struct ResonanceSearchOptions {
  double lo_hz = 0.0;
  double hi_hz = 0.0;
  int scan_points = 11;
  double tolerance_hz = 0.02;
  bool IsValid(std::string* error) const;
};
struct ResonanceResult {
  double freq_hz = 0.0;  // NaN when no maximum-response bound converged anywhere in the range
  BoundsResult bounds;   // the bounds at freq_hz
  int bound_solves = 0;
};
// Each bound solve is ComputeLevelBounds over `levels` (none or one level: ComputeBounds).
ResonanceResult FindResonance(const HarmonicBalance& system, const ResonanceSearchOptions& search,
                              const BoundsOptions& bounds, const LevelSearchOptions& levels = {});

// Bound curve. Pass 1 computes every frequency on its own (independent units of work); pass 2
// (the warm start) re-optimises each point from the optima of its neighbours (the optimum moves
// little between neighbouring frequencies) and keeps, per bound, the better of its two passes.
// One thread, several threads, MPI ranks and a resumed run give the same curve.
struct BoundCurveOptions {
  BoundsOptions bounds;
  // The α levels each point's search runs over (bound_search.h); none or one: ComputeBounds.
  LevelSearchOptions levels;
  bool warm_start = true;  // pass 2
  // How pass 2 reaches the neighbours' optima:
  //  kSweeps     two sweeps, one up and one down the curve, each point from the pass-2 bounds of
  //              the point before it in the sweep, the better of the two kept: an optimum found
  //              at one frequency travels the whole curve in one pass (two units of work);
  //  kNeighbours each point from the pass-1 optima of i − 1 and i + 1 (n units, any order): an
  //              optimum travels one point per pass, so a maximum found at one point reaches
  //              few others (docs/decisions/0015-bound-runs-steps-and-stops.md).
  enum NeighbourPass { kSweeps, kNeighbours };
  NeighbourPass neighbour_pass = kSweeps;
  // Pass 1 in full (every seed, the sample check) at every anchor_every-th frequency and the
  // last; between two anchors the optima are continued in frequency from each anchor towards the
  // other (ContinueBounds) and the better of the two kept. 1: every frequency in full. Cheaper
  // where a point's seeds cost much (near FE resonances), at the price of each point's own
  // multi-start: charted in docs/bounds-and-design.md.
  int anchor_every = 1;
  // Worker threads over the frequencies (0 = every core); more than one needs a BalanceMaker.
  int threads = 1;
  // (stage, done, total): stage "frequencies" after each pass-1 point, "sweeps" after each of
  // pass 2's sweeps (kSweeps) or "neighbour starts" after each pass-2 point; with one thread
  // also each point's own stages prefixed by its frequency ("1000 Hz: seeds", "1000 Hz:
  // samples").
  std::function<void(const std::string& stage, int done, int total)> progress;
  bool IsValid(std::string* error) const;
};
struct BoundCurve {
  std::vector<BoundsResult> points;  // one per frequency, in the given order
  int peak = -1;                     // largest converged y_max; −1 when none converged
  double wall_s = 0.0;
  bool HasPeak() const { return peak >= 0; }
  std::string BriefReport() const;
};
// One stage of a bound curve: its name ("frequencies", "continuations", "sweeps", "neighbour
// starts", "harmonic refinement"), the key of its unit 0 (unit u of the stage is key + u: a
// journal's numbering, the same in every run of the curve), and whether a unit gives several
// points (a sweep, a chain) or one.
struct CurveStageSpec {
  std::string name;
  int key = 0;
  bool many = false;
};
// Runs a curve's stages: ComputeBoundCurve says what each unit computes, the runner where and
// when — threads (ThreadStageRunner), MPI ranks, a journal that skips the units an earlier run
// finished. Run returns every unit's result (unit id -> points) to every caller; a runner over
// MPI ranks is called on every rank alike, each calling ComputeBoundCurve.
class CurveStageRunner {
 public:
  using Unit = std::function<std::vector<BoundsResult>(int unit)>;
  virtual ~CurveStageRunner() = default;
  virtual std::map<int, std::vector<BoundsResult>> Run(const CurveStageSpec& stage,
                                                       const std::vector<int>& units,
                                                       const Unit& unit) = 0;
};
// Units on `threads` threads of this process (0: every core), in the order given, with
// progress(stage, done, total) after each.
class ThreadStageRunner : public CurveStageRunner {
 public:
  ThreadStageRunner(int threads, std::function<void(const std::string&, int, int)> progress = {});
  std::map<int, std::vector<BoundsResult>> Run(const CurveStageSpec& stage,
                                               const std::vector<int>& units,
                                               const Unit& unit) override;

 private:
  int threads_;
  std::function<void(const std::string&, int, int)> progress_;
};

// `points` frequencies evenly spaced over [lo_hz, hi_hz] (both included; points >= 2).
std::vector<double> EvenFrequencies(double lo_hz, double hi_hz, int points);
// Throws std::invalid_argument on invalid options or a non-positive or non-finite frequency.
// make_balance builds the balance of each extra thread (see balance_pool.h).
// The stages run on options.threads threads (ThreadStageRunner with options.progress).
BoundCurve ComputeBoundCurve(
    const HarmonicBalance& system, const std::vector<double>& freqs_hz,
    const BoundCurveOptions& options,
    const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance = {});
// The same curve, its stages run by `runner` (the curve does not depend on how): pass 1 at the
// anchors (keys 0 + i), the continuations between anchors (2n + c), pass 2 as two sweeps
// (n, n + 1) or per point (n + i), the harmonic ladder's refinement (2n + chains + i).
BoundCurve ComputeBoundCurve(const HarmonicBalance& system, const std::vector<double>& freqs_hz,
                             const BoundCurveOptions& options,
                             const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance,
                             CurveStageRunner& runner);

// The two passes one point at a time, for callers that hand the points out themselves (MPI
// ranks, journals). Pass 2 of point i: pass1[i] merged (MergeBounds) with the bounds from the
// neighbours' optimal α that differ from pass1[i]'s own; pass1[i] unchanged, at no cost, when
// they offer no new start. wall_s is pass 1's plus pass 2's.
BoundsResult RefineFromNeighbours(const HarmonicBalance& system,
                                  const std::vector<BoundsResult>& pass1, int i,
                                  const BoundsOptions& bounds);
// Pass 2 as a sweep (BoundCurveOptions::kSweeps): along the points in order (upwards: 0 to
// n − 1, else n − 1 to 0), each point's pass-1 bounds re-optimised as in RefineFromNeighbours
// from the sweep's result at the point before it, its minimum towards the minimum and its
// maximum towards the maximum only; the first point is pass 1's. Results in the points' order.
std::vector<BoundsResult> SweepBounds(const HarmonicBalance& system,
                                      const std::vector<BoundsResult>& pass1, bool upwards,
                                      const BoundsOptions& bounds);
// The two sweeps' results point by point: `up` merged with `down` (MergeBounds); wall_s is pass
// 1's plus both sweeps' time at the point.
std::vector<BoundsResult> MergeSweeps(std::vector<BoundsResult> up,
                                      const std::vector<BoundsResult>& down,
                                      const std::vector<BoundsResult>& pass1,
                                      BoundsOptions::Objective objective);
std::string ToString(BoundCurveOptions::NeighbourPass pass);
bool FromString(const std::string& name, BoundCurveOptions::NeighbourPass* pass);
// The anchors of a curve of n points: 0, k, 2k, ... and n − 1 (every point for k = 1).
std::vector<int> CurveAnchors(int n, int anchor_every);
// Continuation of the optima of `from` along freqs_hz (in the order given, from.freq_hz's
// neighbour first): at each frequency a minimum run from the last minimum and a maximum run from
// the last maximum, Newton starting from their x (ImproveBounds). A point where a direction
// finds nothing keeps that bound failed (NaN) and the next starts from the last that converged.
std::vector<BoundsResult> ContinueBounds(const HarmonicBalance& system, const BoundsResult& from,
                                         const std::vector<double>& freqs_hz,
                                         const BoundsOptions& bounds);
// A continuation between two anchors: from anchor `from`, through `points` in order of travel.
// Each stretch between neighbouring anchors has two, one from either end.
struct CurveChain {
  int from = 0;
  std::vector<int> points;
};
std::vector<CurveChain> CurveChains(const std::vector<int>& anchors);
// Folds the chains' results (chain_results[c][k] for chains[c].points[k]) into `points`: the first
// chain to reach a point sets it, the others merge into it (MergeBounds).
void MergeChains(const std::vector<CurveChain>& chains,
                 const std::vector<std::vector<BoundsResult>>& chain_results,
                 BoundsOptions::Objective objective, std::vector<BoundsResult>* points);
// The curve of finished points (peak located; wall_s left for the caller).
BoundCurve AssembleBoundCurve(std::vector<BoundsResult> points);

struct RobustnessPoint {
  double parameter = 0.0;
  double freq_hz = 0.0;
  BoundsResult bounds;
  double robustness = 0.0;  // NaN when a bound did not converge
  int bound_solves = 0;
};

struct SweepOptions {
  BoundsOptions bounds;
  // The α levels of every value's bound run (ComputeLevelBounds; none or one: ComputeBounds).
  // The levels' maps must fit every value's α count: a design parameter that changes the
  // contacts (a mesh) needs its own levels, i.e. a sweep of its own per mesh.
  LevelSearchOptions levels;
  // R is evaluated at reference_freq_hz when track_peak is false (the NOA's ω_ref), else at the
  // peak of y_max located for every parameter value within `search`.
  double reference_freq_hz = 0.0;
  bool track_peak = false;
  ResonanceSearchOptions search;
  // Warm start: add the previous value's optimal α to the seeds. It makes a point depend on the
  // order the values are run in, so it is off by default (every value is an independent unit of
  // work, which threads, MPI ranks and resumed runs can take in any order with the same result)
  // and needs threads = 1.
  bool warm_start = false;
  int threads = 1;  // worker threads over the values (0 = every core)
  bool IsValid(std::string* error) const;
};

// Progress: (done, total).
using DesignProgress = std::function<void(int, int)>;
// Called once per finished value (index into `values`), one call at a time, in completion order.
using SweepPointDone = std::function<void(int, const RobustnessPoint&)>;

// R at every value. Values whose `finished` entry is true (e.g. read back from a journal of an
// interrupted run) are not computed; their entries of the result are default points.
std::vector<RobustnessPoint> SweepRobustness(const BalanceFactory& factory,
                                             const std::vector<double>& values,
                                             const SweepOptions& options,
                                             const DesignProgress& progress = {},
                                             const SweepPointDone& point_done = {},
                                             const std::vector<bool>& finished = {});

struct NoaOptions {
  enum Objective {
    kLossFactorGap,  // η2 − η1 (paper §3.2): loss factors of the minimum and maximum response
    kOneMinusR,      // 1 − R directly
  };
  double lower = 0.0;  // parameter interval [lower, upper]
  double upper = 1.0;
  Objective objective = kLossFactorGap;
  // Outer method: a global scan of `scan_points` values, then golden-section refinement of the
  // best bracket to `parameter_tolerance`. R(p) has plateaus (R = 1 over an interval) and can be
  // monotone up to the interval's end, where the paper's gradient method stopped early.
  int scan_points = 9;
  double parameter_tolerance = 2e-3;
  SweepOptions inner;  // frequency choice and inner bound options (reference_freq_hz required)
  // The scan's values are independent units of work (cold starts, like a sweep's), evaluated by
  // this function when set (the CLI hands them to MPI ranks), else by SweepRobustness on
  // inner.threads threads. It must return one point per value, in order. The refinement after
  // the scan runs in order, each evaluation warm-started from the nearest evaluated value.
  std::function<std::vector<RobustnessPoint>(const std::vector<double>& values)> scan_evaluator;
  bool IsValid(std::string* error) const;
};
// The values of the NOA's global scan: scan_points values evenly over [lower, upper].
std::vector<double> NoaScanValues(const NoaOptions& options);

struct NoaResult {
  double p_opt = 0.0;
  double robustness = 0.0;
  double eta1 = 0.0;  // loss factor at the maximum response (configuration #1)
  double eta2 = 0.0;  // loss factor at the minimum response (configuration #2)
  double objective = 0.0;
  int outer_iterations = 0;
  int inner_solves = 0;  // bound problems solved (two per outer evaluation: min and max)
  double wall_s = 0.0;
  std::vector<RobustnessPoint> history;  // every outer evaluation, in order
  bool converged = false;
  std::string message;
  std::string BriefReport() const;
};

NoaResult RunNoa(const BalanceFactory& factory, const NoaOptions& options,
                 const DesignProgress& progress = {});

}  // namespace fricrom
