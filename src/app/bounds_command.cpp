// `fricrom bounds`: the response bounds at one frequency or over a curve, its files and report.
#include <array>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/design_state.h"
#include "app/mpi_units.h"
#include "app/progress_line.h"
#include "app/result_files.h"
#include "app/unit_runs.h"
#include "fricrom/balance.h"
#include "fricrom/stability.h"
#include "fricrom/units.h"
#include "fricrom/work_queue.h"

namespace fricrom::app {

using design_detail::Plot;
using design_detail::Seconds;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// The JSON of `fricrom bounds`: the peak's bounds (or the single frequency's), with every point,
// the units of work and the files of a curve.
void PrintBoundsJson(const Case& c, const BoundCurveOptions& co, const std::string& preset,
                     const BoundCurve& curve, const CurveUnitsRun& run, double wall,
                     const std::array<fs::path, 2>& files) {
  const std::vector<BoundsResult>& results = curve.points;
  const bool have_peak = curve.HasPeak();
  const BoundsResult& at = results[have_peak ? curve.peak : 0];
  const int n = static_cast<int>(results.size());
  json j = BoundsJson(c.model, at);
  if (n > 1) {
    j["peak_freq_hz"] = have_peak ? json(at.freq_hz) : json(nullptr);
    json pts = json::array();
    for (const BoundsResult& b : results) pts.push_back(BoundsJson(c.model, b));
    j["points"] = pts;
  }
  // The units of every stage the curve ran (ComputeBoundCurve's stages).
  int units = 0;
  for (const CurveStage& s : run.stages) units += s.units;
  j["units"] = {{"total", units},
                {"computed", run.computed},
                {"resumed", run.resumed},
                {"threads", MpiSize() > 1 ? 1 : WorkerThreads(co.threads, n)},
                {"ranks", MpiSize()}};
  json stages = json::array();  // where the time went: this run's wall time per stage
  for (const CurveStage& s : run.stages) {
    stages.push_back(
        {{"stage", s.name}, {"units", s.units}, {"computed", s.computed}, {"wall_s", s.wall_s}});
  }
  j["stages"] = stages;
  // The search's settings as used (the preset's, or the options that override it).
  json level_names = json::array();
  for (const AlphaLevel& l : co.levels.levels) {
    level_names.push_back({{"name", l.name}, {"parameters", l.num_parameters()}});
  }
  j["search"] = {{"preset", preset},
                 {"levels", level_names},
                 {"max_corners", co.levels.max_corners},
                 {"corner_starts", co.levels.corner_starts},
                 {"random_seeds", co.bounds.random_seeds},
                 {"check_samples", co.bounds.check_samples},
                 {"search_harmonics", co.bounds.search_harmonics}};
  j["wall_s"] = wall;
  j["files"] = {{"hdf5", files[0].string()}, {"csv", files[1].string()}};
  std::cout << j.dump() << "\n";
}

// The text report of `fricrom bounds`: the peak's (or the single frequency's) brief report.
void PrintBoundsText(const Case& c, const BoundCurve& curve, const CurveUnitsRun& run, double wall,
                     const fs::path& h5p, const fs::path& csvp) {
  const std::vector<BoundsResult>& results = curve.points;
  const BoundsResult& at = results[curve.HasPeak() ? curve.peak : 0];
  if (run.resumed > 0)
    std::cout << "Resumed: " << run.resumed << " point passes from the journal\n";
  std::cout << "Response bounds of " << c.name << " (" << c.model.dof_names[c.model.response_dof]
            << "), " << results.size() << " frequencies in " << std::setprecision(3) << wall
            << " s\n";
  std::cout << "  at " << std::fixed << std::setprecision(2) << at.freq_hz << " Hz"
            << (results.size() > 1 ? " (peak of y_max)" : "") << ": " << at.BriefReport() << "\n";
  if (at.min.regimes.size() <= 12) {  // the report above counts them for FE interfaces
    std::cout << "  states at min:";
    for (const std::string& r : RegimeNames(at.min.regimes)) std::cout << " " << r;
    std::cout << "\n  states at max:";
    for (const std::string& r : RegimeNames(at.max.regimes)) std::cout << " " << r;
    std::cout << "\n";
  }
  for (const auto& [name, s] : {std::pair{"min", &at.min}, std::pair{"max", &at.max}}) {
    std::cout << "  stability at " << name << " (Hill): "
              << (s->stability.computed ? (s->stability.stable ? "stable" : "UNSTABLE")
                                        : "not computed")
              << " (" << s->stability.note << ")\n";
  }
  if (at.stable.candidates > 0) {
    const StableBounds& s = at.stable;
    const auto bound = [](double y, bool exact) {
      std::ostringstream o;
      o << std::scientific << std::setprecision(4) << y << (exact ? " (the bound)" : " (a sample)");
      return o.str();
    };
    std::cout << "  stable bounds (" << s.stable << " of " << s.candidates
              << " candidates Hill-stable, " << s.approximate << " approximate verdicts): ";
    if (s.stable > 0) {
      std::cout << "min " << bound(s.min.amplitude, s.exact_min) << ", max "
                << bound(s.max.amplitude, s.exact_max) << ", R " << std::fixed
                << std::setprecision(4) << s.robustness() << "\n";
    } else {
      std::cout << "none stable\n";
    }
    if (s.beyond_bounds > 0) {
      std::cout << "  WARNING: " << s.beyond_bounds
                << " alpha samples lie outside the bounds: the search missed them\n";
    }
  }
  if (run.stages.size() > 1) {  // one stage (a frequency off the harmonic ladder) says nothing new
    std::cout << "  stages:";
    const char* sep = " ";
    for (const CurveStage& s : run.stages) {
      std::cout << sep << s.name << " " << std::defaultfloat << std::setprecision(3) << s.wall_s
                << " s";
      sep = ", ";
    }
    std::cout << "\n";
  }
  std::cout << "  wrote " << h5p.string() << ", " << csvp.string() << "\n";
}

}  // namespace

