#include "fricrom/design.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fricrom/work_queue.h"

namespace fricrom {
namespace {

constexpr double kGolden = 0.6180339887498949;

double Robustness(const BoundsResult& b) { return b.robustness(); }

// Seeds: the configured (or default) ones plus, for warm starts, the optima of the last point.
BoundsOptions WithSeeds(const BoundsOptions& base, int num_contacts, const BoundsResult* previous) {
  BoundsOptions o = base;
  if (o.alpha_seeds.empty()) o.alpha_seeds = DefaultAlphaSeeds(num_contacts);
  if (previous) {
    if (previous->min.IsUsable()) o.alpha_seeds.push_back(previous->min.alpha);
    if (previous->max.IsUsable()) o.alpha_seeds.push_back(previous->max.alpha);
  }
  return o;
}

}  // namespace

bool ResonanceSearchOptions::IsValid(std::string* error) const {
  if (!(lo_hz > 0.0 && hi_hz > lo_hz)) {
    *error = "ResonanceSearchOptions: need 0 < lo_hz < hi_hz";
    return false;
  }
  if (scan_points < 3 || !(tolerance_hz > 0.0)) {
    *error = "ResonanceSearchOptions: need scan_points >= 3 and tolerance_hz > 0";
    return false;
  }
  return true;
}

bool SweepOptions::IsValid(std::string* error) const {
  if (!bounds.IsValid(error) || !levels.IsValid(error)) return false;
  if (threads < 0) {
    *error = "SweepOptions.threads must be >= 0 (0: every core)";
    return false;
  }
  if (warm_start && threads != 1) {
    *error = "SweepOptions.warm_start chains the values in order: it needs threads = 1";
    return false;
  }
  if (track_peak) return search.IsValid(error);
  if (!(reference_freq_hz > 0.0)) {
    *error = "SweepOptions.reference_freq_hz must be > 0 (or set track_peak)";
    return false;
  }
  return true;
}

bool NoaOptions::IsValid(std::string* error) const {
  if (!(upper > lower) || !std::isfinite(lower) || !std::isfinite(upper)) {
    *error = "NoaOptions: need lower < upper (finite)";
    return false;
  }
  if (scan_points < 3 || !(parameter_tolerance > 0.0)) {
    *error = "NoaOptions: need scan_points >= 3 and parameter_tolerance > 0";
    return false;
  }
  return inner.IsValid(error);
}

ResonanceResult FindResonance(const HarmonicBalance& system, const ResonanceSearchOptions& search,
                              const BoundsOptions& bounds, const LevelSearchOptions& levels) {
  std::string error;
  if (!search.IsValid(&error) || !bounds.IsValid(&error) || !levels.IsValid(&error)) {
    throw std::invalid_argument(error);
  }
  ResonanceResult r;
  auto ymax = [&](double f, BoundsResult* out) {
    *out = ComputeLevelBounds(system, f, bounds, levels);
    ++r.bound_solves;
    return out->max.IsUsable() ? out->max.amplitude : -1.0;
  };
  const int n = search.scan_points;
  std::vector<double> f(n), y(n);
  std::vector<BoundsResult> b(n);
  int best = 0;
  for (int i = 0; i < n; ++i) {
    f[i] = search.lo_hz + (search.hi_hz - search.lo_hz) * i / (n - 1);
    y[i] = ymax(f[i], &b[i]);
    if (y[i] > y[best]) best = i;
  }
  if (!(y[best] >= 0.0)) {  // no maximum converged anywhere: there is no peak to report
    r.freq_hz = std::numeric_limits<double>::quiet_NaN();
    r.bounds = b[best];
    return r;
  }
  // Golden-section refinement of the bracket around the best scan point.
  double a = f[std::max(best - 1, 0)], d = f[std::min(best + 1, n - 1)];
  double bx = d - kGolden * (d - a), cx = a + kGolden * (d - a);
  BoundsResult rb, rc;
  double yb = ymax(bx, &rb), yc = ymax(cx, &rc);
  while (d - a > search.tolerance_hz) {
    if (yb >= yc) {
      d = cx;
      cx = bx;
      yc = yb;
      rc = rb;
      bx = d - kGolden * (d - a);
      yb = ymax(bx, &rb);
    } else {
      a = bx;
      bx = cx;
      yb = yc;
      rb = rc;
      cx = a + kGolden * (d - a);
      yc = ymax(cx, &rc);
    }
  }
  r.freq_hz = yb >= yc ? bx : cx;
  r.bounds = yb >= yc ? rb : rc;
  if (y[best] > std::max(yb, yc)) {  // the scan point itself is higher (flat top)
    r.freq_hz = f[best];
    r.bounds = b[best];
  }
  return r;
}

namespace {

RobustnessPoint ComputeRobustnessPoint(const HarmonicBalance& system, double p,
                                       const SweepOptions& options, const BoundsOptions& bo) {
  RobustnessPoint pt;
  pt.parameter = p;
  if (options.track_peak) {
    const ResonanceResult rr = FindResonance(system, options.search, bo, options.levels);
    pt.freq_hz = rr.freq_hz;
    pt.bounds = rr.bounds;
    pt.bound_solves = rr.bound_solves;
  } else {
    pt.freq_hz = options.reference_freq_hz;
    pt.bounds = ComputeLevelBounds(system, pt.freq_hz, bo, options.levels);
    pt.bound_solves = 1;
  }
  pt.robustness = Robustness(pt.bounds);
  return pt;
}

}  // namespace

std::vector<RobustnessPoint> SweepRobustness(const BalanceFactory& factory,
                                             const std::vector<double>& values,
                                             const SweepOptions& options,
                                             const DesignProgress& progress,
                                             const SweepPointDone& point_done,
                                             const std::vector<bool>& finished) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const int n = static_cast<int>(values.size());
  if (!finished.empty() && static_cast<int>(finished.size()) != n) {
    throw std::invalid_argument("SweepRobustness: `finished` must have one entry per value");
  }
  std::vector<RobustnessPoint> out(n);
  std::vector<int> pending;
  for (int i = 0; i < n; ++i) {
    if (finished.empty() || !finished[i]) pending.push_back(i);
  }
  int done = n - static_cast<int>(pending.size());
  const RobustnessPoint* previous = nullptr;  // warm start: serial, in order (IsValid)
  RunWorkUnits(
      pending, options.threads,
      [&](int i) {
        const std::unique_ptr<HarmonicBalance> balance = factory(values[i]);
        const BoundsOptions bo =
            WithSeeds(options.bounds, balance->num_alpha(),
                      options.warm_start && previous ? &previous->bounds : nullptr);
        out[i] = ComputeRobustnessPoint(*balance, values[i], options, bo);
      },
      [&](int i) {
        previous = &out[i];
        if (point_done) point_done(i, out[i]);
        if (progress) progress(++done, n);
      });
  return out;
}

