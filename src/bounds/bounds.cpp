// Response bounds: the driver over α seeds (starts, both directions, ranking, spread), options,
// statuses and reports. The runs themselves: reduced_bounds.cpp (default) and ipopt_bounds.cpp.
#include "fricrom/bounds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bound_runs.h"
#include "fricrom/units.h"
#include "optimise_bounds.h"

namespace fricrom {
namespace {

using bounds_detail::Describe;
using bounds_detail::IpoptBounds;
using bounds_detail::RankValue;
using bounds_detail::RunReduced;
using bounds_detail::RunSetup;
using bounds_detail::StartIsKktPoint;
using bounds_detail::StartSolution;

// Up to kListed entries are listed; longer vectors (FE interfaces) are summarised.
constexpr int kListed = 12;

std::string FormatVector(const Eigen::VectorXd& v) {
  std::ostringstream os;
  if (v.size() > kListed) {
    // α lies in [−1, 1]: below 1e-12 a summary value is round-off of a zero (2.8e-33 said "0").
    const auto shown = [](double a) { return std::abs(a) < 1e-12 ? 0.0 : a; };
    os << v.size() << " values in [" << shown(v.minCoeff()) << ", " << shown(v.maxCoeff())
       << "], mean " << shown(v.mean());
    return os.str();
  }
  os << "[";
  for (int i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << "]";
  return os.str();
}

// The regimes in order, or for many contacts how many are in each.
std::string FormatRegimes(const std::vector<ContactRegime>& regimes) {
  std::ostringstream os;
  if (static_cast<int>(regimes.size()) <= kListed) {
    for (size_t i = 0; i < regimes.size(); ++i) os << (i ? ", " : "") << ToString(regimes[i]);
    return os.str();
  }
  const ContactRegime all[] = {ContactRegime::kFullStick, ContactRegime::kStickSlip,
                               ContactRegime::kFullSlip, ContactRegime::kStickSlipLiftOff,
                               ContactRegime::kFullLiftOff};
  bool first = true;
  for (ContactRegime r : all) {
    const auto n = std::count(regimes.begin(), regimes.end(), r);
    if (n == 0) continue;
    os << (first ? "" : ", ") << n << " " << ToString(r);
    first = false;
  }
  return os.str();
}

}  // namespace

bool BoundsOptions::IsValid(std::string* error) const {
  if (!(negligible_minimum >= 0.0 && negligible_minimum < 1.0)) {
    *error = "BoundsOptions.negligible_minimum must lie in [0, 1), got " +
             std::to_string(negligible_minimum);
    return false;
  }
  if (!(minimum_stop_m >= 0.0 && std::isfinite(minimum_stop_m))) {
    *error = "BoundsOptions.minimum_stop_m must be finite and >= 0, got " +
             std::to_string(minimum_stop_m);
    return false;
  }
  if (line_search_memory < 1 || line_search_memory > 100) {
    *error = "BoundsOptions.line_search_memory must lie in [1, 100], got " +
             std::to_string(line_search_memory);
    return false;
  }
  if (max_iterations < 1) {
    *error = "BoundsOptions.max_iterations must be >= 1, got " + std::to_string(max_iterations);
    return false;
  }
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"stationary_change", stationary_change},
        {"refinement_stationary_change", refinement_stationary_change}}) {
    if (!(value > 0.0 && value < 1.0)) {
      *error = std::string("BoundsOptions.") + name + " must lie in (0, 1), got " +
               std::to_string(value);
      return false;
    }
  }
  if (!(stall_change >= 0.0 && stall_change < 1.0)) {
    *error = "BoundsOptions.stall_change must lie in [0, 1), got " + std::to_string(stall_change);
    return false;
  }
  if (maximum_bfgs_memory < 0 || maximum_bfgs_memory > 100) {
    *error = "BoundsOptions.maximum_bfgs_memory must lie in [0, 100], got " +
             std::to_string(maximum_bfgs_memory);
    return false;
  }
  if (stall_window < 0) {
    *error = "BoundsOptions.stall_window must be >= 0, got " + std::to_string(stall_window);
    return false;
  }
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    *error = "BoundsOptions.tolerance must be positive and finite";
    return false;
  }
  if (objective != kAmplitude && objective != kLossFactor) {
    *error = "BoundsOptions.objective must be kAmplitude or kLossFactor";
    return false;
  }
  if (method != kFullSpace && method != kReducedSpace && method != kBoth) {
    *error = "BoundsOptions.method must be kFullSpace, kReducedSpace or kBoth";
    return false;
  }
  if (random_seeds < 0 || random_seeds > 100000) {
    *error =
        "BoundsOptions.random_seeds must lie in [0, 100000], got " + std::to_string(random_seeds);
    return false;
  }
  for (int g : seed_groups) {
    if (g < 0) {
      *error = "BoundsOptions.seed_groups has a negative group " + std::to_string(g);
      return false;
    }
  }
  if (search_harmonics != 0 && search_harmonics != 1) {
    *error = "BoundsOptions.search_harmonics must be 0 (the system's H) or 1, got " +
             std::to_string(search_harmonics);
    return false;
  }
  if (check_samples < 0) {
    *error = "BoundsOptions.check_samples must be >= 0, got " + std::to_string(check_samples);
    return false;
  }
  for (size_t i = 0; i < alpha_seeds.size(); ++i) {
    const Eigen::VectorXd& a = alpha_seeds[i];
    if (a.size() != alpha_seeds[0].size()) {
      *error = "BoundsOptions.alpha_seeds[" + std::to_string(i) + "] has " +
               std::to_string(a.size()) + " entries, alpha_seeds[0] has " +
               std::to_string(alpha_seeds[0].size());
      return false;
    }
    for (int c = 0; c < a.size(); ++c) {
      if (!(std::abs(a[c]) <= 1.0)) {
        std::ostringstream os;
        os << "BoundsOptions.alpha_seeds[" << i << "][" << c << "] must lie in [-1, 1], got "
           << a[c];
        *error = os.str();
        return false;
      }
    }
  }
  return true;
}