// ------------------------------------------------------------------------------------- bounds
int DesignCommands::State::RunBounds() {
  const auto t0 = std::chrono::steady_clock::now();
  const Case c = bounds_case.Load();
  const auto balance = MakeCaseBalance(c);
  const HarmonicBalance& system = *balance;
  const BoundsOptions base = MakeBoundsOptions(c);
  std::string error;
  if (!base.IsValid(&error)) throw CLI::ValidationError("--seeds", error);
  if (!range.empty() && !(range[1] > range[0])) {
    throw CLI::ValidationError("--range", "needs LO < HI, got " + std::to_string(range[0]) + " " +
                                              std::to_string(range[1]));
  }
  const double lo = range.empty() ? c.analysis.freq_min_hz : range[0];
  const double hi = range.empty() ? c.analysis.freq_max_hz : range[1];
  const std::vector<double> freqs =
      freq > 0.0 ? std::vector<double>{freq} : EvenFrequencies(lo, hi, points);
  if (freq > 0.0) WarnOutsideCaseRange(c, freq, "--freq");
  Progress progress{ShowProgress(), "bounds"};
  BoundCurveOptions co;
  co.bounds = base;
  co.levels = MakeLevelOptions(c);
  co.anchor_every = anchor_every;
  FromString(neighbour_pass, &co.neighbour_pass);  // CLI::IsMember checked the name
  // Ipopt (through MUMPS) is not known to be safe on concurrent threads: one thread for it.
  co.threads = base.method == BoundsOptions::kReducedSpace ? threads : 1;
  if (progress.enabled) {
    co.progress = [&progress](const std::string& stage, int done, int total) {
      progress(stage, done, total);
    };
  }
  // Units of work are the frequencies' two passes (threads or MPI ranks); rank 0 journals and
  // writes the files as a set while it holds the folder's lock.
  const fs::path dir = MpiRank() == 0 ? OutDir(c, "bounds") : fs::path();
  const fs::path h5p = dir / "bounds.h5", csvp = dir / "bounds.csv";
  BoundCurve curve;
  double wall = 0.0;
  const CurveUnitsRun run = RunCurveUnits(
      dir,
      JournalHeader("bounds", bounds_case,
                    {{"freqs_hz", freqs},
                     {"warm_start", co.warm_start},
                     {"anchor_every", co.anchor_every},
                     {"neighbour_pass", ToString(co.neighbour_pass)}}),
      resume, system, [&] { return MakeCaseBalance(c); }, freqs, co,
      [&](const CurveUnitsRun& r) {
        progress.Done();
        curve = AssembleBoundCurve(r.points);
        // Hill stability of each bound (full or condensed balance; the note says why where it
        // is not computed), the condensed balance's modal data shared by the points.
        SolutionStability stability(system);
        for (BoundsResult& p : curve.points) {
          AssessBoundStability(&stability, RadPerS(p.freq_hz), &p);
          if (stable_only) {
            p.stable = BoundsOverStableSolutions(&stability, system, p, stable_samples);
          }
        }
        wall = curve.wall_s = Seconds(t0);
        WriteBoundCurveFiles(c, system, curve, {h5p, csvp});
        WriteManifest(dir, "bounds", {h5p, csvp});
      });
  if (run.worker) return 0;
  if (plot) {
    Plot("plot_bounds.py", {h5p.string(), (dir / "bounds.png").string(), "--normalise"});
    // Time histories are readable for a few contacts; FE interfaces get the contact-state map.
    if (c.model.contacts.size() <= 12)
      Plot("plot_contacts.py", {h5p.string(), (dir / "contacts.png").string()});
    if (HasContactMap(c))
      Plot("plot_contact_map.py", {h5p.string(), (dir / "contact_map.png").string()});
  }
  bool ok = true;
  for (const BoundsResult& b : curve.points) ok = ok && b.IsUsable();
  // Reported: the peak of y_max, else the first point (whose values are NaN).
  if (as_json) {
    PrintBoundsJson(c, co, search, curve, run, wall, {h5p, csvp});
  } else if (!quiet) {
    PrintBoundsText(c, curve, run, wall, h5p, csvp);
  }
  return ok ? 0 : 1;
}

}  // namespace fricrom::app