std::string NoaResult::BriefReport() const {
  std::ostringstream s;
  s << "NOA: p_opt = " << p_opt << ", R = " << robustness << ", eta1 = " << eta1
    << ", eta2 = " << eta2 << " (" << outer_iterations << " outer iterations, " << inner_solves
    << " inner bound solves, " << wall_s << " s)" << (converged ? "" : " NOT CONVERGED");
  if (!message.empty()) s << " [" << message << "]";
  return s.str();
}

std::vector<double> NoaScanValues(const NoaOptions& options) {
  const int n = options.scan_points;
  std::vector<double> p(n);
  for (int i = 0; i < n; ++i) p[i] = options.lower + (options.upper - options.lower) * i / (n - 1);
  return p;
}

namespace {

// The nested optimisation: a global scan of the parameter, then a golden-section refinement of
// the best bracket, or the middle of a plateau of optimal values (the design with most margin).
class NoaSolver {
 public:
  NoaSolver(const BalanceFactory& factory, const NoaOptions& options,
            const DesignProgress& progress)
      : factory_(factory), options_(options), progress_(progress) {}

  NoaResult Solve() {
    const auto t0 = std::chrono::steady_clock::now();
    Scan();
    const double gmin = *std::min_element(g_.begin(), g_.end());
    if (!std::isfinite(gmin)) {
      res_.message = "no scan point had converged bounds";
    } else {
      tie_ = 1e-9 + 1e-6 * std::abs(gmin);
      const auto [best_start, best_len] = LongestRunAtMinimum(gmin);
      const auto [p_best, g_best] =
          best_len >= 2 ? PlateauOfScan(best_start, best_len, gmin) : Refine(best_start);
      Report(p_best, g_best);
    }
    res_.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return std::move(res_);
  }

