// `fricrom verify`: the bounds at one frequency against independent routes — fixed-α solves at
// sampled α and time integrations from several static states, each refined by Newton into a
// harmonic-balance solution. A solution found beyond the bounds proves them local: the bound
// optimisation restarts from it (ImproveBounds) and everything is judged against the result.
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "app/bounds_record.h"
#include "app/cli_common.h"
#include "app/design_state.h"
#include "app/mpi_units.h"
#include "app/progress_line.h"
#include "app/result_files.h"
#include "app/unit_runs.h"
#include "fricrom/alpha_levels.h"
#include "fricrom/balance_pool.h"
#include "fricrom/bound_search.h"
#include "fricrom/bounds.h"
#include "fricrom/certification.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"
#include "io/atomic_file.h"

namespace fricrom::app {

using design_detail::Num;
using design_detail::Seconds;
using json = nlohmann::json;

namespace {

// Relative tolerance of "inside" for fixed-α solutions (solver tolerances are ~1e-10).
constexpr double kInsideTolerance = 1e-6;
// Harmonic truncation (H) separates a time-domain amplitude from the HBM's by up to ~1e-3 off
// resonance: the time integration's own amplitude is judged with this margin.
constexpr double kTimeDomainMargin = 0.02;

// The harmonic-balance solution a time integration ended at: Newton from its last period's
// harmonics at its equivalent α (T/μN per contact at the start of that period). Where it
// converges, the time-domain state is a member of the HBM's α-family, and an amplitude beyond the
// bounds proves them local; null where it does not converge or α is grouped (no α per contact).
// "x" (the solution) is for the improvement stage and is removed before output.
// A run that has not settled and whose state refines into a solution is integrated on from that
// solution's own state (IntegrateFromPeriodicState): where the solution holds (steady, at its
// own amplitude within the truncation margin) and the run lies within that margin of it, the run
// has settled on it. Reported as "continued".
json ContinueFromSolution(const Model& model, const HarmonicBalance& system,
                          const Eigen::VectorXd& x, double freq_hz, const Eigen::VectorXd& alpha,
                          TimeIntegrationOptions to, double run_amplitude) {
  const double y = system.Amplitude(x);
  to.freq_hz = freq_hz;
  to.min_periods = 1;
  to.max_periods = 3 * to.window_periods;
  const TimeIntegrationResult c = IntegrateFromPeriodicState(
      model, PeriodicStartOf(model, system, x, RadPerS(freq_hz), alpha), to);
  const auto near = [&](double v) { return std::abs(v - y) <= kTimeDomainMargin * y; };
  const bool holds = c.IsSteady() && near(c.amplitude);
  return {{"status", ToString(c.status)}, {"amplitude", Num(c.amplitude)},
          {"periods", c.periods},         {"relative_change", Num(c.relative_change)},
          {"solution_holds", holds},      {"run_settled_on_it", holds && near(run_amplitude)}};
}

json HbmFromTimeState(BalancePool& pool, const Model& model, const TimeIntegrationResult& r,
                      double freq_hz, const TimeIntegrationOptions& to) {
  if (!std::isfinite(r.amplitude) || !model.alpha_group.empty() ||
      r.last_period_displacements.cols() == 0) {
    return nullptr;
  }
  const BalancePool::Lease lease = pool.Borrow();
  const HarmonicBalance& system = lease.get();
  Eigen::VectorXd x = system.FromDofCoefficients(LastPeriodCoefficients(r, system.harmonics()));
  const NewtonSummary s = SolveNewton(HbmAtFrequency(system, RadPerS(freq_hz), r.equivalent_alpha),
                                      NewtonOptions{}, &x);
  json j{{"converged", s.IsSolutionUsable()},
         {"amplitude", Num(s.IsSolutionUsable() ? system.Amplitude(x) : NAN)},
         {"iterations", s.iterations}};
  if (s.IsSolutionUsable()) {
    j["x"] = ToStd(x);
    if (!r.IsSteady()) {
      j["continued"] =
          ContinueFromSolution(model, system, x, freq_hz, r.equivalent_alpha, to, r.amplitude);
    }
  }
  return j;
}

bool Outside(double y, double lo, double hi) {
  return y < lo * (1 - kInsideTolerance) || y > hi * (1 + kInsideTolerance);
}

struct SampleTally {
  int failed = 0, inside = 0, outside = 0;
  double min = NAN, max = NAN;
};

// y: one amplitude per sample, NaN where the solve failed.
SampleTally TallySamples(const std::vector<double>& y, double lo, double hi) {
  SampleTally t;
  for (double v : y) {
    if (std::isnan(v)) {
      ++t.failed;
      continue;
    }
    t.min = std::isnan(t.min) ? v : std::min(t.min, v);
    t.max = std::isnan(t.max) ? v : std::max(t.max, v);
    ++(Outside(v, lo, hi) ? t.outside : t.inside);
  }
  return t;
}

struct RunTally {
  int outside = 0, unsteady = 0, beyond = 0;
};

double RefinedAmplitude(const json& run) {
  const json& h = run["hbm_from_state"];
  return h.is_object() && h["converged"].get<bool>() ? h["amplitude"].get<double>() : NAN;
}

// Marks each run inside (its time-domain amplitude, with the truncation margin) and
// hbm_beyond_bounds (its refined HBM solution, to the solver tolerance).
RunTally JudgeRuns(json* runs, double lo, double hi) {
  RunTally t;
  for (json& r : *runs) {
    const double y = r["amplitude"].is_null() ? NAN : r["amplitude"].get<double>();
    const bool in = y >= lo * (1 - kTimeDomainMargin) && y <= hi * (1 + kTimeDomainMargin);
    // Steady: settled by itself, or next to a solution that holds under time integration.
    const json& h = r["hbm_from_state"];
    const bool settled_on_solution =
        h.is_object() && h.contains("continued") && h["continued"]["run_settled_on_it"].get<bool>();
    const bool steady =
        r["status"] == ToString(TimeIntegrationResult::Status::kSteadyState) || settled_on_solution;
    t.outside += steady && !in;
    t.unsteady += !steady;
    r["inside"] = in;
    const double refined = RefinedAmplitude(r);
    const bool beyond = std::isfinite(refined) && Outside(refined, lo, hi);
    r["hbm_beyond_bounds"] = beyond;
    t.beyond += beyond;
  }
  return t;
}

// The solutions beyond [lo, hi]: samples (solved again, the same deterministic solve as their
// unit) and the time integrations' refined states. Removes the runs' "x" entries.
std::vector<KnownSolution> SolutionsBeyond(const HarmonicBalance& system, double freq_hz,
                                           const std::vector<Eigen::VectorXd>& alphas,
                                           const std::vector<double>& y, json* runs, double lo,
                                           double hi) {
  std::vector<KnownSolution> known;
  for (size_t i = 0; i < y.size(); ++i) {
    if (std::isnan(y[i]) || !Outside(y[i], lo, hi)) continue;
    const FrfPoint p =
        SolveAtFrequency(system, alphas[i], freq_hz, Eigen::VectorXd(), FrfOptions{});
    if (p.status == SolverStatus::kConverged) known.push_back({p.x, alphas[i]});
  }
  for (json& r : *runs) {
    json& h = r["hbm_from_state"];
    if (!h.is_object() || !h.contains("x")) continue;
    const double refined = RefinedAmplitude(r);
    if (Outside(refined, lo, hi)) {
      const std::vector<double> x = h["x"].get<std::vector<double>>();
      const std::vector<double> a = r["equivalent_alpha"].get<std::vector<double>>();
      known.push_back({Eigen::Map<const Eigen::VectorXd>(x.data(), std::ssize(x)),
                       Eigen::Map<const Eigen::VectorXd>(a.data(), std::ssize(a))});
    }
    h.erase("x");
  }
  return known;
}

// Every α is drawn before anything is solved, so that unit k is the same computation on any
// number of threads or ranks: a) sampling, the corners of the box first, then uniform random
// (fixed seed); b) time integrations from α = 0, the two alternating corners, then random.
struct VerifyAlphas {
  std::vector<Eigen::VectorXd> samples, time_runs;
};

VerifyAlphas DrawAlphas(int nc, int samples, int ti_runs) {
  std::mt19937 rng(20241);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VerifyAlphas a{std::vector<Eigen::VectorXd>(samples, Eigen::VectorXd(nc)),
                 std::vector<Eigen::VectorXd>(ti_runs, Eigen::VectorXd(nc))};
  for (int i = 0; i < samples; ++i) {
    for (int k = 0; k < nc; ++k) {
      a.samples[i][k] = (nc < 20 && i < (1 << nc)) ? (((i >> k) & 1) ? 1.0 : -1.0) : u(rng);
    }
  }
  for (int i = 0; i < ti_runs; ++i) {
    for (int k = 0; k < nc; ++k)
      a.time_runs[i][k] =
          i == 0 ? 0.0 : (i <= 2 ? ((k % 2 == 0) == (i == 1) ? 1.0 : -1.0) : u(rng));
  }
  return a;
}

// One time integration to the steady state from the static state of `alpha`, as a JSON row.
std::string TimeIntegrationUnit(const Case& c, BalancePool& pool, const Eigen::VectorXd& alpha,
                                double freq, TimeIntegrationOptions to) {
  const auto t_run = std::chrono::steady_clock::now();
  to.freq_hz = freq;
  to.min_periods = std::min(to.min_periods, to.max_periods);
  const TimeIntegrationResult r = IntegrateToSteadyState(c.model, alpha, to);
  return json{{"status", ToString(r.status)},
              {"hbm_from_state", HbmFromTimeState(pool, c.model, r, freq, to)},
              {"message", r.message},
              {"amplitude", Num(r.amplitude)},
              {"periods", r.periods},
              {"scheme", r.scheme},
              {"modes_integrated", r.modes_integrated},
              {"relative_change", Num(r.relative_change)},
              {"free_vibration", Num(r.free_vibration)},
              // T/μN at the start of the last period, per contact: the α of the HBM member
              // this steady state is (e.g. a --seeds entry of `bounds` when α is per contact).
              {"equivalent_alpha", ToStd(r.equivalent_alpha)},
              {"wall_s", Seconds(t_run)},
              {"states", RegimeNames(r.regimes)}}
      .dump();
}

// The certificate `j` as text on stdout.
void PrintCertification(const json& j, const std::filesystem::path& file) {
  const auto num = [](const json& v) {
    std::ostringstream s;
    if (v.is_null()) {
      s << NAN;  // a failed value prints as the NaN it stands for
    } else {
      s << v.get<double>();
    }
    return s.str();
  };
  const json& imp = j.at("bounds_improved");
  const json& smp = j.at("sampling");
  std::cout << "Certification of the bounds at " << j.at("freq_hz").get<double>() << " Hz: ["
            << num(j.at("y_min")) << ", " << num(j.at("y_max")) << "] m\n";
  if (imp.at("restarts").get<int>() > 0) {
    std::cout << "  the optimised bounds [" << num(imp.at("y_min_optimised")) << ", "
              << num(imp.at("y_max_optimised")) << "] m were local: " << imp.at("restarts")
              << " solution(s) beyond them restarted the optimisation (" << imp.at("bounds_moved")
              << " bound(s) moved)\n";
  }
  std::cout << "  alpha sampling: " << smp.at("converged") << "/" << smp.at("samples")
            << " solved, " << smp.at("outside") << " outside the bounds, sampled range ["
            << num(smp.at("sampled_min")) << ", " << num(smp.at("sampled_max")) << "]\n";
  for (const char* kind : {"structured", "uniform"}) {
    const json& k = smp.at(kind);
    std::cout << "    " << kind << ": " << k.at("converged") << "/" << k.at("samples")
              << " solved, " << k.at("outside") << " outside, range [" << num(k.at("sampled_min"))
              << ", " << num(k.at("sampled_max")) << "]\n";
  }
  for (const json& r : j.at("time_integration")) {
    std::cout << "  time integration: " << r.dump() << "\n";
  }
  const bool certified = j.at("certified").get<bool>();
  std::cout << "  " << (certified ? "CERTIFIED" : "NOT CERTIFIED") << "\n";
  for (const json& r : j.at("not_certified_because")) {
    std::cout << "    " << r.get<std::string>() << "\n";
  }
  std::cout << "  wrote " << file.string() << "\n";
}

}  // namespace

int DesignCommands::State::RunVerify() {
  const auto t0 = std::chrono::steady_clock::now();
  const Case c = verify_case.Load();
  const auto balance = MakeCaseBalance(c);
  const HarmonicBalance& system = *balance;
  const int nc = system.num_alpha();
  const BoundsOptions bo = MakeBoundsOptions(c);
  const LevelSearchOptions levels = MakeLevelOptions(c);
  const VerifyAlphas drawn = DrawAlphas(nc, samples, ti_runs);
  // Structured α first (the levels' corners and face tilts, which uniform samples of a large box
  // never come near), then the uniform samples.
  std::vector<Eigen::VectorXd> alphas = StructuredAlphaPatterns(levels.levels);
  const int structured = static_cast<int>(alphas.size());
  alphas.insert(alphas.end(), drawn.samples.begin(), drawn.samples.end());
  const int all_samples = static_cast<int>(alphas.size());
  const std::vector<Eigen::VectorXd>& ti_alphas = drawn.time_runs;
  // Units: 0 the bounds, then the α samples, then the time integrations (threads or MPI ranks).
  BalancePool pool(system, [&] { return MakeCaseBalance(c); });
  const auto unit = [&](int k) -> std::string {
    if (k == 0) {
      return BoundsRecord(ComputeLevelBounds(pool.Borrow().get(), freq, bo, levels)).dump();
    }
    if (k <= all_samples) {
      const BalancePool::Lease lease = pool.Borrow();
      const FrfPoint p =
          SolveAtFrequency(lease.get(), alphas[k - 1], freq, Eigen::VectorXd(), FrfOptions{});
      return Num(p.status == SolverStatus::kConverged ? p.amplitude : NAN).dump();
    }
    return TimeIntegrationUnit(c, pool, ti_alphas[k - 1 - all_samples], freq, time_options);
  };
  Progress progress{ShowProgress(), "verify"};
  // Ipopt (through MUMPS) is not known to be safe on concurrent threads: one thread for it.
  const std::vector<std::string> texts =
      RunTextUnits(1 + all_samples + ti_runs,
                   bo.method == BoundsOptions::kReducedSpace ? threads : 1, unit, progress);
  progress.Done();
  if (MpiRank() != 0) return 0;
  BoundsResult b = BoundsFromRecord(json::parse(texts[0]));
  if (!b.IsUsable()) {
    std::cerr << "fricrom: bounds did not converge: " << b.BriefReport() << "\n";
    return 1;
  }
  std::vector<double> y(all_samples);
  for (int i = 0; i < all_samples; ++i) {
    const json v = json::parse(texts[1 + i]);
    y[i] = v.is_null() ? NAN : v.get<double>();
  }
  json runs = json::array();
  for (int i = 0; i < ti_runs; ++i) {
    json r = json::parse(texts[1 + all_samples + i]);
    r["initial_alpha"] = ToStd(ti_alphas[i]);
    runs.push_back(r);
  }
  // A solution beyond the bounds: the optimisation restarts from it (its x keeps the branch of
  // periodic solutions it was found on), and the evidence is judged against the result.
  const double lo0 = b.min.amplitude, hi0 = b.max.amplitude;
  const std::vector<KnownSolution> beyond =
      SolutionsBeyond(system, freq, alphas, y, &runs, lo0, hi0);
  int moved = 0;
  if (!beyond.empty()) {
    if (ShowProgress()) {
      std::cerr << "verify: " << beyond.size()
                << " solution(s) beyond the bounds: restarting the bound optimisation from them\n";
    }
    moved = ImproveBounds(system, freq, bo, beyond, &b);
  }
  const double lo = b.min.amplitude, hi = b.max.amplitude;
  const SampleTally st = TallySamples(y, lo, hi);
  const SampleTally st_structured =
      TallySamples(std::vector<double>(y.begin(), y.begin() + structured), lo, hi);
  const SampleTally st_uniform =
      TallySamples(std::vector<double>(y.begin() + structured, y.end()), lo, hi);
  // How far the bound run's own bounds were beaten (relative), by samples or time states.
  const double excess_min = std::isfinite(lo0) && lo < lo0 ? (lo0 - lo) / lo0 : 0.0;
  const double excess_max = std::isfinite(hi0) && hi > hi0 ? (hi - hi0) / hi0 : 0.0;
  const RunTally rt = JudgeRuns(&runs, lo, hi);
  CertificationEvidence evidence{all_samples, st.failed,  st.outside, ti_runs,
                                 rt.unsteady, rt.outside, rt.beyond};
  evidence.bounds_beaten = moved;
  const std::vector<std::string> reasons = CertificationGaps(evidence);
  const bool certified = reasons.empty();
  json j;
  j["freq_hz"] = freq;
  j["y_min"] = Num(lo);
  j["y_max"] = Num(hi);
  j["bounds_improved"] = {{"restarts", beyond.size()},
                          {"bounds_moved", moved},
                          {"y_min_optimised", Num(lo0)},
                          {"y_max_optimised", Num(hi0)}};
  j["bounds_beaten"] = {{"count", moved},
                        {"y_min_relative_excess", excess_min},
                        {"y_max_relative_excess", excess_max}};
  const auto tally = [](const SampleTally& t, int n) {
    return json{{"samples", n},
                {"converged", n - t.failed},
                {"failed", t.failed},
                {"failed_share", n > 0 ? static_cast<double>(t.failed) / n : 0.0},
                {"inside", t.inside},
                {"outside", t.outside},
                {"sampled_min", Num(t.min)},
                {"sampled_max", Num(t.max)}};
  };
  j["sampling"] = tally(st, all_samples);
  j["sampling"]["structured"] = tally(st_structured, structured);
  j["sampling"]["uniform"] = tally(st_uniform, all_samples - structured);
  j["time_integration"] = runs;
  j["time_integration_outside"] = rt.outside;
  j["time_integration_unsteady"] = rt.unsteady;
  j["time_integration_hbm_beyond"] = rt.beyond;
  j["certified"] = certified;
  j["not_certified_because"] = reasons;
  j["wall_s"] = Seconds(t0);
  // The certificate is kept beside the other results (--out), not only on stdout.
  const std::filesystem::path file = OutDir(c, "verify") / "verify.json";
  WriteTextAtomically(file, j.dump(1) + "\n");
  if (as_json) {
    std::cout << j.dump() << "\n";
  } else if (!quiet) {
    PrintCertification(j, file);
  }
  return certified ? 0 : 1;
}

}  // namespace fricrom::app
