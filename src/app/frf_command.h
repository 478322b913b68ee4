// `fricrom frf`: the forced response at fixed α — a continuation over the case's range or solves
// at given frequencies — with, on request, the Hill stability of every point and the time
// integration from each solution.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "app/cli_common.h"

namespace fricrom::app {

struct FrfArgs {
  std::string alpha;
  std::string freqs;
  std::string out;
  bool as_json = false;
  bool plot = false;
  bool normalise = false;
  bool quiet = false;
  bool stability = false;   // Hill stability of every converged point
  bool time_check = false;  // time integration from every converged point
  double max_step = 0.02;
  int linear_points = 400;
  bool linear_references = false;  // the figure's reference curves without a figure
};

CLI::App* RegisterFrf(CLI::App& app, CaseArgs* cargs, FrfArgs* a);
int RunFrf(const CaseArgs& cargs, const FrfArgs& a);

}  // namespace fricrom::app