 private:
  double ObjectiveOf(const RobustnessPoint& pt) const {
    if (!pt.bounds.IsUsable()) return std::numeric_limits<double>::infinity();
    if (options_.objective == NoaOptions::kOneMinusR) return 1.0 - pt.robustness;
    return pt.bounds.min.loss_factor - pt.bounds.max.loss_factor;  // η2 − η1 ≥ 0
  }

  // One outer evaluation: the two inner bound problems, warm-started from the nearest
  // evaluated parameter's optimal α.
  double Evaluate(double p) {
    const RobustnessPoint* nearest = nullptr;
    for (const RobustnessPoint& h : res_.history) {
      if (!nearest || std::abs(h.parameter - p) < std::abs(nearest->parameter - p)) nearest = &h;
    }
    const std::unique_ptr<HarmonicBalance> balance = factory_(p);
    const BoundsOptions bo = WithSeeds(options_.inner.bounds, balance->num_alpha(),
                                       nearest ? &nearest->bounds : nullptr);
    const RobustnessPoint pt = ComputeRobustnessPoint(*balance, p, options_.inner, bo);
    res_.inner_solves += 2 * pt.bound_solves;
    ++res_.outer_iterations;
    res_.history.push_back(pt);
    if (progress_) progress_(res_.outer_iterations, -1);
    return ObjectiveOf(res_.history.back());
  }

  // 1) Global scan: independent values, on threads or through the caller's evaluator.
  void Scan() {
    p_ = NoaScanValues(options_);
    const int n = static_cast<int>(p_.size());
    SweepOptions cold = options_.inner;
    cold.warm_start = false;
    const std::vector<RobustnessPoint> scan =
        options_.scan_evaluator ? options_.scan_evaluator(p_)
                                : SweepRobustness(factory_, p_, cold, [&](int done, int) {
                                    if (progress_) progress_(done, -1);
                                  });
    if (static_cast<int>(scan.size()) != n) {
      throw std::logic_error("RunNoa: the scan evaluator returned " + std::to_string(scan.size()) +
                             " points for " + std::to_string(n) + " values");
    }
    g_.resize(n);
    for (int i = 0; i < n; ++i) {
      res_.history.push_back(scan[i]);
      res_.inner_solves += 2 * scan[i].bound_solves;
      ++res_.outer_iterations;
      g_[i] = ObjectiveOf(scan[i]);
    }
  }

  // Ties at the minimum (a plateau, e.g. R = 1 over an interval): the longest run of scan
  // values at the minimum, as (first index, length).
  std::pair<int, int> LongestRunAtMinimum(double gmin) const {
    const int n = static_cast<int>(g_.size());
    int run_start = -1, best_start = 0, best_len = 0;
    for (int i = 0; i <= n; ++i) {
      const bool at_min = i < n && g_[i] <= gmin + tie_;
      if (at_min && run_start < 0) run_start = i;
      if (!at_min && run_start >= 0) {
        if (i - run_start > best_len) {
          best_len = i - run_start;
          best_start = run_start;
        }
        run_start = -1;
      }
    }
    return {best_start, best_len};
  }

