// `fricrom verify`: the library's certification (certification.h) with its units of work — the
// bound run, the α samples, the time integrations — on threads or MPI ranks, its certificate
// written as JSON and text.
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
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
#include "fricrom/balance_pool.h"
#include "fricrom/bound_search.h"
#include "fricrom/bounds.h"
#include "fricrom/certification.h"
#include "fricrom/stability.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"
#include "io/atomic_file.h"

namespace fricrom::app {

using design_detail::Num;
using design_detail::Seconds;
using json = nlohmann::json;

namespace {

json RegimesJson(const std::vector<ContactRegime>& r) { return RegimeNames(r); }

// A time run as a unit's text (with the refined solution's x, for the judgement on rank 0) and
// back: the units travel between ranks as text.
json TimeRunJson(const TimeRunEvidence& e, bool with_x) {
  json refined = nullptr;
  if (e.refinable) {
    const RefinedState& s = e.refined;
    refined = {
        {"converged", s.converged}, {"amplitude", Num(s.amplitude)}, {"iterations", s.iterations}};
    if (with_x && s.converged) refined["x"] = ToStd(s.x);
    if (s.continued) {
      refined["continued"] = {{"status", s.continued_status},
                              {"amplitude", Num(s.continued_amplitude)},
                              {"periods", s.continued_periods},
                              {"relative_change", Num(s.continued_relative_change)},
                              {"solution_holds", s.solution_holds},
                              {"run_settled_on_it", s.run_settled_on_it}};
    }
  }
  return {{"status", ToString(e.status)},
          {"hbm_from_state", refined},
          {"message", e.message},
          {"amplitude", Num(e.amplitude)},
          {"periods", e.periods},
          {"scheme", e.scheme},
          {"modes_integrated", e.modes_integrated},
          {"relative_change", Num(e.relative_change)},
          {"free_vibration", Num(e.free_vibration)},
          // T/μN at the start of the last period, per contact: the α of the HBM member this
          // steady state is (e.g. a --seeds entry of `bounds` when α is per contact).
          {"equivalent_alpha", ToStd(e.equivalent_alpha)},
          {"initial_alpha", ToStd(e.initial_alpha)},
          {"wall_s", e.wall_s},
          {"states", RegimesJson(e.regimes)}};
}

double NumOr(const json& v) { return v.is_null() ? NAN : v.get<double>(); }
Eigen::VectorXd Vec(const json& v) {
  const std::vector<double> a = v.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(a.data(), std::ssize(a));
}

TimeRunEvidence TimeRunFromJson(const json& j) {
  TimeRunEvidence e;
  for (auto st :
       {TimeIntegrationResult::Status::kSteadyState, TimeIntegrationResult::Status::kNotSettled,
        TimeIntegrationResult::Status::kUnstable, TimeIntegrationResult::Status::kStaticFailed,
        TimeIntegrationResult::Status::kContactFailed}) {
    if (j.at("status") == ToString(st)) e.status = st;
  }
  e.message = j.at("message");
  e.scheme = j.at("scheme");
  e.amplitude = NumOr(j.at("amplitude"));
  e.periods = j.at("periods");
  e.modes_integrated = j.at("modes_integrated");
  e.relative_change = NumOr(j.at("relative_change"));
  e.free_vibration = NumOr(j.at("free_vibration"));
  e.equivalent_alpha = Vec(j.at("equivalent_alpha"));
  e.initial_alpha = Vec(j.at("initial_alpha"));
  e.wall_s = j.at("wall_s");
  const json& h = j.at("hbm_from_state");
  e.refinable = h.is_object();
  if (e.refinable) {
    RefinedState& s = e.refined;
    s.converged = h.at("converged");
    s.amplitude = NumOr(h.at("amplitude"));
    s.iterations = h.at("iterations");
    if (h.contains("x")) s.x = Vec(h.at("x"));
    if (h.contains("continued")) {
      const json& c = h.at("continued");
      s.continued = true;
      s.continued_status = c.at("status");
      s.continued_amplitude = NumOr(c.at("amplitude"));
      s.continued_periods = c.at("periods");
      s.continued_relative_change = NumOr(c.at("relative_change"));
      s.solution_holds = c.at("solution_holds");
      s.run_settled_on_it = c.at("run_settled_on_it");
    }
  }
  return e;
}

// The certificate as the JSON of `verify` (without the solutions' x).
json CertificateJson(const Certificate& c, const std::vector<json>& run_states) {
  json j;
  j["freq_hz"] = c.freq_hz;
  j["y_min"] = Num(c.bounds.min.amplitude);
  j["y_max"] = Num(c.bounds.max.amplitude);
  j["bounds_improved"] = {{"restarts", c.restarts},
                          {"bounds_moved", c.bounds_moved},
                          {"y_min_optimised", Num(c.y_min_optimised)},
                          {"y_max_optimised", Num(c.y_max_optimised)}};
  j["bounds_beaten"] = {{"count", c.bounds_moved},
                        {"y_min_relative_excess", c.y_min_relative_excess},
                        {"y_max_relative_excess", c.y_max_relative_excess}};
  const auto tally = [](const SampleTally& t) {
    return json{{"samples", t.samples},
                {"converged", t.samples - t.failed},
                {"failed", t.failed},
                {"failed_share", t.samples > 0 ? static_cast<double>(t.failed) / t.samples : 0.0},
                {"inside", t.inside},
                {"outside", t.outside},
                {"sampled_min", Num(t.min)},
                {"sampled_max", Num(t.max)}};
  };
  j["sampling"] = tally(c.sampling);
  j["sampling"]["structured"] = tally(c.structured);
  j["sampling"]["uniform"] = tally(c.uniform);
  json runs = json::array();
  for (size_t i = 0; i < c.time_runs.size(); ++i) {
    const TimeRunEvidence& r = c.time_runs[i];
    json rj = TimeRunJson(r, false);
    rj["states"] = run_states[i];
    rj["inside"] = r.inside;
    rj["steady"] = r.steady;
    rj["hbm_beyond_bounds"] = r.beyond;
    runs.push_back(rj);
  }
  j["time_integration"] = runs;
  j["time_integration_outside"] = c.time_outside;
  j["time_integration_unsteady"] = c.time_unsteady;
  j["time_integration_hbm_beyond"] = c.time_beyond;
  j["certified"] = c.certified;
  j["not_certified_because"] = c.gaps;
  return j;
}

// Both bound solutions judged twice: Hill's Floquet exponents and the time integration from the
// solution's own state (stability.h). Reported, not part of the certificate: a bound is the
// extreme of the harmonic-balance solutions, stable or not; the two routes should agree.
json BoundStabilityJson(const Case& c, const HarmonicBalance& system, const Certificate& cert) {
  json out = json::object();
  SolutionStability stability(system);
  const double omega = RadPerS(cert.freq_hz);
  for (const auto& [name, s] :
       {std::pair<const char*, const BoundSolution*>{"min", &cert.bounds.min},
        {"max", &cert.bounds.max}}) {
    if (!s->IsUsable()) {
      out[name] = nullptr;
      continue;
    }
    json hill;
    bool hill_stable = false, computed = false;
    try {
      const HillResult r = stability.At(s->x, omega, s->alpha);
      computed = true;
      hill_stable = r.stable;
      hill = {{"stable", r.stable}, {"max_floquet_real_per_s", r.max_real}, {"note", r.message}};
    } catch (const std::domain_error& e) {
      hill = {{"stable", nullptr}, {"note", std::string("not computed: ") + e.what()}};
    }
    const HoldResult h = HoldsUnderTimeIntegration(c.model, system, s->x, omega, s->alpha);
    out[name] = {{"hill", hill},
                 {"time_integration",
                  {{"holds", h.holds},
                   {"settled", h.settled},
                   {"amplitude", Num(h.amplitude)},
                   {"periods", h.periods},
                   {"message", h.message}}},
                 {"agree", computed ? json(hill_stable == h.holds) : json(nullptr)}};
  }
  return out;
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
  // One line a run: where it started, where it settled, whether inside the bounds (the JSON has
  // every field).
  for (const json& r : j.at("time_integration")) {
    const json& a = r.at("initial_alpha");
    std::ostringstream from;
    if (a.size() <= 8) {
      from << "alpha0 [";
      for (size_t i = 0; i < a.size(); ++i) from << (i ? ", " : "") << num(a[i]);
      from << "]";
    } else {
      from << "alpha0 of " << a.size() << " values";
    }
    std::cout << "  time integration from " << from.str() << ": amplitude "
              << num(r.at("amplitude")) << " m, "
              << (!r.at("inside").is_boolean() ? "not judged"
                  : r.at("inside").get<bool>() ? "inside"
                                               : "OUTSIDE")
              << " (" << r.at("message").get<std::string>() << ")\n";
  }
  if (j.contains("bound_stability")) {
    for (const char* name : {"min", "max"}) {
      const json& b = j["bound_stability"][name];
      if (b.is_null()) continue;
      const json& h = b["hill"];
      std::cout << "  y_" << name << " solution: Hill "
                << (h["stable"].is_null()     ? "not computed"
                    : h["stable"].get<bool>() ? "stable"
                                              : "UNSTABLE")
                << "; time integration from it: "
                << b["time_integration"]["message"].get<std::string>() << "\n";
    }
  }
  if (j.contains("cyclic_note")) std::cout << "  " << j["cyclic_note"].get<std::string>() << "\n";
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
  WarnOutsideCaseRange(c, freq, "--freq");
  const auto balance = MakeCaseBalance(c);
  const HarmonicBalance& system = *balance;
  const BoundsOptions bo = MakeBoundsOptions(c);
  const LevelSearchOptions levels = MakeLevelOptions(c);
  CertifyOptions co;
  co.samples = samples;
  co.time_runs = ti_runs;
  // A sector's neighbour is the sector itself one delay later: the time integrators step one
  // model without delays, so a cyclic sector is certified by its α samples alone (said so).
  const bool cyclic = c.model.cyclic.sectors > 0;
  if (cyclic) co.time_runs = 0;
  co.time = time_options;
  const CertificationPlan plan = PlanCertification(system.num_alpha(), levels.levels, co);
  const int all_samples = static_cast<int>(plan.samples.size());
  // Units: 0 the bounds, then the α samples, then the time integrations (threads or MPI ranks).
  BalancePool pool(system, [&] { return MakeCaseBalance(c); });
  const auto unit = [&](int k) -> std::string {
    const BalancePool::Lease lease = pool.Borrow();
    if (k == 0) return BoundsRecord(ComputeLevelBounds(lease.get(), freq, bo, levels)).dump();
    if (k <= all_samples) {
      return Num(SolveSampleAmplitude(lease.get(), plan.samples[k - 1], freq)).dump();
    }
    const Eigen::VectorXd& a = plan.time_runs[k - 1 - all_samples];
    return TimeRunJson(RunTimeEvidence(c.model, lease.get(), a, freq, co.time), true).dump();
  };
  Progress progress{ShowProgress(), "verify"};
  // Ipopt (through MUMPS) is not known to be safe on concurrent threads: one thread for it.
  const std::vector<std::string> texts =
      RunTextUnits(1 + all_samples + co.time_runs,
                   bo.method == BoundsOptions::kReducedSpace ? threads : 1, unit, progress);
  progress.Done();
  if (MpiRank() != 0) return 0;
  BoundsResult b = BoundsFromRecord(json::parse(texts[0]));
  if (!b.IsUsable()) {
    std::cerr << "fricrom: bounds did not converge: " << b.BriefReport() << "\n";
    return 1;
  }
  std::vector<double> y(all_samples);
  for (int i = 0; i < all_samples; ++i) y[i] = NumOr(json::parse(texts[1 + i]));
  std::vector<TimeRunEvidence> runs;
  std::vector<json> states;
  for (int i = 0; i < co.time_runs; ++i) {
    const json r = json::parse(texts[1 + all_samples + i]);
    runs.push_back(TimeRunFromJson(r));
    states.push_back(r.at("states"));
  }
  const Certificate cert =
      JudgeCertification(system, freq, bo, plan, std::move(b), y, std::move(runs));
  if (ShowProgress() && cert.restarts > 0) {
    std::cerr << "verify: " << cert.restarts
              << " solution(s) beyond the bounds restarted the bound optimisation\n";
  }
  json j = CertificateJson(cert, states);
  if (cyclic) {
    j["cyclic_note"] =
        "cyclic sector: no time integration (the coupling to the next sector is a delay the time "
        "integrators do not model) and no Hill stability; the certificate rests on the alpha "
        "samples";
  } else {
    j["bound_stability"] = BoundStabilityJson(c, system, cert);
  }
  j["wall_s"] = Seconds(t0);
  // The certificate is kept beside the other results (--out), not only on stdout.
  const std::filesystem::path file = OutDir(c, "verify") / "verify.json";
  WriteTextAtomically(file, j.dump(1) + "\n");
  if (as_json) {
    std::cout << j.dump() << "\n";
  } else if (!quiet) {
    PrintCertification(j, file);
  }
  return cert.certified ? 0 : 1;
}

}  // namespace fricrom::app
