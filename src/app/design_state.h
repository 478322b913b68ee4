// The state of the design commands (bounds, sweep, noa, verify): their options and the helpers
// they share. Private to the app: design_commands.cpp registers and runs them, bounds_command.cpp
// holds `bounds`.
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "app/design_commands.h"
#include "app/result_files.h"
#include "fricrom/alpha_levels.h"
#include "fricrom/bounds.h"
#include "fricrom/design.h"
#include "fricrom/time_integration.h"
#include "io/content_hash.h"

namespace fricrom::app {
namespace design_detail {

inline double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
inline nlohmann::json Num(double v) { return NumberOrNull(v); }
// Runs scripts/<script> with the system Python; figures go to stderr's side, never stdout.
void Plot(const std::string& script, const std::vector<std::string>& args);

}  // namespace design_detail

struct DesignCommands::State {
  using json = nlohmann::json;
  CaseArgs bounds_case, sweep_case, noa_case, verify_case;
  CLI::App* bounds = nullptr;
  CLI::App* sweep = nullptr;
  CLI::App* noa = nullptr;
  CLI::App* verify = nullptr;
  // shared options
  std::string seeds, out, objective = "amplitude", method = "reduced";
  int check_samples = BoundsOptions{}.check_samples, random_seeds = 0;
  int line_search_memory = BoundsOptions{}.line_search_memory;
  double negligible_minimum = BoundsOptions{}.negligible_minimum;
  double refinement_change = BoundsOptions{}.refinement_stationary_change;
  double stall_change = BoundsOptions{}.stall_change;
  int stall_window = BoundsOptions{}.stall_window;
  int maximum_bfgs_memory = BoundsOptions{}.maximum_bfgs_memory;
  std::string dominance = BoundsOptions{}.dominated_by_earlier_runs ? "runs" : "starts";
  int search_harmonics = -1;       // --search-harmonics; -1: the case's analysis.search_harmonics
  std::string search = "default";  // --search: quick | default | thorough (MakeLevelOptions)
  std::string alpha_levels = "auto";  // --alpha-levels: auto (the case's hierarchy) | pair
  bool as_json = false, plot = false, quiet = false, track_peak = false;
  double freq = 0.0, from = 0.0, to = 0.0;
  std::vector<double> range;              // bounds --range LO HI [Hz]; empty: the case's range
  int anchor_every = 1;                   // bounds curve: BoundCurveOptions::anchor_every
  std::string neighbour_pass = "sweeps";  // bounds curve: BoundCurveOptions::neighbour_pass
  int points = 41, steps = 44, sweep_steps = 44, samples = 200, ti_runs = 4;
  int scan_points = NoaOptions{}.scan_points;
  std::string param, noa_objective = "eta-gap";
  bool no_sweep = false, resume = false;
  int threads = 0;
  bool stable_only = false;  // bounds --stable-only: also the bounds over stable candidates
  int stable_samples = 32;   // bounds --stable-samples: α samples beside the bounds' solutions
  TimeIntegrationOptions time_options;  // verify: the time integrations (freq_hz set per run)