  // The middle of the longest run of optimal scan values: the largest margin on both sides.
  std::pair<double, double> PlateauOfScan(int best_start, int best_len, double gmin) {
    const double lo = p_[best_start], hi = p_[best_start + best_len - 1];
    double p_best = 0.5 * (lo + hi);
    // A middle that is a scan value (an odd run) is known already.
    const auto known = std::find(p_.begin(), p_.end(), p_best);
    double g_best = known != p_.end() ? g_[known - p_.begin()] : Evaluate(p_best);
    if (!(g_best <= gmin + tie_)) {  // not a true plateau: keep the best scanned point
      p_best = p_[best_start];
      g_best = g_[best_start];
    }
    res_.message = "plateau of the objective between " + std::to_string(lo) + " and " +
                   std::to_string(hi) + "; its middle is returned";
    return {p_best, g_best};
  }

  // 2) Golden-section refinement of the bracket around the best scan point k.
  std::pair<double, double> Refine(int k) {
    const int n = static_cast<int>(p_.size());
    double a = p_[std::max(k - 1, 0)], d = p_[std::min(k + 1, n - 1)];
    double b = d - kGolden * (d - a), c = a + kGolden * (d - a);
    double gb = Evaluate(b), gc = Evaluate(c);
    while (d - a > options_.parameter_tolerance) {
      if (gb <= gc) {
        d = c;
        c = b;
        gc = gb;
        b = d - kGolden * (d - a);
        gb = Evaluate(b);
      } else {
        a = b;
        b = c;
        gb = gc;
        c = a + kGolden * (d - a);
        gc = Evaluate(c);
      }
    }
    double p_best = gb <= gc ? b : c;
    double g_best = std::min(gb, gc);
    if (g_[k] < g_best) {
      p_best = p_[k];
      g_best = g_[k];
    }
    if (g_best <= tie_) NarrowPlateau(&p_best, &g_best);
    return {p_best, g_best};
  }

  // A unique response (objective 0) found inside a plateau narrower than the scan step:
  // bisect for both edges of the plateau and return its middle, the design with most margin.
  void NarrowPlateau(double* p_best, double* g_best) {
    auto edge = [&](double inside, double outside) {
      while (std::abs(outside - inside) > options_.parameter_tolerance) {
        const double mid = 0.5 * (inside + outside);
        (Evaluate(mid) <= tie_ ? inside : outside) = mid;
      }
      return inside;
    };
    double left = options_.lower, right = options_.upper;
    for (const RobustnessPoint& h : res_.history) {  // nearest evaluated points off the plateau
      if (ObjectiveOf(h) > tie_ && h.parameter < *p_best) left = std::max(left, h.parameter);
      if (ObjectiveOf(h) > tie_ && h.parameter > *p_best) right = std::min(right, h.parameter);
    }
    const double lo = left < *p_best ? edge(*p_best, left) : *p_best;
    const double hi = right > *p_best ? edge(*p_best, right) : *p_best;
    const double mid = 0.5 * (lo + hi);
    const double g_mid = Evaluate(mid);
    if (g_mid <= tie_) {
      *p_best = mid;
      *g_best = g_mid;
      res_.message = "plateau of the objective between " + std::to_string(lo) + " and " +
                     std::to_string(hi) + "; its middle is returned";
    }
  }

  // Report the evaluation at p_best.
  void Report(double p_best, double g_best) {
    for (const RobustnessPoint& h : res_.history) {
      if (h.parameter == p_best) {
        res_.p_opt = h.parameter;
        res_.robustness = h.robustness;
        res_.eta1 = h.bounds.max.loss_factor;
        res_.eta2 = h.bounds.min.loss_factor;
      }
    }
    res_.objective = g_best;
    res_.converged = std::isfinite(g_best);
  }

  const BalanceFactory& factory_;
  const NoaOptions& options_;
  const DesignProgress& progress_;
  NoaResult res_;
  std::vector<double> p_;  // scan values
  std::vector<double> g_;  // objective at the scan values
  double tie_ = 0.0;       // objective values within tie_ of the minimum count as optimal
};

}  // namespace

NoaResult RunNoa(const BalanceFactory& factory, const NoaOptions& options,
                 const DesignProgress& progress) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  return NoaSolver(factory, options, progress).Solve();
}

}  // namespace fricrom