std::vector<Eigen::VectorXd> DefaultAlphaSeeds(int num_contacts) {
  if (num_contacts < 0) throw std::invalid_argument("DefaultAlphaSeeds: num_contacts < 0");
  const int n = num_contacts;
  std::vector<Eigen::VectorXd> seeds;
  auto add = [&seeds](const Eigen::VectorXd& a) {
    for (const Eigen::VectorXd& s : seeds) {
      if (s == a) return;
    }
    seeds.push_back(a);
  };
  Eigen::VectorXd alt(n);
  for (int c = 0; c < n; ++c) alt[c] = (c % 2 == 0) ? 1.0 : -1.0;
  add(Eigen::VectorXd::Zero(n));
  add(Eigen::VectorXd::Constant(n, 0.5));
  add(Eigen::VectorXd::Constant(n, -0.5));
  add(alt);
  add(-alt);
  return seeds;
}

std::vector<Eigen::VectorXd> AlphaSeeds(int num_alpha, const BoundsOptions& options,
                                        SeedCounts* counts) {
  const int n = num_alpha;
  std::vector<Eigen::VectorXd> seeds;
  auto add = [&seeds](const Eigen::VectorXd& a) {
    for (const Eigen::VectorXd& s : seeds) {
      if (s == a) return 0;
    }
    seeds.push_back(a);
    return 1;
  };
  SeedCounts c;
  for (const Eigen::VectorXd& a :
       options.alpha_seeds.empty() ? DefaultAlphaSeeds(n) : options.alpha_seeds) {
    c.base += add(a);
  }
  if (!options.seed_groups.empty()) {
    if (static_cast<int>(options.seed_groups.size()) != n) {
      throw std::invalid_argument("AlphaSeeds: seed_groups has " +
                                  std::to_string(options.seed_groups.size()) + " entries for " +
                                  std::to_string(n) + " alpha");
    }
    const int groups = *std::max_element(options.seed_groups.begin(), options.seed_groups.end());
    for (int g = 0; g <= groups; ++g) {
      Eigen::VectorXd a(n);
      for (int i = 0; i < n; ++i) a[i] = options.seed_groups[i] == g ? 1.0 : -1.0;
      c.group_patterns += add(a);
      c.group_patterns += add(-a);
    }
  }
  // A stream of its own, so that adding random seeds leaves the check samples unchanged.
  std::mt19937 rng(options.sample_seed + 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int r = 0; r < options.random_seeds; ++r) {
    Eigen::VectorXd a(n);
    for (int i = 0; i < n; ++i) a[i] = uniform(rng);
    c.random += add(a);
  }
  if (counts) *counts = c;
  return seeds;
}