  BoundsOptions MakeBoundsOptions(const Case& c) const {
    const int nc = c.model.num_alpha();
    BoundsOptions o;
    if (!seeds.empty()) o.alpha_seeds = ParseSeeds(seeds, nc);
    o.random_seeds = random_seeds;
    if (objective == "loss-factor") o.objective = BoundsOptions::kLossFactor;
    if (!FromString(method, &o.method))
      throw CLI::ValidationError("--method", "unknown: " + method);
    o.check_samples = check_samples;
    o.line_search_memory = line_search_memory;
    o.negligible_minimum = negligible_minimum;
    o.refinement_stationary_change = refinement_change;
    o.stall_change = stall_change;
    o.stall_window = stall_window;
    o.maximum_bfgs_memory = maximum_bfgs_memory;
    o.dominated_by_earlier_runs = dominance == "runs";
    o.search_harmonics = search_harmonics >= 0 ? search_harmonics : c.analysis.search_harmonics;
    if (search == "thorough") {  // the preset's finest level: more starts and samples
      o.random_seeds = std::max(o.random_seeds, 8);
      o.check_samples = std::max(o.check_samples, 64);
    }
    return o;
  }
  // The α levels of the case's bound search and the preset's starts on the coarsest level:
  // quick 16 corners (1 start per direction), default 256 (2), thorough 4096 (4).
  LevelSearchOptions MakeLevelOptions(const Case& c) const {
    LevelSearchOptions o;
    if (alpha_levels == "auto") o.levels = AlphaLevelsOf(c);
    if (search == "quick") {
      o.max_corners = 16;
      o.corner_starts = 1;
    } else if (search == "thorough") {
      o.max_corners = 4096;
      o.corner_starts = 4;
    }
    return o;
  }
  std::filesystem::path OutDir(const Case& c, const std::string& sub) const {
    std::filesystem::path d =
        out.empty() ? std::filesystem::path("results") / c.name / sub : std::filesystem::path(out);
    std::filesystem::create_directories(d);
    return d;
  }
  // What a journal must match to be resumed: the case (its content), every option that changes a
  // result, and the command's own keys in `extra` (values, frequencies). (Files the case names are
  // not hashed here: an FE body's reduction is cached by their content, but a changed matrix
  // file under an unchanged case needs a fresh --out.)
  json JournalHeader(const std::string& kind, const CaseArgs& ca, const json& extra) const {
    Hasher h;
    HashFile(ca.path, &h);
    json j = {{"journal", "fricrom-" + kind + "-1"},
              {"version", Version()},
              {"case", ca.path},
              {"case_content", h.Hex()},
              {"sets", ca.sets},
              {"harmonics", ca.harmonics},
              {"samples", ca.samples},
              {"balance", ca.balance},
              {"receptance", ca.receptance},
              {"seeds", seeds},
              {"objective", objective},
              {"method", method},
              {"check_samples", check_samples},
              {"line_search_memory", line_search_memory},
              {"negligible_minimum", negligible_minimum},
              {"refinement_change", refinement_change},
              {"stall_change", stall_change},
              {"stall_window", stall_window},
              {"maximum_bfgs_memory", maximum_bfgs_memory},
              {"dominance", dominance},
              {"search_harmonics", search_harmonics},
              {"random_seeds", random_seeds},
              {"search", search},
              {"alpha_levels", alpha_levels}};
    j.update(extra);
    return j;
  }
  // On stderr (JSON goes to stdout, so --json does not silence it); app/progress_line.h.
  bool ShowProgress() const { return !quiet; }

  // Reference frequency: --freq, else the peak of y_max over the case range at the given case.
  double ReferenceFrequency(const Case& c, const BoundsOptions& bo, int* solves) const {
    if (freq > 0.0) {
      WarnOutsideCaseRange(c, freq, "--freq");
      return freq;
    }
    const auto balance = MakeCaseBalance(c);
    const HarmonicBalance& system = *balance;
    ResonanceSearchOptions rs;
    rs.lo_hz = c.analysis.freq_min_hz;
    rs.hi_hz = c.analysis.freq_max_hz;
    rs.scan_points = 21;
    const ResonanceResult r = FindResonance(system, rs, bo, MakeLevelOptions(c));
    *solves += r.bound_solves;
    if (!std::isfinite(r.freq_hz)) {
      throw NotConverged("no maximum-response bound converged over " + std::to_string(rs.lo_hz) +
                         "-" + std::to_string(rs.hi_hz) +
                         " Hz: no resonance to evaluate R at (give --freq)");
    }
    return r.freq_hz;
  }

  // The options of each command (and those they share), bound to the fields above.
  void RegisterCommon(CLI::App* cmd);
  void RegisterBounds(CLI::App& app);
  void RegisterSweep(CLI::App& app);
  void RegisterNoa(CLI::App& app);
  void RegisterVerify(CLI::App& app);

  int RunBounds();
  int RunSweep();
  int RunNoa();
  int RunVerify();
};

}  // namespace fricrom::app
