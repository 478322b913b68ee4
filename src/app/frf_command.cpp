// `fricrom frf` (frf_command.h).
#include "app/frf_command.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/result_files.h"
#include "fricrom/case_file.h"
#include "fricrom/frf.h"
#include "fricrom/linear.h"
#include "fricrom/stability.h"
#include "fricrom/units.h"
#include "io/atomic_file.h"
#include "io/hdf5_file.h"

namespace fricrom::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The α of the FRF: the case's, or --alpha (one value per α, each in [-1, 1]).
Eigen::VectorXd FrfAlpha(const Case& c, const FrfArgs& a) {
  if (a.alpha.empty()) {
    return Eigen::Map<const Eigen::VectorXd>(c.analysis.alpha.data(), c.analysis.alpha.size());
  }
  const std::vector<double> al = ParseList(a.alpha, "--alpha");
  if (static_cast<int>(al.size()) != c.model.num_alpha()) {
    throw CLI::ValidationError("--alpha", "expected " + std::to_string(c.model.num_alpha()) +
                                              " values (one per α: per contact or α group), got " +
                                              std::to_string(al.size()));
  }
  for (double v : al) {
    if (!(std::abs(v) <= 1.0)) throw CLI::ValidationError("--alpha", "values must lie in [-1, 1]");
  }
  return Eigen::Map<const Eigen::VectorXd>(al.data(), al.size());
}

struct FrfRun {
  std::vector<FrfPoint> points;
  // Per point, with --stability / --time-check: {"stability": {...}, "time_check": {...}}.
  std::vector<json> checks;
  json summary;
  bool ok = true;
  double wall_s = 0.0;
};

