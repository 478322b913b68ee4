#include "app/commands.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "app/cli_common.h"
#include "app/design_commands.h"
#include "app/fe_commands.h"
#include "app/mpi_units.h"
#include "app/reduce_commands.h"
#include "app/result_files.h"
#include "fricrom/blas_core.h"
#include "fricrom/blas_threads.h"
#include "fricrom/case_file.h"
#include "fricrom/fe_model.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/linear.h"
#include "fricrom/lumped_calibration.h"
#include "io/atomic_file.h"
#include "io/hdf5_file.h"

namespace fricrom::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// ---------------------------------------------------------------- modes
int RunModes(const CaseArgs& args, bool as_json) {
  const Case c = args.Load();
  const ModalResult free = FreeSystemModes(c.model);
  const ModalResult stick = StickSystemModes(c.model);
  if (as_json) {
    json j;
    j["case"] = c.name;
    j["units"] = "Hz";
    j["free_hz"] = std::vector<double>(free.frequencies_hz.data(),
                                       free.frequencies_hz.data() + free.frequencies_hz.size());
    j["stick_hz"] = std::vector<double>(stick.frequencies_hz.data(),
                                        stick.frequencies_hz.data() + stick.frequencies_hz.size());
    j["free_dofs"] = free.frequencies_hz.size();
    j["stick_dofs"] = stick.frequencies_hz.size();
    j["free_massless"] = free.massless;
    j["stick_massless"] = stick.massless;
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << "Natural frequencies of " << c.name << " [Hz]\n";
  std::cout << "  mode       free   full-stick\n";
  for (int i = 0; i < stick.frequencies_hz.size(); ++i) {
    std::cout << "  " << std::setw(4) << i + 1 << "  ";
    if (i < free.frequencies_hz.size()) {
      std::cout << std::setw(9) << std::fixed << std::setprecision(2) << free.frequencies_hz[i];
    } else {
      std::cout << std::setw(9) << "";
    }
    std::cout << "  " << std::setw(11) << std::fixed << std::setprecision(2)
              << stick.frequencies_hz[i] << "\n";
  }
  if (free.massless + stick.massless > 0) {
    std::cout << "  directions without mass (a semi-definite mass; no finite frequency): "
              << free.massless << " free, " << stick.massless << " full-stick\n";
  }
  return 0;
}

// ---------------------------------------------------------------- frf
struct FrfArgs {
  std::string alpha;
  std::string freqs;
  std::string out;
  bool as_json = false;
  bool plot = false;
  bool normalise = false;
  bool quiet = false;
  double max_step = 0.02;
  int linear_points = 400;
  bool linear_references = false;  // the figure's reference curves without a figure
};

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
                   {"rejected_steps", tr.summary.rejected_steps},
                   {"evaluations", tr.summary.evaluations}};
    if (!a.as_json && !a.quiet)
      std::cerr << (show_progress ? "\n" : "") << tr.summary.BriefReport() << "\n";
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
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
  h5.Vector("frf/freq_hz", f);
  h5.Vector("frf/amplitude_m", amp);
  h5.Strings("frf/status", status);
  h5.IntVector("frf/iterations", iters);
  h5.Matrix("frf/x", x);
  h5.Strings("frf/regimes", regimes);
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
  label << "HBM (H = " << c.analysis.harmonics << "), alpha = (";
  for (int i = 0; i < alpha.size(); ++i) label << (i ? ", " : "") << alpha[i];
  label << ")";
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
  csv << "\n" << std::setprecision(12);
  for (const FrfPoint& p : run.points) {
    csv << p.freq_hz << "," << p.amplitude << "," << ToString(p.status) << "," << p.iterations;
    for (size_t k = 0; k < c.model.contacts.size(); ++k) csv << "," << RegimeName(p, k);
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
  for (const FrfPoint& p : run.points) {
    json s = json::array();
    for (ContactRegime r : p.regimes) s.push_back(ToString(r));
    pts.push_back({{"freq_hz", p.freq_hz},
                   {"amplitude", p.amplitude},
                   {"status", ToString(p.status)},
                   {"iterations", p.iterations},
                   {"states", s}});
  }
  j["points"] = pts;
  j["files"] = {{"hdf5", files.h5.string()}, {"csv", files.csv.string()}};
  if (files.plotted) j["files"]["figure"] = files.png.string();
  std::cout << j.dump() << "\n";
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
  std::cout << "  wrote " << files.h5.string() << ", " << files.csv.string();
  if (files.plotted) std::cout << ", " << files.png.string();
  std::cout << "\n";
}

