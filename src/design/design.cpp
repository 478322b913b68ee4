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
  if (!bounds.IsValid(error)) return false;
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
                              const BoundsOptions& bounds) {
  std::string error;
  if (!search.IsValid(&error) || !bounds.IsValid(&error)) throw std::invalid_argument(error);
  ResonanceResult r;
  auto ymax = [&](double f, BoundsResult* out) {
    *out = ComputeBounds(system, f, bounds);
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
    const ResonanceResult rr = FindResonance(system, options.search, bo);
    pt.freq_hz = rr.freq_hz;
    pt.bounds = rr.bounds;
    pt.bound_solves = rr.bound_solves;
  } else {
    pt.freq_hz = options.reference_freq_hz;
    pt.bounds = ComputeBounds(system, pt.freq_hz, bo);
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

NoaResult RunNoa(const BalanceFactory& factory, const NoaOptions& options,
                 const DesignProgress& progress) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const auto t0 = std::chrono::steady_clock::now();
  NoaResult res;
  const double inf = std::numeric_limits<double>::infinity();
  auto objective_of = [&](const RobustnessPoint& pt) {
    if (!pt.bounds.IsUsable()) return inf;
    if (options.objective == NoaOptions::kOneMinusR) return 1.0 - pt.robustness;
    return pt.bounds.min.loss_factor - pt.bounds.max.loss_factor;  // η2 − η1 ≥ 0
  };
  // One outer evaluation: the two inner bound problems, warm-started from the nearest
  // evaluated parameter's optimal α.
  auto evaluate = [&](double p) {
    const RobustnessPoint* nearest = nullptr;
    for (const RobustnessPoint& h : res.history) {
      if (!nearest || std::abs(h.parameter - p) < std::abs(nearest->parameter - p)) nearest = &h;
    }
    SweepOptions so = options.inner;
    const std::unique_ptr<HarmonicBalance> balance = factory(p);
    const HarmonicBalance& system = *balance;
    const BoundsOptions bo =
        WithSeeds(so.bounds, system.num_alpha(), nearest ? &nearest->bounds : nullptr);
    const RobustnessPoint pt = ComputeRobustnessPoint(system, p, so, bo);
    res.inner_solves += 2 * pt.bound_solves;
    ++res.outer_iterations;
    res.history.push_back(pt);
    if (progress) progress(res.outer_iterations, -1);
    return objective_of(res.history.back());
  };

  // 1) Global scan: independent values, on threads or through the caller's evaluator.
  const int n = options.scan_points;
  const std::vector<double> p = NoaScanValues(options);
  std::vector<double> g(n);
  {
    SweepOptions cold = options.inner;
    cold.warm_start = false;
    const std::vector<RobustnessPoint> scan =
        options.scan_evaluator ? options.scan_evaluator(p)
                               : SweepRobustness(factory, p, cold, [&](int done, int) {
                                   if (progress) progress(done, -1);
                                 });
    if (static_cast<int>(scan.size()) != n) {
      throw std::logic_error("RunNoa: the scan evaluator returned " + std::to_string(scan.size()) +
                             " points for " + std::to_string(n) + " values");
    }
    for (int i = 0; i < n; ++i) {
      res.history.push_back(scan[i]);
      res.inner_solves += 2 * scan[i].bound_solves;
      ++res.outer_iterations;
      g[i] = objective_of(scan[i]);
    }
  }
  const double gmin = *std::min_element(g.begin(), g.end());
  if (!std::isfinite(gmin)) {
    res.message = "no scan point had converged bounds";
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  // Ties at the minimum (a plateau, e.g. R = 1 over an interval): take the middle of the longest
  // run — the design with the largest margin on both sides.
  const double tie = 1e-9 + 1e-6 * std::abs(gmin);
  int run_start = -1, best_start = 0, best_len = 0;
  for (int i = 0; i <= n; ++i) {
    const bool at_min = i < n && g[i] <= gmin + tie;
    if (at_min && run_start < 0) run_start = i;
    if (!at_min && run_start >= 0) {
      if (i - run_start > best_len) {
        best_len = i - run_start;
        best_start = run_start;
      }
      run_start = -1;
    }
  }
  double p_best, g_best;
  if (best_len >= 2) {
    const double lo = p[best_start], hi = p[best_start + best_len - 1];
    p_best = 0.5 * (lo + hi);
    // A middle that is a scan value (an odd run) is known already.
    const auto known = std::find(p.begin(), p.end(), p_best);
    g_best = known != p.end() ? g[known - p.begin()] : evaluate(p_best);
    if (!(g_best <= gmin + tie)) {  // not a true plateau: keep the best scanned point
      p_best = p[best_start];
      g_best = g[best_start];
    }
    res.message = "plateau of the objective between " + std::to_string(lo) + " and " +
                  std::to_string(hi) + "; its middle is returned";
  } else {
    // 2) Golden-section refinement of the bracket around the best scan point.
    const int k = best_start;
    double a = p[std::max(k - 1, 0)], d = p[std::min(k + 1, n - 1)];
    double b = d - kGolden * (d - a), c = a + kGolden * (d - a);
    double gb = evaluate(b), gc = evaluate(c);
    while (d - a > options.parameter_tolerance) {
      if (gb <= gc) {
        d = c;
        c = b;
        gc = gb;
        b = d - kGolden * (d - a);
        gb = evaluate(b);
      } else {
        a = b;
        b = c;
        gb = gc;
        c = a + kGolden * (d - a);
        gc = evaluate(c);
      }
    }
    p_best = gb <= gc ? b : c;
    g_best = std::min(gb, gc);
    if (g[k] < g_best) {
      p_best = p[k];
      g_best = g[k];
    }
    // A unique response (objective 0) found inside a plateau narrower than the scan step:
    // bisect for both edges of the plateau and return its middle, the design with most margin.
    if (g_best <= tie) {
      auto edge = [&](double inside, double outside) {
        while (std::abs(outside - inside) > options.parameter_tolerance) {
          const double mid = 0.5 * (inside + outside);
          (evaluate(mid) <= tie ? inside : outside) = mid;
        }
        return inside;
      };
      double left = options.lower, right = options.upper;
      for (const RobustnessPoint& h : res.history) {  // nearest evaluated points off the plateau
        if (objective_of(h) > tie && h.parameter < p_best) left = std::max(left, h.parameter);
        if (objective_of(h) > tie && h.parameter > p_best) right = std::min(right, h.parameter);
      }
      const double lo = left < p_best ? edge(p_best, left) : p_best;
      const double hi = right > p_best ? edge(p_best, right) : p_best;
      const double mid = 0.5 * (lo + hi);
      const double g_mid = evaluate(mid);
      if (g_mid <= tie) {
        p_best = mid;
        g_best = g_mid;
        res.message = "plateau of the objective between " + std::to_string(lo) + " and " +
                      std::to_string(hi) + "; its middle is returned";
      }
    }
  }
  // Report the evaluation at p_best.
  for (const RobustnessPoint& h : res.history) {
    if (h.parameter == p_best) {
      res.p_opt = h.parameter;
      res.robustness = h.robustness;
      res.eta1 = h.bounds.max.loss_factor;
      res.eta2 = h.bounds.min.loss_factor;
    }
  }
  res.objective = g_best;
  res.converged = std::isfinite(g_best);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace fricrom
