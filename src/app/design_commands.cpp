#include "app/design_commands.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>

#include "app/bounds_record.h"
#include "app/cli_common.h"
#include "app/design_state.h"
#include "app/mpi_units.h"
#include "app/progress_line.h"
#include "app/result_files.h"
#include "app/unit_runs.h"
#include "fricrom/balance_pool.h"
#include "fricrom/bounds.h"
#include "fricrom/certification.h"
#include "fricrom/design.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/linear.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"
#include "fricrom/work_queue.h"
#include "io/atomic_file.h"
#include "io/content_hash.h"
#include "io/hdf5_file.h"

namespace fricrom::app {

using design_detail::Num;
using design_detail::Plot;
using design_detail::Seconds;
namespace fs = std::filesystem;
using json = nlohmann::json;

void design_detail::Plot(const std::string& script, const std::vector<std::string>& args) {
  std::string cmd =
      "/usr/bin/python3 '" + std::string(FRICROM_SOURCE_DIR) + "/scripts/" + script + "'";
  for (const std::string& a : args) cmd += " '" + a + "'";
  cmd += " 1>&2";  // stdout is reserved for --json
  if (std::system(cmd.c_str()) != 0)
    std::cerr << "fricrom: figure not written by " << script << "\n";
}

DesignCommands::DesignCommands() : state_(std::make_unique<State>()) {}
DesignCommands::~DesignCommands() = default;

void DesignCommands::State::RegisterCommon(CLI::App* cmd) {
  // The optimiser's knobs, apart in the help: the --search presets set the search; these stay for
  // studies of the search itself (docs/bounds-and-design.md says what each changes).
  static const std::string kTuning = "Search tuning (expert; --search sets the search)";
  cmd->add_option("--seeds", seeds, "Alpha seeds of the bound optimisations: a,b,c,d;e,f,g,h");
  cmd->add_option("--objective", objective, "Bound objective: amplitude (default) or loss-factor")
      ->check(CLI::IsMember({"amplitude", "loss-factor"}));
  cmd->add_option("--method", method,
                  "Bound optimiser: reduced (projected gradient over alpha, Newton + adjoint; "
                  "default), ipopt (full space [x, alpha] with R = 0) or both (best of the two)")
      ->check(CLI::IsMember({"reduced", "ipopt", "both"}));
  cmd->add_option("--random-seeds", random_seeds,
                  "Add this many random alpha seeds, uniform in [-1, 1] (fixed generator seed)")
      ->check(CLI::Range(0, 100000))
      ->group(kTuning);
  cmd->add_option("--check-samples", check_samples,
                  "Random alpha solves that check (and improve) each bound; 0: no check")
      ->check(CLI::Range(0, 1000000))
      ->group(kTuning);
  cmd->add_option("--line-search-memory", line_search_memory,
                  "Reduced-space runs: accept a step against the largest of the last N "
                  "objectives (nonmonotone; default 10); 1: monotone Armijo")
      ->check(CLI::Range(1, 100))
      ->group(kTuning);
  cmd->add_option("--negligible-minimum", negligible_minimum,
                  "Minimum runs whose result starts nothing else (the harmonic ladder's "
                  "refinement, a curve's neighbour starts) stop once y_min falls to this "
                  "fraction of the point's y_max (R is then below it); 0: never (default 0.001)")
      ->check(FractionBelowOne(true))
      ->group(kTuning);
  cmd->add_option("--refinement-change", refinement_change,
                  "Harmonic ladder: a refinement run at H stops once its objective changes by at "
                  "most this relative amount in 3 iterations in a row (default 1e-5; the search's "
                  "runs: 1e-7)")
      ->check(FractionBelowOne(false))
      ->group(kTuning);
  cmd->add_option("--stall-change", stall_change,
                  "Reduced-space runs stop once their best objective improved by at most this "
                  "relative amount over the last --stall-window iterations (default 1e-4)")
      ->check(FractionBelowOne(true))
      ->group(kTuning);
  cmd->add_option("--stall-window", stall_window,
                  "Accepted iterations the stall test looks back over (default 20); 0: no stall "
                  "test (runs end at their other tests or the iteration limit)")
      ->check(CLI::Range(0, 100000))
      ->group(kTuning);
  cmd->add_option("--max-bfgs-memory", maximum_bfgs_memory,
                  "Maximum runs step along limited-memory BFGS directions built from the last N "
                  "accepted steps: another path to the local maxima, a second opinion on y_max "
                  "(e.g. 5); 0 (default): the projected gradient with Barzilai-Borwein steps, "
                  "which the minimum runs always take")
      ->check(CLI::Range(0, 100))
      ->group(kTuning);
  cmd->add_option("--dominance", dominance,
                  "What a reduced-space run that cannot catch up is measured against before it "
                  "is stopped: starts (the seeds' KKT starts and the bounds a curve holds) or "
                  "runs (also the best bound of the earlier seeds' runs at the point)")
      ->check(CLI::IsMember({"starts", "runs"}))
      ->group(kTuning);
  cmd->add_option("--search-harmonics", search_harmonics,
                  "Bounds at H > 1: 1 searches at H = 1 (seeds, sample check) and refines each "
                  "optimum at H, 0 searches at H (default: the case's "
                  "analysis.search_harmonics)")
      ->check(CLI::Range(0, 1))
      ->group(kTuning);
  cmd->add_option("--search", search,
                  "Bound search preset: quick (16 corners of the coarsest alpha level, 1 start "
                  "per direction), default (256, 2) or thorough (4096, 4; and at least 8 random "
                  "seeds and 64 check samples)")
      ->check(CLI::IsMember({"quick", "default", "thorough"}));
  cmd->add_option("--alpha-levels", alpha_levels,
                  "auto (default): search coarse to fine over the case's alpha levels (interface, "
                  "face shapes, pair); pair: one level, the pair alpha only")
      ->check(CLI::IsMember({"auto", "pair"}));
  cmd->add_option("--out", out, "Output directory (default results/<case>/<command>)");
  cmd->add_flag("--json", as_json, "Print one JSON object on stdout");
  cmd->add_flag("--quiet", quiet, "Print nothing but errors");
}

void DesignCommands::State::RegisterBounds(CLI::App& app) {
  bounds = app.add_subcommand("bounds", "Minimum and maximum response over alpha, R");
  bounds_case.Register(bounds);
  RegisterCommon(bounds);
  bounds->add_option("--freq", freq, "Single frequency [Hz] (default: a curve over the case range)")
      ->check(Positive());
  bounds
      ->add_option("--range", range,
                   "Frequency range of the curve LO HI [Hz] (default: the case's analysis range)")
      ->expected(2)
      ->check(Positive());
  bounds->add_option("--points", points, "Frequencies of the curve")->check(CLI::Range(2, 100000));
  bounds
      ->add_option("--anchor-every", anchor_every,
                   "Curve: full bounds (every seed, sample check) at every K-th frequency and the "
                   "last, continuation of the optima in frequency between them (default 1: every "
                   "frequency in full)")
      ->check(CLI::Range(1, 100000));
  bounds
      ->add_option("--neighbour-pass", neighbour_pass,
                   "Curve, pass 2: sweeps (default: one sweep up and one down the curve, each "
                   "point from the bounds the sweep reached at the point before it) or "
                   "neighbours (each point from its neighbours' pass-1 optima)")
      ->check(CLI::IsMember({"sweeps", "neighbours"}));
  bounds->add_flag(
      "--stable-only", stable_only,
      "Also report the bounds over the stable (Hill) solutions among the bounds' own "
      "and fixed-alpha solves at --stable-samples points of the alpha box: exact where "
      "a bound's own solution is stable, else an inner estimate (docs/stability.md)");
  bounds
      ->add_option("--stable-samples", stable_samples,
                   "With --stable-only: alpha samples solved and judged beside the bounds' "
                   "solutions (default 32)")
      ->check(CLI::Range(0, 100000));
  bounds->add_flag("--plot", plot, "Draw the bound curve and the contact time histories");
  bounds
      ->add_option("--threads", threads,
                   "Worker threads over the frequencies (0: every core this process may use; "
                   "results do not depend on it)")
      ->check(CLI::Range(0, 4096));
  bounds->add_flag("--resume", resume,
                   "Complete an interrupted run in the same --out (an error if there is none; "
                   "rerunning the same command resumes as well)");
}

void DesignCommands::State::RegisterSweep(CLI::App& app) {
  sweep = app.add_subcommand("sweep", "Robustness R over a design parameter (manual sweep)");
  sweep_case.Register(sweep);
  RegisterCommon(sweep);
  sweep->add_option("--param", param, "Case parameter to sweep (e.g. gamma, beta)")->required();
  sweep->add_option("--from", from, "First value")->required();
  sweep->add_option("--to", to, "Last value")->required();
  sweep->add_option("--steps", steps, "Number of values")->check(CLI::Range(2, 100000));
  sweep
      ->add_option("--freq", freq,
                   "Reference frequency [Hz] (default: peak of y_max at the first value)")
      ->check(Positive());
  sweep->add_flag("--track-peak", track_peak, "Locate the resonance again at every value");
  sweep->add_flag("--plot", plot, "Draw R(p)");
  sweep
      ->add_option(
          "--threads", threads,
          "Worker threads over the values (0: every core this process may use; results do not "
          "depend on it)")
      ->check(CLI::Range(0, 4096));
  sweep->add_flag("--resume", resume,
                  "Complete an interrupted run in the same --out (an error if there is none; "
                  "rerunning the same command resumes as well)");
}

void DesignCommands::State::RegisterNoa(CLI::App& app) {
  noa = app.add_subcommand("noa", "Nested optimisation: the most robust parameter value");
  noa_case.Register(noa);
  RegisterCommon(noa);
  noa->add_option("--param", param, "Case parameter to optimise")->required();
  noa->add_option("--from", from, "Lower end of the interval")->required();
  noa->add_option("--to", to, "Upper end of the interval")->required();
  noa->add_option("--freq", freq, "Reference frequency [Hz] (default: peak of y_max at --from)")
      ->check(Positive());
  noa->add_option("--noa-objective", noa_objective,
                  "Outer objective: eta-gap (paper) or one-minus-r")
      ->check(CLI::IsMember({"eta-gap", "one-minus-r"}));
  noa->add_option("--sweep-steps", sweep_steps, "Steps of the manual sweep run for comparison")
      ->check(CLI::Range(2, 100000));
  noa->add_option("--scan-points", scan_points, "Values of the global scan (default 9)")
      ->check(CLI::Range(3, 100000));
  noa->add_flag("--no-sweep", no_sweep, "Skip the manual-sweep cost comparison");
  noa->add_option("--threads", threads,
                  "Worker threads over the scan's values and the comparison sweep's (0: every "
                  "core this process may use; same result for any)")
      ->check(CLI::Range(0, 4096));
}

void DesignCommands::State::RegisterVerify(CLI::App& app) {
  verify = app.add_subcommand("verify", "Certify the bounds: alpha sampling and time integration");
  verify_case.Register(verify);
  RegisterCommon(verify);
  verify->add_option("--freq", freq, "Frequency [Hz]")->required()->check(Positive());
  verify
      ->add_option("--alpha-samples", samples,
                   "Uniform alpha samples after the structured ones (the box's corners first "
                   "where it has fewer than 20 alpha; default 200)")
      ->check(CLI::Range(1, 1000000));
  verify->add_option("--time-runs", ti_runs, "Time integrations from different initial states")
      ->check(CLI::Range(0, 1000));
  verify
      ->add_option("--threads", threads,
                   "Worker threads over the bounds, alpha samples and time integrations (0: every "
                   "core this process may use; same result for any)")
      ->check(CLI::Range(0, 4096));
  TimeIntegrationOptions& to = time_options;
  // At the FE cascade's resonance (1100 Hz) the runs settle after 4700-4900 periods.
  to.max_periods = 8000;
  verify->add_option("--time-steps", to.steps_per_period, "Time steps per period (default 256)")
      ->check(CLI::Range(8, 100000));
  verify
      ->add_option("--time-ramp", to.ramp_periods,
                   "Periods over which the harmonic loads are ramped in (default: 20 for lumped "
                   "models, 300 with a smooth ramp for FE models)")
      ->check(CLI::Range(0, 1000000));
  verify
      ->add_option("--time-max-periods", to.max_periods,
                   "Periods after which a run that has not settled stops (default 8000)")
      ->check(CLI::Range(1, 10000000));
  verify
      ->add_option("--time-tolerance", to.steady_tolerance,
                   "Steady when the amplitude changes less than this, relative (default: 1e-6 "
                   "lumped, 1e-4 FE)")
      ->check(CLI::Range(1e-12, 0.1));
  verify
      ->add_option("--time-cutoff", to.modal_cutoff_factor,
                   "Implicit scheme (FE models): modes up to this multiple of --freq are "
                   "integrated, the rest quasi-static (default 20)")
      ->check(CLI::Range(1.0, 1e9));
}

void DesignCommands::Register(CLI::App& app) {
  state_->RegisterBounds(app);
  state_->RegisterSweep(app);
  state_->RegisterNoa(app);
  state_->RegisterVerify(app);
}

int DesignCommands::Run() {
  State& s = *state_;
  if (*s.bounds) return s.RunBounds();
  if (*s.sweep) return s.RunSweep();
  if (*s.noa) return s.RunNoa();
  if (*s.verify) return s.RunVerify();
  return -1;
}

// -------------------------------------------------------------------------------------- sweep
int DesignCommands::State::RunSweep() {
  const auto t0 = std::chrono::steady_clock::now();
  const Case c0 = sweep_case.Load({{param, from}});  // also checks that the parameter exists
  const BoundsOptions bo = MakeBoundsOptions(c0);
  int solves = 0;
  SweepOptions so;
  so.bounds = bo;
  so.levels = MakeLevelOptions(c0);
  so.track_peak = track_peak;
  so.search.lo_hz = c0.analysis.freq_min_hz;
  so.search.hi_hz = c0.analysis.freq_max_hz;
  so.search.scan_points = 21;
  // Ipopt (through MUMPS) is not known to be safe on concurrent threads: one thread for it.
  so.threads = bo.method == BoundsOptions::kReducedSpace ? threads : 1;
  if (!track_peak) {
    // Under MPI, rank 0 locates the reference (possibly a peak search) and shares it.
    const double f = MpiRank() == 0 ? ReferenceFrequency(c0, bo, &solves) : 0.0;
    so.reference_freq_hz = BroadcastFromRoot(f);
  }
  std::vector<double> values;
  for (int i = 0; i < steps; ++i) values.push_back(from + (to - from) * i / (steps - 1));
  const BalanceFactory factory = [&](double p) {
    return MakeCaseBalance(sweep_case.Load({{param, p}}));
  };
  // Units of work are the values (threads or MPI ranks); rank 0 journals and writes.
  const fs::path dir = MpiRank() == 0 ? OutDir(c0, "sweep_" + param) : fs::path();
  const fs::path h5p = dir / "sweep.h5", csvp = dir / "sweep.csv";
  Progress progress{ShowProgress(), "sweep " + param};
  double wall = 0.0;
  const SweepUnitsRun run = RunSweepUnits(
      dir,
      JournalHeader("sweep", sweep_case,
                    {{"param", param},
                     {"values", values},
                     {"reference_freq_hz", so.reference_freq_hz},
                     {"track_peak", track_peak}}),
      resume, c0.model, values, so, factory, progress, [&](const SweepUnitsRun& r) {
        progress.Done();
        solves += 2 * r.columns.bound_solves;
        wall = Seconds(t0);
        WriteSweepFiles(c0, param, values, r.columns, track_peak ? NAN : so.reference_freq_hz, wall,
                        solves, {h5p, csvp});
        WriteManifest(dir, "sweep", {h5p, csvp});
      });
  if (run.worker) return 0;
  const SweepColumns& cols = run.columns;
  const int computed = run.computed, resumed = run.resumed;
  const bool ranks = MpiSize() > 1;
  const auto& [r, ymin, ymax, emin, emax, fr, st, states_min, states_max, mixed_min, mixed_max,
               unit_solves] = cols;
  if (plot) Plot("plot_sweep.py", {h5p.string(), (dir / "sweep.png").string()});
  bool ok = true;
  for (const std::string& x : st) ok = ok && x == "converged";
  if (as_json) {
    json j;
    j["param"] = param;
    j["values"] = values;
    json rj = json::array();
    for (double x : r) rj.push_back(Num(x));
    j["robustness"] = rj;
    j["y_min"] = ymin;
    j["y_max"] = ymax;
    j["freq_hz"] = fr;
    j["status"] = st;
    j["states_at_min"] = states_min;
    j["states_at_max"] = states_max;
    j["mixed_configuration_at_min"] = mixed_min;
    j["mixed_configuration_at_max"] = mixed_max;
    j["reference_freq_hz"] = track_peak ? json(nullptr) : json(so.reference_freq_hz);
    j["inner_solves"] = solves;
    j["units"] = {{"total", steps},
                  {"computed", computed},
                  {"resumed", resumed},
                  {"threads", ranks ? 1 : WorkerThreads(so.threads, steps - resumed)},
                  {"ranks", MpiSize()}};
    j["wall_s"] = wall;
    j["files"] = {{"hdf5", h5p.string()}, {"csv", csvp.string()}};
    std::cout << j.dump() << "\n";
  } else if (!quiet) {
    if (resumed > 0)
      std::cout << "Resumed: " << resumed << " of " << steps << " values from the journal\n";
    std::cout << "Robustness over " << param << " in [" << from << ", " << to << "], " << steps
              << " values, "
              << (track_peak ? std::string("at the peak of y_max")
                             : "at " + std::to_string(so.reference_freq_hz) + " Hz")
              << ": " << std::setprecision(3) << wall << " s, " << solves
              << " inner bound solves\n";
    for (size_t i = 0; i < values.size(); ++i) {
      std::cout << "  " << param << " = " << std::setw(8) << values[i] << "  R = " << r[i] << "\n";
    }
    std::cout << "  wrote " << h5p.string() << ", " << csvp.string() << "\n";
  }
  return ok ? 0 : 1;
}

// ---------------------------------------------------------------------------------------- noa
namespace {

// The keys of `fricrom noa --json` (and OUT/noa.json).
json NoaJson(const NoaResult& res, const std::string& param, const std::string& objective,
             const NoaOptions& no, int ref_solves, const json& sweep_json, double wall,
             bool ranks) {
  json j;
  j["param"] = param;
  j["p_opt"] = res.p_opt;
  j["R_opt"] = Num(res.robustness);
  j["eta1"] = res.eta1;
  j["eta2"] = res.eta2;
  j["objective"] = objective;
  j["objective_value"] = Num(res.objective);
  j["outer_iterations"] = res.outer_iterations;
  j["inner_solves"] = res.inner_solves;
  j["wall_s"] = res.wall_s;
  j["reference_freq_hz"] = no.inner.reference_freq_hz;
  j["reference_search_solves"] = ref_solves;
  j["converged"] = res.converged;
  j["message"] = res.message;
  json hist = json::array();
  for (const RobustnessPoint& h : res.history)
    hist.push_back({{"p", h.parameter}, {"R", Num(h.robustness)}});
  j["history"] = hist;
  j["manual_sweep"] = sweep_json;
  j["total_wall_s"] = wall;
  j["units"] = {{"scan", no.scan_points},
                {"threads", ranks ? 1 : WorkerThreads(no.inner.threads, no.scan_points)},
                {"ranks", MpiSize()}};
  return j;
}

}  // namespace

int DesignCommands::State::RunNoa() {
  const auto t0 = std::chrono::steady_clock::now();
  const Case c0 = noa_case.Load({{param, from}});
  const BoundsOptions bo = MakeBoundsOptions(c0);
  int ref_solves = 0;
  NoaOptions no;
  no.lower = from;
  no.upper = to;
  no.objective =
      noa_objective == "one-minus-r" ? NoaOptions::kOneMinusR : NoaOptions::kLossFactorGap;
  no.scan_points = scan_points;
  no.inner.bounds = bo;
  no.inner.levels = MakeLevelOptions(c0);
  // Under MPI, rank 0 locates the reference (possibly a peak search) and shares it.
  const double f = MpiRank() == 0 ? ReferenceFrequency(c0, bo, &ref_solves) : 0.0;
  no.inner.reference_freq_hz = BroadcastFromRoot(f);
  // Ipopt (through MUMPS) is not known to be safe on concurrent threads: one thread for it.
  no.inner.threads = bo.method == BoundsOptions::kReducedSpace ? threads : 1;
  const BalanceFactory factory = [&](double p) {
    return MakeCaseBalance(noa_case.Load({{param, p}}));
  };
  // The scan's values and the comparison sweep's are independent units (threads or MPI ranks);
  // the refinement in between runs in order on rank 0.
  std::vector<double> sweep_values;
  for (int i = 0; i < sweep_steps; ++i)
    sweep_values.push_back(from + (to - from) * i / (sweep_steps - 1));
  SweepOptions one = no.inner;
  one.threads = 1;
  const auto unit_of = [&](const std::vector<double>& values) {
    return std::function<std::string(int)>([&, values](int i) {
      return RobustnessRecord(SweepRobustness(factory, {values[i]}, one).front()).dump();
    });
  };
  const bool ranks = MpiSize() > 1;
  if (ranks && MpiRank() != 0) {
    DistributeUnits({}, unit_of(NoaScanValues(no)), {});
    if (!no_sweep) DistributeUnits({}, unit_of(sweep_values), {});
    return 0;
  }
  Progress progress{ShowProgress(), "noa " + param};
  const auto on_ranks = [&](const std::vector<double>& values) {
    std::vector<RobustnessPoint> pts(values.size());
    std::vector<int> all(values.size());
    std::iota(all.begin(), all.end(), 0);
    int done = 0;
    DistributeUnits(all, unit_of(values), [&](int i, const std::string& text) {
      pts[i] = RobustnessFromRecord(json::parse(text));
      progress(++done, static_cast<int>(values.size()));
    });
    return pts;
  };
  if (ranks) no.scan_evaluator = on_ranks;
  const NoaResult res = fricrom::RunNoa(factory, no, progress);
  progress.Done();
  const double wall = Seconds(t0);
  json sweep_json = nullptr;
  if (!no_sweep) {
    const auto ts = std::chrono::steady_clock::now();
    const std::vector<RobustnessPoint> pts =
        ranks ? on_ranks(sweep_values) : SweepRobustness(factory, sweep_values, no.inner);
    int best = 0, solves = 0;
    for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
      solves += 2 * pts[i].bound_solves;
      if (pts[i].robustness > pts[best].robustness) best = i;
    }
    sweep_json = {{"steps", sweep_steps},
                  {"wall_s", Seconds(ts)},
                  {"inner_solves", solves},
                  {"p_best", pts[best].parameter},
                  {"R_best", Num(pts[best].robustness)}};
  }
  const fs::path dir = OutDir(c0, "noa_" + param);
  const json j = NoaJson(res, param, noa_objective, no, ref_solves, sweep_json, wall, ranks);
  WriteTextAtomically(dir / "noa.json", j.dump(2) + "\n");
  if (as_json) {
    std::cout << j.dump() << "\n";
  } else if (!quiet) {
    std::cout << res.BriefReport() << "\n  reference frequency " << no.inner.reference_freq_hz
              << " Hz\n";
    if (!sweep_json.is_null()) {
      const json& r = sweep_json["R_best"];
      std::cout << "  manual sweep of the same range (" << sweep_steps << " values, "
                << sweep_json["inner_solves"] << " inner solves, "
                << sweep_json["wall_s"].get<double>() << " s): best " << param << " = "
                << sweep_json["p_best"].get<double>()
                << ", R = " << (r.is_null() ? NAN : r.get<double>()) << "\n";
    }
    std::cout << "  wrote " << (dir / "noa.json").string() << "\n";
  }
  return res.converged ? 0 : 1;
}

}  // namespace fricrom::app