int RunFrf(const CaseArgs& cargs, const FrfArgs& a) {
  const Case c = cargs.Load();
  const Eigen::VectorXd alpha = FrfAlpha(c, a);
  const auto balance = MakeCaseBalance(c);
  const FrfRun run = SolveFrf(c, *balance, alpha, a);

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

// ---------------------------------------------------------------- case (dry run)
int RunCase(const CaseArgs& args) {
  const Case c = args.Load();
  std::cout << "# resolved case '" << c.name << "' from " << c.source << " (units: SI)\n"
            << c.resolved << "\n";
  std::cout << "# " << c.model.num_dofs() << " DOFs, " << c.model.contacts.size()
            << " contacts, H = " << c.analysis.harmonics << ", " << c.analysis.samples_per_period
            << " samples/period\n";
  return 0;
}

}  // namespace

// `fricrom lump`: the lumped case calibrated from an FE cascade, written atomically.
int RunLump(const CaseArgs& args, const std::string& to, bool as_json) {
  const Case fe = args.Load();
  const LumpedCalibration l = CalibrateLumped(fe);
  WriteTextAtomically(to, l.toml);
  if (as_json) {
    json j = {{"case", fe.source},
              {"lumped_case", to},
              {"response_blade", l.response_blade},
              {"response_scale", l.response_scale},
              {"units", "SI"}};
    for (const LumpedBlade& b : l.blades) {
      j["blades"].push_back({{"name", b.name},
                             {"mode", b.mode + 1},
                             {"mode_hz", b.mode_hz},
                             {"modal_mass_kg", b.modal_mass},
                             {"k_circumferential_n_per_m", b.k_circumferential},
                             {"k_radial_n_per_m", b.k_radial},
                             {"damping_ratio", b.damping_ratio},
                             {"force_cos_n", b.force_cos},
                             {"force_sin_n", b.force_sin}});
    }
    for (const LumpedDamper& d : l.dampers) {
      j["dampers"].push_back({{"name", d.name},
                              {"mass_kg", d.mass},
                              {"preload_n", d.preload},
                              {"ground_stiffness_n_per_m", d.ground_stiffness}});
    }
    for (const LumpedContact& c : l.contacts) {
      j["contacts"].push_back({{"name", c.name},
                               {"damper", c.damper},
                               {"blade", c.counterpart},
                               {"face", c.left_face ? "left" : "right"},
                               {"theta_rad", c.theta},
                               {"kn_n_per_m", c.kn},
                               {"kt_n_per_m", c.kt},
                               {"mu", c.mu},
                               {"pairs", c.pairs}});
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "Lumped model of " << fe.source << " -> " << to << " (SI units)\n";
  for (const LumpedBlade& b : l.blades) {
    std::cout << "  " << b.name << ": mode " << b.mode + 1 << " at " << b.mode_hz
              << " Hz, platform mass " << b.modal_mass << " kg, k_circ " << b.k_circumferential
              << " N/m, k_rad " << b.k_radial << " N/m, zeta " << b.damping_ratio << ", force "
              << b.force_cos << " N\n";
  }
  for (const LumpedDamper& d : l.dampers) {
    std::cout << "  " << d.name << ": mass " << d.mass << " kg, preload " << d.preload << " N\n";
  }
  for (const LumpedContact& c : l.contacts) {
    std::cout << "  " << c.name << " (" << c.damper << " " << (c.left_face ? "left" : "right")
              << " face on " << c.counterpart << ", " << c.pairs << " pairs): theta " << c.theta
              << " rad, kn " << c.kn << " N/m, kt " << c.kt << " N/m, mu " << c.mu << "\n";
  }
  std::cout << "  response: " << l.response_blade << ".x x " << l.response_scale
            << " (the FE response point per unit platform motion; DOFs scaled by it)\n";
  return 0;
}

namespace {

// The commands of this file (modes, frf, case, export-fe, lump): their arguments, registration
// and dispatch.
struct BasicCommands {
  CaseArgs modes_args, frf_args, case_args, export_args, lump_args;
  bool modes_json = false, lump_json = false;
  FrfArgs fa;
  std::string export_dir, lump_to;
  CLI::App *modes = nullptr, *frf = nullptr, *casecmd = nullptr, *exportcmd = nullptr,
           *lumpcmd = nullptr;

  void Register(CLI::App& app) {
    modes = app.add_subcommand("modes", "Natural frequencies of the free and full-stick systems");
    modes_args.Register(modes);
    modes->add_flag("--json", modes_json, "Print one JSON object on stdout");

    frf = app.add_subcommand("frf", "Nonlinear forced response at fixed alpha (HBM/AFT)");
    frf_args.Register(frf);
    frf->add_option("--alpha", fa.alpha,
                    "Initial tangential force coefficients, one per contact: a1,a2,...");
    frf->add_option("--freq", fa.freqs,
                    "Solve at these frequencies [Hz] (comma list) instead of tracing the range");
    frf->add_option("--out", fa.out, "Output directory (default results/<case name>)");
    frf->add_option("--max-step", fa.max_step, "Largest continuation step (scaled arclength)")
        ->check(Positive());
    frf->add_flag("--json", fa.as_json, "Print one JSON object on stdout");
    frf->add_flag("--plot", fa.plot, "Draw the FRF figure (PNG) with the linear references");
    frf->add_flag("--linear-references", fa.linear_references,
                  "Also write the linear free and full-stick response over the case range (400 "
                  "points) into frf.h5, as --plot does");
    frf->add_flag("--normalise", fa.normalise, "Normalise the figure by the full-stick peak");
    frf->add_flag("--quiet", fa.quiet, "Print nothing but errors");

    casecmd = app.add_subcommand("case", "Validate a case file and print it resolved (dry run)");
    case_args.Register(casecmd);
    exportcmd = app.add_subcommand(
        "export-fe",
        "Write a lumped case as an FE assembly case (Matrix Market bodies, node pairs)");
    export_args.Register(exportcmd);
    exportcmd->add_option("--to", export_dir, "Output directory")->required();

    lumpcmd = app.add_subcommand(
        "lump", "Write a lumped 3-blade/2-damper case calibrated from an FE cascade assembly");
    lump_args.Register(lumpcmd);
    lumpcmd->add_option("--to", lump_to, "Lumped case file to write (TOML)")->required();
    lumpcmd->add_flag("--json", lump_json, "Print the calibration as JSON");
  }

  // The exit code of the command given, or −1 if it is none of these.
  int Run() {
    if (*modes) return RunModes(modes_args, modes_json);
    if (*frf) return RunFrf(frf_args, fa);
    if (*casecmd) return RunCase(case_args);
    if (*exportcmd) {
      std::cout << "wrote " << ExportAssembly(export_args.Load(), export_dir) << "\n";
      return 0;
    }
    if (*lumpcmd) return RunLump(lump_args, lump_to, lump_json);
    return -1;
  }
};

}  // namespace

int Run(int argc, char** argv) {
  CLI::App app{"fricrom " + Version() +
               ": forced-response bounds of bladed assemblies with friction contacts"};
  app.require_subcommand(1);
  app.set_version_flag("--version",
                       Version() + " (" + InstructionSet() + "; BLAS: " + BlasCoreReport() + ")");

  BasicCommands basic;
  basic.Register(app);
  DesignCommands design;
  design.Register(app);
  FeCommands fe;
  fe.Register(app);
  ReduceCommands reduce;
  reduce.Register(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "fricrom: error: " << e.what() << "\nRun with --help for more information.\n";
    return 2;
  }
  if (MpiSize() > 1 && !app.got_subcommand("sweep") && !app.got_subcommand("bounds") &&
      !app.got_subcommand("verify") && !app.got_subcommand("noa")) {
    std::cerr << "fricrom: error: only `sweep`, `bounds`, `verify` and `noa` distribute their "
                 "work over MPI ranks; run this command without mpirun (or with -np 1)\n";
    return 2;
  }
  // One BLAS thread for the harmonic-balance commands (fricrom/blas_threads.h says why); the
  // Craig-Bampton reduction keeps OpenBLAS's default, and the environment always wins.
  if (!app.got_subcommand("reduce") && std::getenv("OPENBLAS_NUM_THREADS") == nullptr) {
    SetBlasThreads(1);
  }
  try {
    const int basic_rc = basic.Run();
    if (basic_rc >= 0) return basic_rc;
    const int rc = design.Run();
    if (rc >= 0) return rc;
    const int fe_rc = fe.Run();
    if (fe_rc >= 0) return fe_rc;
    const int reduce_rc = reduce.Run();
    if (reduce_rc >= 0) return reduce_rc;
  } catch (const NotConverged& e) {
    std::cerr << "fricrom: not converged: " << e.what() << "\n";
    return 1;
  } catch (const FeReadError& e) {
    std::cerr << "fricrom: error: " << e.what() << "\n";
    return 2;
  } catch (const CaseError& e) {
    std::cerr << "fricrom: error: " << e.what() << "\n";
    return 2;
  } catch (const CLI::ValidationError& e) {
    std::cerr << "fricrom: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fricrom: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace fricrom::app
