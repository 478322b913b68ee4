#include "app/commands.h"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
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
#include "app/frf_command.h"
#include "app/mpi_units.h"
#include "app/reduce_commands.h"
#include "app/result_files.h"
#include "fricrom/blas_core.h"
#include "fricrom/blas_threads.h"
#include "fricrom/case_file.h"
#include "fricrom/cyclic.h"
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
// A cyclic sector: the free system's frequencies (the same at every nodal diameter: the rigid
// disk couples the sectors only through the dampers) and the full-stick ones per nodal diameter.
int RunCyclicModes(const Case& c, bool as_json, int count) {
  const ModalResult free = FreeSystemModes(c.model);
  const CyclicSymmetry& cyc = c.model.cyclic;
  std::vector<Eigen::VectorXd> stick;
  for (int nd = 0; nd <= cyc.sectors / 2; ++nd) {
    stick.push_back(CyclicNaturalFrequencies(c.model, nd, true));
  }
  std::vector<int> harmonic_nd;
  for (int h = 1; h <= c.analysis.harmonics; ++h)
    harmonic_nd.push_back(NodalDiameterOfHarmonic(cyc, h));
  if (as_json) {
    json j;
    j["case"] = c.name;
    j["units"] = "Hz";
    j["sectors"] = cyc.sectors;
    j["engine_order"] = cyc.engine_order;
    j["harmonic_nodal_diameters"] = harmonic_nd;
    j["free_hz"] = std::vector<double>(free.frequencies_hz.data(),
                                       free.frequencies_hz.data() + free.frequencies_hz.size());
    json per_nd = json::array();
    for (size_t nd = 0; nd < stick.size(); ++nd) {
      per_nd.push_back({{"nodal_diameter", nd},
                        {"stick_hz", std::vector<double>(stick[nd].data(),
                                                         stick[nd].data() + stick[nd].size())}});
    }
    j["stick_by_nodal_diameter"] = per_nd;
    std::cout << j.dump() << "\n";
    return 0;
  }
  const int total = static_cast<int>(stick[0].size());
  const int shown = count > 0 ? std::min(count, total) : total;
  std::cout << "Natural frequencies of " << c.name << " [Hz], one sector of " << cyc.sectors
            << " (engine order " << cyc.engine_order << ": harmonic 1 at nodal diameter "
            << harmonic_nd[0] << ")\n";
  std::cout << "  free system (every nodal diameter):";
  for (int i = 0; i < std::min<int>(shown, static_cast<int>(free.frequencies_hz.size())); ++i) {
    std::cout << " " << std::fixed << std::setprecision(2) << free.frequencies_hz[i];
  }
  std::cout << "\n  full stick by nodal diameter:\n  mode";
  for (size_t nd = 0; nd < stick.size(); ++nd)
    std::cout << std::setw(10) << ("ND " + std::to_string(nd));
  std::cout << "\n";
  for (int i = 0; i < shown; ++i) {
    std::cout << "  " << std::setw(4) << i + 1;
    for (const Eigen::VectorXd& f : stick)
      std::cout << std::setw(10) << std::fixed << std::setprecision(2) << f[i];
    std::cout << "\n";
  }
  if (shown < total) {
    std::cout << "  ... " << total - shown
              << " more per nodal diameter (--count 0 lists every one; --json has them all)\n";
  }
  return 0;
}

int RunModes(const CaseArgs& args, bool as_json, int count) {
  const Case c = args.Load();
  if (c.model.cyclic.sectors > 0) return RunCyclicModes(c, as_json, count);
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
  const int total = static_cast<int>(stick.frequencies_hz.size());
  const int shown = count > 0 ? std::min(count, total) : total;
  for (int i = 0; i < shown; ++i) {
    std::cout << "  " << std::setw(4) << i + 1 << "  ";
    if (i < free.frequencies_hz.size()) {
      std::cout << std::setw(9) << std::fixed << std::setprecision(2) << free.frequencies_hz[i];
    } else {
      std::cout << std::setw(9) << "";
    }
    std::cout << "  " << std::setw(11) << std::fixed << std::setprecision(2)
              << stick.frequencies_hz[i] << "\n";
  }
  if (shown < total) {
    std::cout << "  ... " << total - shown
              << " more full-stick modes (--count 0 lists every one; --json has them all)\n";
  }
  if (free.massless + stick.massless > 0) {
    std::cout << "  directions without mass (a semi-definite mass; no finite frequency): "
              << free.massless << " free, " << stick.massless << " full-stick\n";
  }
  return 0;
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
  int modes_count = 20;
  FrfArgs fa;
  std::string export_dir, lump_to;
  CLI::App *modes = nullptr, *frf = nullptr, *casecmd = nullptr, *exportcmd = nullptr,
           *lumpcmd = nullptr;

  void Register(CLI::App& app) {
    modes = app.add_subcommand("modes", "Natural frequencies of the free and full-stick systems");
    modes_args.Register(modes);
    modes->add_flag("--json", modes_json, "Print one JSON object on stdout");
    modes
        ->add_option("--count", modes_count,
                     "Modes listed in the text output (default 20; 0: every mode; --json has all)")
        ->check(CLI::NonNegativeNumber);

    frf = RegisterFrf(app, &frf_args, &fa);

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
    if (*modes) return RunModes(modes_args, modes_json, modes_count);
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