std::string ToString(BoundsOptions::Method method) {
  switch (method) {
    case BoundsOptions::kFullSpace:
      return "ipopt";
    case BoundsOptions::kReducedSpace:
      return "reduced";
    case BoundsOptions::kBoth:
      return "both";
  }
  return "unknown";
}

bool FromString(const std::string& name, BoundsOptions::Method* method) {
  for (BoundsOptions::Method m :
       {BoundsOptions::kFullSpace, BoundsOptions::kReducedSpace, BoundsOptions::kBoth}) {
    if (ToString(m) == name) {
      *method = m;
      return true;
    }
  }
  return false;
}

std::string ToString(BoundStatus status) {
  switch (status) {
    case BoundStatus::kConverged:
      return "converged";
    case BoundStatus::kMaxIterations:
      return "max-iterations";
    case BoundStatus::kInfeasible:
      return "infeasible";
    case BoundStatus::kAbandoned:
      return "abandoned";
    case BoundStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

double BoundsResult::robustness() const {
  if (!IsUsable() || !(max.amplitude > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 1.0 - (max.amplitude - min.amplitude) / max.amplitude;
}

double StableBounds::robustness() const {
  if (!(min.amplitude >= 0.0) || !(max.amplitude > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return 1.0 - (max.amplitude - min.amplitude) / max.amplitude;
}

std::string BoundsResult::BriefReport() const {
  std::ostringstream os;
  auto one = [&os](const char* name, const BoundSolution& s) {
    os << "  " << name << ": " << ToString(s.status);
    if (s.seed >= 0) {
      os << " (seed " << s.seed << ", " << s.iterations << " it.), amplitude " << s.amplitude
         << " m, eta " << s.loss_factor << ", |R|/scale " << s.residual << ", alpha "
         << FormatVector(s.alpha) << ", regimes [";
      os << FormatRegimes(s.regimes) << "]";
    }
    os << " -- " << s.message << "\n";
  };
  os << "Response bounds at " << freq_hz << " Hz: robustness " << robustness() << "\n";
  one("min", min);
  one("max", max);
  os << "  seeds: " << seeds_tried << " tried, " << seeds_converged << " fully converged, "
     << start_failures << " start failures, " << min_failures << " failed min runs, "
     << max_failures << " failed max runs, " << runs_abandoned << " runs abandoned, "
     << optimizer_runs
     << " optimiser runs (the others started at a KKT point); spread of the optimum over "
     << "seeds: min " << spread_min << ", max " << spread_max
     << "; sample check: " << samples_checked << " samples (" << samples_failed << " failed), "
     << improved_by_samples << " bounds improved";
  if (search_harmonics == 1 && harmonics > 1) {
    os << "; searched at H = 1, refined at H = " << harmonics << " (" << refinement_fallbacks
       << " bounds searched again at H = " << harmonics << ")";
  }
  return os.str();
}

namespace {

// A seed's feasible start and what the first-order check said of it, per direction.
struct SeedStart {
  bool ok = false;
  Eigen::VectorXd x0;
  double objective = 0.0;        // φ at the start: a1² + b1², or η
  Eigen::VectorXd alpha0;        // the α of x0: the seed's, or short of it on the α homotopy
  double objective_scale = 1.0;  // the runs' objectives are divided by this
  bool kkt[2] = {false, false};  // [min response, max response]: start is a KKT point
  // The KKT check's gradient, kept for the runs (released once they are done).
  bounds_detail::StartGradient gradient;
};

// Minimum response: min a², or max η; maximum response: max a², or min η.
double RunSign(const BoundsOptions& options, bool maximise_response) {
  return (maximise_response == (options.objective == BoundsOptions::kAmplitude)) ? -1.0 : 1.0;
}

// Phase 1: each seed's start (falling back on the earlier seeds' starts) and its KKT checks.
std::vector<SeedStart> SeedStarts(const HarmonicBalance& system, double freq_hz,
                                  const BoundsOptions& options,
                                  const std::vector<Eigen::VectorXd>& seeds,
                                  const std::vector<Eigen::VectorXd>& known_x,
                                  const std::vector<bool>& short_starts, RunSetup setup,
                                  BoundsResult* result) {
  const double omega = RadPerS(freq_hz);
  std::vector<SeedStart> out(seeds.size());
  std::vector<Eigen::VectorXd> starts;
  for (size_t s = 0; s < seeds.size(); ++s) {
    SeedStart& st = out[s];
    const Eigen::VectorXd known = s < known_x.size() ? known_x[s] : Eigen::VectorXd();
    st.alpha0 = seeds[s];
    const bool may_fall_short = s < short_starts.size() && short_starts[s];
    if (!StartSolution(system, freq_hz, seeds[s], starts, &st.x0, known,
                       may_fall_short ? &st.alpha0 : nullptr)) {
      ++result->start_failures;
      continue;
    }
    st.ok = true;
    starts.push_back(st.x0);
    if (options.objective == BoundsOptions::kAmplitude) {
      const double y0 = system.Amplitude(st.x0);
      st.objective = y0 * y0;
      st.objective_scale = std::max(y0 * y0, 1e-300);
    } else {
      st.objective = system.Energies(st.x0, omega, st.alpha0).loss_factor();
      st.objective_scale = std::max(std::abs(st.objective), 1e-6);
    }
    setup.objective_scale = st.objective_scale;
    if (system.num_alpha() == 0) {
      st.kkt[0] = st.kkt[1] = true;
    } else {
      const std::array<bool, 2> kkt =
          StartIsKktPoint(setup, st.x0, st.alpha0, options.tolerance,
                          {RunSign(options, false), RunSign(options, true)}, &st.gradient);
      st.kkt[0] = kkt[0];
      st.kkt[1] = kkt[1];
      if (kkt[0] && kkt[1]) st.gradient = {};
    }
  }
  return out;
}

// The best φ over the starts accepted as KKT points in one direction and the bound the caller
// holds (`held`, NaN if none; NaN if neither): the value a run in that direction must beat to
// matter.
double Incumbent(const std::vector<SeedStart>& starts, const BoundsOptions& options, int dir,
                 double held) {
  const double sign = RunSign(options, dir == 1);
  double best = held;
  for (const SeedStart& st : starts) {
    if (!st.ok || !st.kkt[dir]) continue;
    if (!std::isfinite(best) || sign * st.objective < sign * best) best = st.objective;
  }
  return best;
}

// A feasible point beats a bound only by more than this relative margin (solver noise).
constexpr double kBeyondMargin = 1e-7;

// Whether `a` lies beyond `b` in the run's direction by more than kBeyondMargin.
bool Beyond(const BoundSolution& a, const BoundSolution& b, BoundsOptions::Objective objective,
            bool maximise_response) {
  return bounds_detail::LiesBeyond(a, b, objective, maximise_response, kBeyondMargin);
}

// Folds the runs into the bounds, in order: the best converged run per direction, the spread of
// the converged optima, failures and abandoned runs counted. A run stopped at its iteration limit
// does not converge, but its last iterate satisfies R = 0 (the reduced-space runs keep every
// iterate feasible): where it goes beyond the converged runs it becomes the bound (50-point FE
// curve: y_max 5-7 % higher at 1074.5 and 1123.5 Hz, y_min 2x lower at 1084.7 Hz).
struct RunTally {
  BoundsOptions::Objective objective = BoundsOptions::kAmplitude;
  bool have[2] = {false, false};
  double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 0.0};
  BoundSolution unfinished[2];  // the most extreme feasible last iterate of an unfinished run

  // False unless `sol` converged.
  bool Add(BoundSolution sol, bool maximise_response, BoundsResult* result) {
    const int d = maximise_response ? 1 : 0;
    BoundSolution& best = maximise_response ? result->max : result->min;
    if (sol.status == BoundStatus::kMaxIterations && sol.residual <= bounds_detail::kFeasibility &&
        std::isfinite(RankValue(sol, objective)) &&
        (unfinished[d].x.size() == 0 || Beyond(sol, unfinished[d], objective, maximise_response))) {
      unfinished[d] = sol;
    }
    if (!sol.IsUsable()) {
      if (sol.status == BoundStatus::kAbandoned) {
        ++result->runs_abandoned;  // dominated by a KKT start: `best` is already usable
      } else {
        ++(maximise_response ? result->max_failures : result->min_failures);
        if (!have[d]) best = std::move(sol);  // keep a failure on record until a run converges
      }
      return false;
    }
    const double v = RankValue(sol, objective);
    const double obj = objective == BoundsOptions::kAmplitude ? sol.amplitude : sol.loss_factor;
    lo[d] = have[d] ? std::min(lo[d], obj) : obj;
    hi[d] = have[d] ? std::max(hi[d], obj) : obj;
    const double v_best = have[d] ? RankValue(best, objective) : 0.0;
    if (!have[d] || (maximise_response ? v > v_best : v < v_best)) best = std::move(sol);
    have[d] = true;
    return true;
  }

  void Finish(BoundsResult* result) {
    for (int d = 0; d < 2; ++d) {
      BoundSolution& best = d == 1 ? result->max : result->min;
      if (unfinished[d].x.size() == 0) continue;
      if (!have[d]) {
        // Alone an unfinished run is no bound here, but its point stays on record (the failure
        // kept): a caller that holds a bound already may widen it (UsableUnfinished).
        best = unfinished[d];
        continue;
      }
      if (!Beyond(unfinished[d], best, objective, d == 1)) continue;
      const double obj = objective == BoundsOptions::kAmplitude ? unfinished[d].amplitude
                                                                : unfinished[d].loss_factor;
      lo[d] = std::min(lo[d], obj);
      hi[d] = std::max(hi[d], obj);
      best = unfinished[d];
      bounds_detail::MarkUnfinishedAsBound(&best);
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    result->spread_min = have[0] ? hi[0] - lo[0] : nan;
    result->spread_max = have[1] ? hi[1] - lo[1] : nan;
  }
};

}  // namespace

BoundsResult OptimiseBounds(const HarmonicBalance& system, double freq_hz,
                            const BoundsOptions& options, const std::vector<Eigen::VectorXd>& seeds,
                            const std::vector<Eigen::VectorXd>& known_x,
                            const std::vector<int>& directions,
                            const std::vector<bool>& short_starts, std::array<double, 2> held) {
  const int nc = system.num_alpha();
  if (seeds.empty() || seeds[0].size() != nc) {
    throw std::invalid_argument("ComputeBounds: alpha seeds have " +
                                std::to_string(seeds.empty() ? 0 : seeds[0].size()) +
                                " entries, the system has " + std::to_string(nc) + " contacts");
  }
  const double omega = RadPerS(freq_hz);

  BoundsResult result;
  result.freq_hz = freq_hz;
  result.seeds_tried = static_cast<int>(seeds.size());
  result.min.message = result.max.message = "no seed produced a starting solution";

  // Scaling: per harmonic-coefficient block of the full-stick solution.
  // Unknowns are harmonic-major: 2H+1 equal blocks (HarmonicBalance).
  const int nh = 2 * system.harmonics() + 1, n = system.num_unknowns() / nh;
  const Eigen::VectorXd x_stick = system.StickLinearSolution(omega);
  const double x_ref = std::max(x_stick.lpNorm<Eigen::Infinity>(), 1e-300);
  RunSetup setup;
  setup.system = &system;
  setup.omega = omega;
  setup.objective = options.objective;
  setup.residual_scale = system.ResidualScale();
  setup.stall_tolerance = options.tolerance;
  setup.line_search_memory = options.line_search_memory;
  setup.stationary_change = options.stationary_change;
  setup.stall_change = options.stall_change;
  setup.stall_window = options.stall_window;
  setup.gauss_newton =
      options.gauss_newton_minimum && options.objective == BoundsOptions::kAmplitude;
  setup.x_scale.resize(system.num_unknowns());
  for (int j = 0; j < nh; ++j) {
    const double block = x_stick.segment(j * n, n).lpNorm<Eigen::Infinity>();
    setup.x_scale.segment(j * n, n).setConstant(std::max(block, 1e-6 * x_ref));
  }

  std::vector<SeedStart> st =
      SeedStarts(system, freq_hz, options, seeds, known_x, short_starts, setup, &result);
  // Phase 2: the runs. Each is told what phase 1 found (the KKT starts' best) and the bound the
  // caller holds, and with dominated_by_earlier_runs the best bound of the runs before it.
  double incumbent[2] = {Incumbent(st, options, 0, held[0]), Incumbent(st, options, 1, held[1])};
  IpoptBounds ipopt(system, options);
  RunTally tally;
  tally.objective = options.objective;
  const int num_seeds = static_cast<int>(seeds.size());
  for (int s = 0; s < num_seeds; ++s) {
    if (options.progress && s > 0) options.progress("seeds", s, num_seeds);
    if (!st[s].ok) continue;
    const Eigen::VectorXd& x0 = st[s].x0;
    setup.objective_scale = st[s].objective_scale;
    bool both = true;
    const int mask = static_cast<size_t>(s) < directions.size() ? directions[s] : 3;
    for (int dir = 0; dir < 2; ++dir) {
      if ((mask & (1 << dir)) == 0) continue;
      const bool maximise_response = dir == 1;
      setup.sign = RunSign(options, maximise_response);
      setup.bfgs_memory = maximise_response ? options.maximum_bfgs_memory : 0;
      setup.incumbent = options.stop_dominated_runs && std::isfinite(incumbent[dir])
                            ? setup.sign * incumbent[dir] / setup.objective_scale
                            : std::numeric_limits<double>::quiet_NaN();
      const bool stops = !maximise_response && options.objective == BoundsOptions::kAmplitude &&
                         options.minimum_stop_m > 0.0;
      setup.stop_below =
          stops ? options.minimum_stop_m * options.minimum_stop_m / setup.objective_scale
                : -std::numeric_limits<double>::infinity();
      BoundSolution sol;
      if (st[s].kkt[dir]) {
        sol.x = x0;
        sol.alpha = st[s].alpha0;
        sol.seed = s;
        sol.status = BoundStatus::kConverged;
        sol.stationary = true;
        sol.message = nc == 0 ? "no contacts: unique response"
                              : "the start is already a KKT point (zero reduced gradient in alpha)";
        Describe(system, omega, &sol);
      } else {
        const bool reduced = options.method != BoundsOptions::kFullSpace;
        const bool full = options.method != BoundsOptions::kReducedSpace;
        if (reduced) {
          sol =
              RunReduced(setup, x0, st[s].alpha0, s, options.max_iterations, 1e-7, &st[s].gradient);
        }
        if (full) {
          BoundSolution other = ipopt.Run(setup, x0, st[s].alpha0, s);
          const double sign = maximise_response ? 1.0 : -1.0;  // larger is better after the sign
          if (!reduced || !sol.IsUsable() ||
              (other.IsUsable() && sign * RankValue(other, options.objective) >
                                       sign * RankValue(sol, options.objective))) {
            sol = std::move(other);
          }
        }
        result.optimizer_runs += (reduced ? 1 : 0) + (full ? 1 : 0);
      }
      if (!tally.Add(std::move(sol), maximise_response, &result)) both = false;
      if (options.dominated_by_earlier_runs) {
        // The later runs must beat the best bound so far as well (BoundsOptions).
        const BoundSolution& b = maximise_response ? result.max : result.min;
        const double phi = options.objective == BoundsOptions::kAmplitude
                               ? b.amplitude * b.amplitude
                               : b.loss_factor;
        if (b.IsUsable() && std::isfinite(phi) &&
            (!std::isfinite(incumbent[dir]) || setup.sign * phi < setup.sign * incumbent[dir])) {
          incumbent[dir] = phi;
        }
      }
    }
    if (both) ++result.seeds_converged;
    st[s].gradient = {};  // its LU: up to 20 MB at H = 3 on the FE cascade
  }
  if (options.progress) options.progress("seeds", num_seeds, num_seeds);
  tally.Finish(&result);
  for (BoundSolution* b : {&result.min, &result.max}) {
    if (b->IsUsable()) continue;  // a failed bound is never a number
    b->amplitude = b->loss_factor = std::numeric_limits<double>::quiet_NaN();
  }
  return result;
}

void MergeBounds(const BoundsResult& other, BoundsOptions::Objective objective,
                 BoundsResult* into) {
  if (other.freq_hz != into->freq_hz) {
    throw std::invalid_argument("MergeBounds: the two results are at different frequencies");
  }
  const bool amp = objective == BoundsOptions::kAmplitude;
  const auto widen = [&](const BoundSolution& a, const BoundSolution& b, double* spread) {
    // Each side keeps only its best value and spread, so the merged spread is the largest
    // difference these show (a lower estimate of the spread over every run of both).
    if (!a.IsUsable() || !b.IsUsable()) return;
    const double va = amp ? a.amplitude : a.loss_factor;
    const double vb = amp ? b.amplitude : b.loss_factor;
    *spread = std::max(*spread, std::abs(va - vb));
  };
  for (int dir = 0; dir < 2; ++dir) {
    const bool maximise_response = dir == 1;
    BoundSolution& best = maximise_response ? into->max : into->min;
    const BoundSolution& cand = maximise_response ? other.max : other.min;
    double* spread = maximise_response ? &into->spread_max : &into->spread_min;
    const double other_spread = maximise_response ? other.spread_max : other.spread_min;
    if (std::isfinite(other_spread)) {
      *spread = std::isfinite(*spread) ? std::max(*spread, other_spread) : other_spread;
    }
    widen(best, cand, spread);
    if (!cand.IsUsable()) continue;
    const double sign = maximise_response ? 1.0 : -1.0;  // larger is better after the sign
    if (!best.IsUsable() || sign * RankValue(cand, objective) > sign * RankValue(best, objective)) {
      best = cand;
    }
  }
  into->seeds_tried += other.seeds_tried;
  into->seeds_converged += other.seeds_converged;
  into->start_failures += other.start_failures;
  into->min_failures += other.min_failures;
  into->max_failures += other.max_failures;
  into->optimizer_runs += other.optimizer_runs;
  into->runs_abandoned += other.runs_abandoned;
  into->samples_checked += other.samples_checked;
  into->samples_failed += other.samples_failed;
  into->improved_by_samples += other.improved_by_samples;
  into->refinement_fallbacks += other.refinement_fallbacks;
  into->wall_s += other.wall_s;
}

}  // namespace fricrom
