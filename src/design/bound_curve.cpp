// Bound curves over frequency: the bounds point by point (independent units of work, on threads),
// the order-free warm start from the neighbours' optima, and the resonance of the maximum bound.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/balance_pool.h"
#include "fricrom/design.h"
#include "fricrom/work_queue.h"

namespace fricrom {

std::vector<double> EvenFrequencies(double lo_hz, double hi_hz, int points) {
  if (points < 2 || !(lo_hz > 0.0) || !(hi_hz > lo_hz) || !std::isfinite(hi_hz)) {
    throw std::invalid_argument("EvenFrequencies: need 0 < lo < hi (finite) and points >= 2");
  }
  std::vector<double> f(points);
  for (int i = 0; i < points; ++i) f[i] = lo_hz + (hi_hz - lo_hz) * i / (points - 1);
  return f;
}

bool BoundCurveOptions::IsValid(std::string* error) const {
  if (anchor_every < 1) {
    *error = "BoundCurveOptions.anchor_every must be >= 1, got " + std::to_string(anchor_every);
    return false;
  }
  if (threads < 0) {
    *error =
        "BoundCurveOptions.threads must be >= 0 (0: every core), got " + std::to_string(threads);
    return false;
  }
  return bounds.IsValid(error) && levels.IsValid(error);
}

namespace {

// True when `a` is already among the starts (the point's own optima) or not usable.
bool AlreadyTried(const BoundSolution& a, const BoundsResult& own) {
  if (!a.IsUsable()) return true;
  for (const BoundSolution* b : {&own.min, &own.max}) {
    if (b->IsUsable() && b->alpha.size() == a.alpha.size() && b->alpha == a.alpha) return true;
  }
  return false;
}

// Point `own` re-optimised from the optima of `from` (other frequencies' bounds): each optimum
// in both directions, or with own_direction a minimum only towards the minimum and a maximum
// only towards the maximum.
BoundsResult RefineFrom(const HarmonicBalance& system, const BoundsResult& own,
                        const std::vector<const BoundsResult*>& from, const BoundsOptions& bounds,
                        bool own_direction) {
  // The neighbours' optima as known solutions: Newton (or the residual homotopy) from their x
  // keeps their branch of periodic solutions, where a cold start at their α may not; one that
  // neither reaches is dropped, not started cold (50-point FE curve: 272 s of cold routes at
  // 1101.02 Hz in pass 2).
  // Pass 2's minima start nothing else (the ladder's refinement at most): its minimum runs stop
  // at a negligible response, and make none where pass 1's minimum is negligible already
  // (BoundsOptions::negligible_minimum).
  BoundsOptions options = bounds;
  bool run_min = true;
  if (bounds.negligible_minimum > 0.0 && bounds.objective == BoundsOptions::kAmplitude &&
      own.max.IsUsable()) {
    options.minimum_stop_m = bounds.negligible_minimum * own.max.amplitude;
    run_min = !(own.min.IsUsable() && own.min.amplitude <= options.minimum_stop_m);
  }
  std::vector<KnownSolution> known;
  for (const BoundsResult* r : from) {
    for (const BoundSolution* s : {&r->min, &r->max}) {
      if (AlreadyTried(*s, own)) continue;
      bool dup = false;
      for (const KnownSolution& k : known) dup = dup || k.alpha == s->alpha;
      if (dup) continue;
      const bool is_min = s == &r->min;
      known.push_back({s->x, s->alpha, run_min && (!own_direction || is_min),
                       !own_direction || !is_min, false});
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  BoundsResult out = own;
  // Only the neighbours' optima: pass 1 already ran the seed set and the sample check.
  ImproveBounds(system, own.freq_hz, options, known, &out);
  // A point's time is what it cost in all passes (the curve's per-point wall times).
  out.wall_s =
      own.wall_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

BoundsResult RefineFromNeighbours(const HarmonicBalance& system,
                                  const std::vector<BoundsResult>& pass1, int i,
                                  const BoundsOptions& bounds) {
  const int n = static_cast<int>(pass1.size());
  if (i < 0 || i >= n) throw std::invalid_argument("RefineFromNeighbours: no such point");
  std::vector<const BoundsResult*> from;
  for (int j : {i - 1, i + 1}) {
    if (j >= 0 && j < n) from.push_back(&pass1[j]);
  }
  return RefineFrom(system, pass1[i], from, bounds, false);
}

std::vector<BoundsResult> SweepBounds(const HarmonicBalance& system,
                                      const std::vector<BoundsResult>& pass1, bool upwards,
                                      const BoundsOptions& bounds) {
  const int n = static_cast<int>(pass1.size());
  std::vector<BoundsResult> out(n);
  for (int k = 0; k < n; ++k) {
    const int i = upwards ? k : n - 1 - k;
    if (k == 0) {
      out[i] = pass1[i];
      continue;
    }
    // The point before it in the sweep, already improved by the sweep, as its only neighbour;
    // each optimum in its own direction (on the FE cascade's curve the other direction's runs
    // doubled the sweeps' time and moved no bound).
    out[i] = RefineFrom(system, pass1[i], {&out[upwards ? i - 1 : i + 1]}, bounds, true);
  }
  return out;
}

std::vector<BoundsResult> MergeSweeps(std::vector<BoundsResult> up,
                                      const std::vector<BoundsResult>& down,
                                      const std::vector<BoundsResult>& pass1,
                                      BoundsOptions::Objective objective) {
  if (down.size() != up.size() || pass1.size() != up.size()) {
    throw std::invalid_argument("MergeSweeps: one result per point in each sweep and in pass 1");
  }
  for (size_t i = 0; i < up.size(); ++i) {
    const double wall = up[i].wall_s + down[i].wall_s - pass1[i].wall_s;
    MergeBounds(down[i], objective, &up[i]);
    up[i].wall_s = wall;
  }
  return up;
}

std::string ToString(BoundCurveOptions::NeighbourPass pass) {
  return pass == BoundCurveOptions::kSweeps ? "sweeps" : "neighbours";
}

bool FromString(const std::string& name, BoundCurveOptions::NeighbourPass* pass) {
  if (name == "sweeps") {
    *pass = BoundCurveOptions::kSweeps;
  } else if (name == "neighbours") {
    *pass = BoundCurveOptions::kNeighbours;
  } else {
    return false;
  }
  return true;
}

std::vector<int> CurveAnchors(int n, int anchor_every) {
  if (n < 0 || anchor_every < 1) throw std::invalid_argument("CurveAnchors: n >= 0, every >= 1");
  std::vector<int> a;
  for (int i = 0; i < n; i += anchor_every) a.push_back(i);
  if (n > 0 && a.back() != n - 1) a.push_back(n - 1);
  return a;
}

std::vector<BoundsResult> ContinueBounds(const HarmonicBalance& system, const BoundsResult& from,
                                         const std::vector<double>& freqs_hz,
                                         const BoundsOptions& bounds) {
  std::vector<BoundsResult> out;
  BoundSolution last_min = from.min, last_max = from.max;
  for (double f : freqs_hz) {
    const auto t0 = std::chrono::steady_clock::now();
    BoundsResult r;
    r.freq_hz = f;
    r.min.message = r.max.message = "continuation in frequency: no run converged";
    std::vector<KnownSolution> known;
    if (last_min.IsUsable()) known.push_back({last_min.x, last_min.alpha, true, false});
    if (last_max.IsUsable()) known.push_back({last_max.x, last_max.alpha, false, true});
    ImproveBounds(system, f, bounds, known, &r);
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.min.IsUsable()) last_min = r.min;
    if (r.max.IsUsable()) last_max = r.max;
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<CurveChain> CurveChains(const std::vector<int>& anchors) {
  std::vector<CurveChain> chains;
  for (size_t k = 0; k + 1 < anchors.size(); ++k) {
    const int a = anchors[k], b = anchors[k + 1];
    if (b - a < 2) continue;
    CurveChain up{a, {}}, down{b, {}};
    for (int i = a + 1; i < b; ++i) up.points.push_back(i);
    for (int i = b - 1; i > a; --i) down.points.push_back(i);
    chains.push_back(std::move(up));
    chains.push_back(std::move(down));
  }
  return chains;
}

void MergeChains(const std::vector<CurveChain>& chains,
                 const std::vector<std::vector<BoundsResult>>& chain_results,
                 BoundsOptions::Objective objective, std::vector<BoundsResult>* points) {
  if (chain_results.size() != chains.size()) {
    throw std::invalid_argument("MergeChains: one result list per chain");
  }
  std::vector<bool> set(points->size(), false);
  for (size_t c = 0; c < chains.size(); ++c) {
    if (chain_results[c].size() != chains[c].points.size()) {
      throw std::invalid_argument("MergeChains: one result per point of a chain");
    }
    for (size_t k = 0; k < chains[c].points.size(); ++k) {
      const int i = chains[c].points[k];
      if (set.at(i)) {
        MergeBounds(chain_results[c][k], objective, &(*points)[i]);
      } else {
        (*points)[i] = chain_results[c][k];
        set[i] = true;
      }
    }
  }
}

BoundCurve AssembleBoundCurve(std::vector<BoundsResult> points) {
  BoundCurve curve;
  curve.points = std::move(points);
  for (int i = 0; i < static_cast<int>(curve.points.size()); ++i) {
    const BoundsResult& b = curve.points[i];
    if (b.max.IsUsable() &&
        (curve.peak < 0 || b.max.amplitude > curve.points[curve.peak].max.amplitude)) {
      curve.peak = i;
    }
  }
  return curve;
}

ThreadStageRunner::ThreadStageRunner(int threads,
                                     std::function<void(const std::string&, int, int)> progress)
    : threads_(threads), progress_(std::move(progress)) {}

std::map<int, std::vector<BoundsResult>> ThreadStageRunner::Run(const CurveStageSpec& stage,
                                                                const std::vector<int>& units,
                                                                const Unit& unit) {
  std::map<int, std::vector<BoundsResult>> out;
  for (int u : units) out[u];  // every entry exists before the workers write theirs
  const int total = static_cast<int>(units.size());
  int done = 0;
  RunWorkUnits(
      units, WorkerThreads(threads_, total), [&](int u) { out.at(u) = unit(u); },
      [&](int) {
        if (progress_) progress_(stage.name, ++done, total);
      });
  return out;
}

namespace {

// The points dearest first by an earlier stage's wall time (the longest-processing-time rule: no
// worker starts a long point while the others run out of work; the curve does not depend on the
// order). A time that is not finite sorts last, keeping the order strict.
std::vector<int> DearestFirst(const std::vector<BoundsResult>& by) {
  const auto cost = [&](int i) { return std::isfinite(by[i].wall_s) ? by[i].wall_s : -1.0; };
  std::vector<int> order(by.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost(a) > cost(b); });
  return order;
}

// The one point of each unit of a one-point stage, into `points`.
void TakePoints(const std::map<int, std::vector<BoundsResult>>& results,
                std::vector<BoundsResult>* points) {
  for (const auto& [i, r] : results) {
    if (r.size() != 1) throw std::logic_error("ComputeBoundCurve: a point unit gave no point");
    (*points)[i] = r.front();
  }
}

// The curve's stages (design.h): one algorithm, whoever runs the units. point_progress: each
// pass-1 point's own stages, prefixed by its frequency (when they come in order).
BoundCurve CurveStages(const HarmonicBalance& system, const std::vector<double>& freqs_hz,
                       const BoundCurveOptions& options, const BalanceMaker& make_balance,
                       CurveStageRunner& runner, bool point_progress) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  for (double f : freqs_hz) {
    if (!(f > 0.0) || !std::isfinite(f)) {
      throw std::invalid_argument("ComputeBoundCurve: frequencies must be positive and finite");
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(freqs_hz.size());
  BalancePool pool(system, make_balance);
  const auto at_search = [&](const BalancePool::Lease& lease) -> const HarmonicBalance& {
    return SearchBalance(lease.get(), options.bounds);
  };
  // On the harmonic ladder every stage below runs at H = 1 and a last one refines each point at
  // H from its H = 1 optima.
  const bool ladder = UsesHarmonicLadder(system, options.bounds);
  BoundsOptions search = options.bounds;
  search.search_harmonics = 0;
  std::vector<BoundsResult> pass1(n);
  const std::vector<int> anchors = CurveAnchors(n, options.anchor_every);
  TakePoints(runner.Run({"frequencies", 0, false}, anchors,
                        [&](int i) {
                          BoundsOptions bo = search;
                          if (point_progress && options.progress) {
                            std::ostringstream label;
                            label << freqs_hz[i] << " Hz: ";
                            const std::string prefix = label.str();
                            const auto& progress = options.progress;
                            bo.progress = [&progress, prefix](const std::string& st, int d, int t) {
                              progress(prefix + st, d, t);
                            };
                          }
                          const BalancePool::Lease lease = pool.Borrow();
                          return std::vector<BoundsResult>{
                              SearchLevels(at_search(lease), freqs_hz[i], bo, options.levels)};
                        }),
             &pass1);
  const std::vector<CurveChain> chains = CurveChains(anchors);
  if (!chains.empty()) {
    std::vector<int> ids(chains.size());
    std::iota(ids.begin(), ids.end(), 0);
    const auto results = runner.Run({"continuations", 2 * n, true}, ids, [&](int c) {
      std::vector<double> f;
      for (int i : chains[c].points) f.push_back(freqs_hz[i]);
      const BalancePool::Lease lease = pool.Borrow();
      return ContinueBounds(at_search(lease), pass1[chains[c].from], f, search);
    });
    std::vector<std::vector<BoundsResult>> chain_results(chains.size());
    for (const auto& [c, r] : results) chain_results[c] = r;
    MergeChains(chains, chain_results, search.objective, &pass1);
  }
  std::vector<BoundsResult> points = pass1;
  if (options.warm_start && n > 1 && options.neighbour_pass == BoundCurveOptions::kSweeps) {
    const auto sweeps = runner.Run({"sweeps", n, true}, {0, 1}, [&](int d) {
      const BalancePool::Lease lease = pool.Borrow();
      return SweepBounds(at_search(lease), pass1, d == 0, search);
    });
    for (const auto& [d, r] : sweeps) {
      if (static_cast<int>(r.size()) != n) {
        throw std::runtime_error("ComputeBoundCurve: a sweep holds " + std::to_string(r.size()) +
                                 " points, the curve has " + std::to_string(n));
      }
    }
    points = MergeSweeps(sweeps.at(0), sweeps.at(1), pass1, search.objective);
  } else if (options.warm_start && n > 1) {
    // Dearest first, by the pass-1 time (near a resonance both passes are long).
    TakePoints(runner.Run({"neighbour starts", n, false}, DearestFirst(pass1),
                          [&](int i) {
                            const BalancePool::Lease lease = pool.Borrow();
                            return std::vector<BoundsResult>{
                                RefineFromNeighbours(at_search(lease), pass1, i, search)};
                          }),
               &points);
  }
  if (ladder) {
    const std::vector<BoundsResult> low = points;
    const int key = 2 * n + static_cast<int>(chains.size());
    TakePoints(runner.Run({"harmonic refinement", key, false}, DearestFirst(low),
                          [&](int i) {
                            const BalancePool::Lease lease = pool.Borrow();
                            return std::vector<BoundsResult>{RefineLevelsAtHarmonics(
                                lease.get(), low[i], options.bounds, options.levels)};
                          }),
               &points);
  }
  BoundCurve curve = AssembleBoundCurve(std::move(points));
  curve.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return curve;
}

}  // namespace

BoundCurve ComputeBoundCurve(
    const HarmonicBalance& system, const std::vector<double>& freqs_hz,
    const BoundCurveOptions& options,
    const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance) {
  ThreadStageRunner runner(options.threads, options.progress);
  const bool in_order = WorkerThreads(options.threads, static_cast<int>(freqs_hz.size())) == 1;
  return CurveStages(system, freqs_hz, options, make_balance, runner, in_order);
}

BoundCurve ComputeBoundCurve(const HarmonicBalance& system, const std::vector<double>& freqs_hz,
                             const BoundCurveOptions& options,
                             const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance,
                             CurveStageRunner& runner) {
  return CurveStages(system, freqs_hz, options, make_balance, runner, false);
}

std::string BoundCurve::BriefReport() const {
  std::ostringstream os;
  int usable = 0;
  for (const BoundsResult& b : points) usable += b.IsUsable();
  os << "bound curve: " << points.size() << " frequencies, " << usable << " with both bounds";
  if (HasPeak()) {
    const BoundsResult& p = points[peak];
    os << "; peak of y_max at " << p.freq_hz << " Hz: y_min " << p.min.amplitude << " m, y_max "
       << p.max.amplitude << " m, R " << p.robustness();
  } else {
    os << "; no maximum-response bound converged";
  }
  os << "; " << wall_s << " s";
  return os.str();
}

}  // namespace fricrom