// Solves at the --freq list, or traces the case's range by arclength continuation.
FrfRun SolveFrf(const Case& c, const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                const FrfArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  FrfOptions opt;
  opt.max_step = a.max_step;
  opt.initial_step = std::min(opt.initial_step, a.max_step);
  const bool show_progress = !a.quiet && !a.as_json && isatty(STDERR_FILENO);
  FrfRun run;
  if (!a.freqs.empty()) {
    const std::vector<double> f = ParseList(a.freqs, "--freq");
    for (double v : f) {
      if (!(v > 0.0)) throw CLI::ValidationError("--freq", "frequencies must be > 0 Hz");
      WarnOutsideCaseRange(c, v, "--freq");
    }
    run.points = SolveAtFrequencies(system, alpha, f, opt, [&](int done, int total) {
      if (show_progress)
        std::cerr << "\rfrf: " << done << "/" << total << " frequencies" << std::flush;
    });
    for (const FrfPoint& p : run.points) run.ok = run.ok && p.status == SolverStatus::kConverged;
    run.summary = {{"mode", "frequencies"}};
    if (show_progress) std::cerr << "\n";
  } else {
    FrfTrace tr = TraceFrf(system, alpha, c.analysis.freq_min_hz, c.analysis.freq_max_hz, opt,
                           [&](int done, int) {
                             if (show_progress && done % 10 == 0) {
                               std::cerr << "\rfrf: " << done << " points" << std::flush;
                             }
                           });
    run.points = std::move(tr.points);
    run.ok = tr.summary.IsSolutionUsable();
    run.summary = {{"mode", "continuation"},
                   {"status", ToString(tr.summary.status)},
                   {"message", tr.summary.message},
                   {"turning_points", tr.summary.turning_points},
                   {"jumps", tr.jumps},
                   {"rejected_steps", tr.summary.rejected_steps},
                   {"evaluations", tr.summary.evaluations}};
    if (!a.as_json && !a.quiet)
      std::cerr << (show_progress ? "\n" : "") << tr.summary.BriefReport() << "\n";
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

json HillJson(SolutionStability* stability, const FrfPoint& p, const Eigen::VectorXd& alpha) {
  try {
    const HillResult r = stability->At(p.x, RadPerS(p.freq_hz), alpha);
    return {{"computed", true},
            {"stable", r.stable},
            {"approximate", r.approximate()},
            {"switching_contacts", r.switching_contacts},
            {"max_floquet_real_per_s", r.max_real},
            {"note", r.message}};
  } catch (const std::domain_error& e) {
    return {{"computed", false},
            {"stable", nullptr},
            {"approximate", nullptr},
            {"switching_contacts", nullptr},
            {"max_floquet_real_per_s", nullptr},
            {"note", std::string("not computed: ") + e.what()}};
  }
}

json HoldJson(const Case& c, const HarmonicBalance& system, const FrfPoint& p,
              const Eigen::VectorXd& alpha) {
  const HoldResult h = HoldsUnderTimeIntegration(c.model, system, p.x, RadPerS(p.freq_hz), alpha);
  return {{"holds", h.holds},
          {"settled", h.settled},
          {"status", h.status},
          {"amplitude", std::isfinite(h.amplitude) ? json(h.amplitude) : json(nullptr)},
          {"periods", h.periods},
          {"wall_s", h.wall_s},
          {"message", h.message}};
}

// Hill stability and/or the time integration from every converged point (--stability,
// --time-check); points without a solution get nulls.
void CheckFrfPoints(const Case& c, const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                    const FrfArgs& a, FrfRun* run) {
  if (!a.stability && !a.time_check) return;
  const bool show_progress = !a.quiet && !a.as_json && isatty(STDERR_FILENO);
  SolutionStability stability(system);
  for (size_t i = 0; i < run->points.size(); ++i) {
    const FrfPoint& p = run->points[i];
    json j = json::object();
    const bool solved = p.status == SolverStatus::kConverged;
    if (a.stability) j["stability"] = solved ? HillJson(&stability, p, alpha) : json(nullptr);
    if (a.time_check) j["time_check"] = solved ? HoldJson(c, system, p, alpha) : json(nullptr);
    run->checks.push_back(j);
    if (show_progress) {
      std::cerr << "\rfrf: checked " << i + 1 << "/" << run->points.size() << " points"
                << std::flush;
    }
  }
  if (show_progress) std::cerr << "\n";
}

// -1 where a check is absent or was not computed, else 0/1.
int CheckFlag(const FrfRun& run, size_t i, const char* check, const char* key) {
  if (i >= run.checks.size() || !run.checks[i].contains(check)) return -1;
  const json& v = run.checks[i][check];
  if (v.is_null() || !v.contains(key) || !v[key].is_boolean()) return -1;
  return v[key].get<bool>() ? 1 : 0;
}

std::string RegimeName(const FrfPoint& p, size_t k) {
  return k < p.regimes.size() ? ToString(p.regimes[k]) : "unknown";
}

void WriteFrfHdf5(const fs::path& path, const Case& c, const HarmonicBalance& system,
                  const Eigen::VectorXd& alpha, const FrfRun& run, int linear_points) {
  // Linear references over the case range, for figures (0 points: none; on an FE assembly they
  // cost far more than a few nonlinear points).
  std::vector<double> lf(linear_points);
  for (int i = 0; i < linear_points; ++i) {
    lf[i] = c.analysis.freq_min_hz +
            (c.analysis.freq_max_hz - c.analysis.freq_min_hz) * i / (linear_points - 1);
  }
  const std::vector<double> free_amp =
      lf.empty()
          ? std::vector<double>{}
          : LinearResponseAmplitude(c.model, LinearSystemKind::kFree, lf, c.analysis.receptance);
  const std::vector<double> stick_amp =
      lf.empty()
          ? std::vector<double>{}
          : LinearResponseAmplitude(c.model, LinearSystemKind::kStick, lf, c.analysis.receptance);
  const std::vector<FrfPoint>& points = run.points;
  Hdf5Writer h5(path);
  CommonAttributes(h5, c, "frf");
  std::vector<double> f, amp;
  std::vector<int> iters;
  std::vector<std::string> status;
  Eigen::MatrixXd x(points.size(), system.num_unknowns());
  std::vector<std::string> regimes;
  for (size_t i = 0; i < points.size(); ++i) {
    f.push_back(points[i].freq_hz);
    amp.push_back(points[i].amplitude);
    iters.push_back(points[i].iterations);
    status.push_back(ToString(points[i].status));
    // A point that did not converge has no solution: NaN, not its last iterate.
    if (points[i].status == SolverStatus::kConverged) {
      x.row(i) = points[i].x.transpose();
    } else {
      x.row(i).setConstant(NAN);
    }
    for (size_t k = 0; k < c.model.contacts.size(); ++k)
      regimes.push_back(RegimeName(points[i], k));
  }
  std::vector<int> jumps;
  for (const FrfPoint& p : points) jumps.push_back(p.jump_before ? 1 : 0);
  h5.IntVector("frf/jump_before", jumps);
  h5.Vector("frf/freq_hz", f);
  h5.Vector("frf/amplitude_m", amp);
  h5.Strings("frf/status", status);
  h5.IntVector("frf/iterations", iters);
  h5.Matrix("frf/x", x);
  h5.Strings("frf/regimes", regimes);
  if (!run.checks.empty()) {
    std::vector<int> stable, holds;
    std::vector<double> growth;
    for (size_t i = 0; i < points.size(); ++i) {
      stable.push_back(CheckFlag(run, i, "stability", "stable"));
      holds.push_back(CheckFlag(run, i, "time_check", "holds"));
      const json* s = run.checks[i].contains("stability") ? &run.checks[i]["stability"] : nullptr;
      growth.push_back(s && !s->is_null() && (*s)["max_floquet_real_per_s"].is_number()
                           ? (*s)["max_floquet_real_per_s"].get<double>()
                           : NAN);
    }
    h5.IntVector("frf/stable", stable);
    h5.Vector("frf/max_floquet_real_per_s", growth);
    h5.IntVector("frf/time_holds", holds);
    h5.Attribute("frf", "checks_layout",
                 "stable, time_holds per point: 1 yes, 0 no, -1 not computed; "
                 "max_floquet_real_per_s NaN where not computed");
  }
  h5.Vector("frf/alpha", alpha);
  h5.Strings("frf/contacts", c.contact_names);
  h5.Strings("frf/dof_names", c.model.dof_names);
  h5.Attribute("frf", "x_layout",
               c.analysis.balance == BalanceKind::kCondensed
                   ? "row = point; columns = [q0 | a1 | b1 | ... | aH | bH], each block the "
                     "contacts' relative displacements (tangential and normal rows) then the "
                     "response DOF (condensed balance)"
                   : "row = point; columns = [q0 | a1 | b1 | ... | aH | bH], each block all "
                     "DOFs in dof_names order");
  h5.Attribute("frf", "regimes_layout", "flattened [point][contact]");
  std::ostringstream label;
  label << "HBM (H = " << c.analysis.harmonics << "), alpha = ";
  if (alpha.size() <= 8) {
    label << "(";
    for (int i = 0; i < alpha.size(); ++i) label << (i ? ", " : "") << alpha[i];
    label << ")";
  } else {
    label << alpha.size() << " values (frf/alpha)";
  }
  h5.Attribute("frf", "label", label.str());
  h5.Attribute("frf", "harmonics", static_cast<double>(c.analysis.harmonics));
  h5.Attribute("frf", "samples_per_period", static_cast<double>(c.analysis.samples_per_period));
  h5.Attribute("frf", "wall_s", run.wall_s);
  if (!lf.empty()) {
    h5.Vector("linear/freq_hz", lf);
    h5.Vector("linear/free_amplitude_m", free_amp);
    h5.Vector("linear/stick_amplitude_m", stick_amp);
  }
  h5.Commit();
}

void WriteFrfCsv(const fs::path& path, const Case& c, const FrfRun& run) {
  std::ostringstream csv;
  csv << "# fricrom " << Version() << " frf of " << c.name << "; units: Hz, m\n";
  csv << "freq_hz,amplitude_m,status,iterations";
  for (const std::string& n : c.contact_names) csv << ",state_" << n;
  const bool checked = !run.checks.empty();
  if (checked) csv << ",stable,time_holds";
  csv << "\n" << std::setprecision(12);
  const auto flag = [](int v) { return v < 0 ? std::string("") : std::to_string(v); };
  for (size_t i = 0; i < run.points.size(); ++i) {
    const FrfPoint& p = run.points[i];
    csv << p.freq_hz << "," << p.amplitude << "," << ToString(p.status) << "," << p.iterations;
    for (size_t k = 0; k < c.model.contacts.size(); ++k) csv << "," << RegimeName(p, k);
    if (checked) {
      csv << "," << flag(CheckFlag(run, i, "stability", "stable")) << ","
          << flag(CheckFlag(run, i, "time_check", "holds"));
    }
    csv << "\n";
  }
  WriteTextAtomically(path, csv.str());
}

struct FrfFiles {
  fs::path h5, csv, png;
  bool plotted = false;
};

void PrintFrfJson(const Case& c, const Eigen::VectorXd& alpha, const FrfRun& run,
                  const FrfFiles& files) {
  json j;
  j["case"] = c.name;
  j["units"] = {{"freq", "Hz"}, {"amplitude", "m"}};
  j["alpha"] = std::vector<double>(alpha.data(), alpha.data() + alpha.size());
  j["harmonics"] = c.analysis.harmonics;
  j["samples_per_period"] = c.analysis.samples_per_period;
  j["contacts"] = c.contact_names;
  j["summary"] = run.summary;
  j["wall_s"] = run.wall_s;
  json pts = json::array();
  for (size_t i = 0; i < run.points.size(); ++i) {
    const FrfPoint& p = run.points[i];
    json s = json::array();
    for (ContactRegime r : p.regimes) s.push_back(ToString(r));
    json point = {
        {"freq_hz", p.freq_hz},
        {"amplitude", p.status == SolverStatus::kConverged ? json(p.amplitude) : json(nullptr)},
        {"status", ToString(p.status)},
        {"iterations", p.iterations},
        {"states", s}};
    if (p.jump_before) point["jump_before"] = true;
    if (i < run.checks.size()) point.update(run.checks[i]);
    pts.push_back(point);
  }
  j["points"] = pts;
  j["files"] = {{"hdf5", files.h5.string()}, {"csv", files.csv.string()}};
  if (files.plotted) j["files"]["figure"] = files.png.string();
  std::cout << j.dump() << "\n";
}

// Per checked point: Hill's verdict and the time integration's, on a line each.
void PrintFrfChecks(const FrfRun& run) {
  if (run.checks.size() > 20) {
    int counts[3] = {0, 0, 0};  // not computed, unstable, stable
    for (size_t i = 0; i < run.checks.size(); ++i)
      ++counts[CheckFlag(run, i, "stability", "stable") + 1];
    std::cout << "  Hill stability: " << counts[2] << " stable, " << counts[1] << " unstable, "
              << counts[0] << " not computed of " << run.checks.size() << " points\n";
    return;
  }
  for (size_t i = 0; i < run.checks.size(); ++i) {
    const json& j = run.checks[i];
    std::ostringstream line;
    line << std::fixed << std::setprecision(3) << run.points[i].freq_hz << " Hz:";
    if (j.contains("stability")) {
      const json& h = j["stability"];
      if (h.is_null()) {
        line << " no solution";
      } else if (!h["computed"].get<bool>()) {
        line << " Hill " << h["note"].get<std::string>();
      } else {
        line << " Hill " << (h["stable"].get<bool>() ? "stable" : "UNSTABLE")
             << (h["approximate"].get<bool>() ? " (approximate: stick-slip)" : "")
             << " (largest Re " << std::scientific << std::setprecision(3)
             << h["max_floquet_real_per_s"].get<double>() << " 1/s)";
      }
    }
    if (j.contains("time_check") && !j["time_check"].is_null()) {
      const json& t = j["time_check"];
      line << "; time integration " << (t["holds"].get<bool>() ? "stays" : "leaves") << " ("
           << t["status"].get<std::string>() << ", " << t["periods"].get<int>() << " periods, "
           << std::fixed << std::setprecision(1) << t["wall_s"].get<double>() << " s)";
    }
    std::cout << "  " << line.str() << "\n";
  }
}

void PrintFrfText(const Case& c, const Eigen::VectorXd& alpha, const FrfRun& run,
                  const FrfFiles& files) {
  const std::vector<FrfPoint>& points = run.points;
  std::cout << "FRF of " << c.name << " (alpha =";
  for (int i = 0; i < alpha.size(); ++i) std::cout << (i ? ", " : " ") << alpha[i];
  std::cout << "), H = " << c.analysis.harmonics << ", " << c.analysis.samples_per_period
            << " samples/period: " << points.size() << " points in " << std::setprecision(3)
            << run.wall_s << " s\n";
  double peak = NAN, fpeak = NAN;
  for (const FrfPoint& p : points) {
    if (p.status == SolverStatus::kConverged && !(p.amplitude <= peak)) {
      peak = p.amplitude;
      fpeak = p.freq_hz;
    }
  }
  if (std::isnan(peak)) {
    std::cout << "  no point converged: no peak amplitude\n";
  } else {
    std::cout << "  peak amplitude of " << c.model.dof_names[c.model.response_dof] << ": "
              << std::scientific << peak << " m at " << std::fixed << std::setprecision(2) << fpeak
              << " Hz\n";
  }
  if (points.size() <= 20) {
    for (const FrfPoint& p : points) {
      std::cout << "  " << std::fixed << std::setprecision(3) << p.freq_hz << " Hz  "
                << std::scientific << std::setprecision(6) << p.amplitude << " m  "
                << ToString(p.status);
      for (ContactRegime r : p.regimes) std::cout << "  " << ToString(r);
      std::cout << "\n";
    }
  }
  PrintFrfChecks(run);
  std::cout << "  wrote " << files.h5.string() << ", " << files.csv.string();
  if (files.plotted) std::cout << ", " << files.png.string();
  std::cout << "\n";
}

}  // namespace

CLI::App* RegisterFrf(CLI::App& app, CaseArgs* cargs, FrfArgs* a) {
  CLI::App* f = app.add_subcommand("frf", "Nonlinear forced response at fixed alpha (HBM/AFT)");
  cargs->Register(f);
  f->add_option("--alpha", a->alpha,
                "Initial tangential force coefficients, one per contact: a1,a2,...");
  f->add_option("--freq", a->freqs,
                "Solve at these frequencies [Hz] (comma list) instead of tracing the range");
  f->add_option("--out", a->out, "Output directory (default results/<case name>)");
  f->add_option("--max-step", a->max_step, "Largest continuation step (scaled arclength)")
      ->check(Positive());
  f->add_flag("--json", a->as_json, "Print one JSON object on stdout");
  f->add_flag("--plot", a->plot, "Draw the FRF figure (PNG) with the linear references");
  f->add_flag("--linear-references", a->linear_references,
              "Also write the linear free and full-stick response over the case range (400 "
              "points) into frf.h5, as --plot does");
  f->add_flag("--normalise", a->normalise, "Normalise the figure by the full-stick peak");
  f->add_flag("--quiet", a->quiet, "Print nothing but errors");
  f->add_flag("--stability", a->stability,
              "Hill stability (Floquet exponents) of every converged point; unstable stretches "
              "are dashed in the figure");
  f->add_flag("--time-check", a->time_check,
              "Integrate in time from every converged point (implicit modal scheme, up to 150 "
              "periods) and say whether the motion stays on it; slow, meant for --freq lists");
  return f;
}

int RunFrf(const CaseArgs& cargs, const FrfArgs& a) {
  const Case c = cargs.Load();
  const Eigen::VectorXd alpha = FrfAlpha(c, a);
  const auto balance = MakeCaseBalance(c);
  FrfRun run = SolveFrf(c, *balance, alpha, a);
  CheckFrfPoints(c, *balance, alpha, a, &run);

  const fs::path out_dir = a.out.empty() ? fs::path("results") / c.name : fs::path(a.out);
  fs::create_directories(out_dir);
  FrfFiles files{out_dir / "frf.h5", out_dir / "frf.csv", out_dir / "frf.png"};
  WriteFrfHdf5(files.h5, c, *balance, alpha, run,
               a.plot || a.linear_references ? a.linear_points : 0);
  WriteFrfCsv(files.csv, c, run);
  if (a.plot) {
    const std::string cmd = "/usr/bin/python3 '" + std::string(FRICROM_SOURCE_DIR) +
                            "/scripts/plot_frf.py' '" + files.h5.string() + "' '" +
                            files.png.string() + "'" + (a.normalise ? " --normalise" : "") +
                            " 1>&2";  // stdout is for --json
    files.plotted = std::system(cmd.c_str()) == 0;
    if (!files.plotted) std::cerr << "frf: figure not written (see the message above)\n";
  }
  std::vector<fs::path> written = {files.h5, files.csv};
  if (files.plotted) written.push_back(files.png);
  WriteManifest(out_dir, "frf", written);
  if (a.as_json) {
    PrintFrfJson(c, alpha, run, files);
  } else if (!a.quiet) {
    PrintFrfText(c, alpha, run, files);
  }
  return run.ok ? 0 : 1;
}

}  // namespace fricrom::app
