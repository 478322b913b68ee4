// CLI commands of the Craig-Bampton reduction: `reduce` (FE model -> reduced HDF5 model with its
// checks) and `check-reduced` (structural checks of a given Craig-Bampton model, e.g. a Nastran
// EXTSEOUT superelement).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

namespace fricrom::app {

class ReduceCommands {
 public:
  ReduceCommands();
  ~ReduceCommands();
  void Register(CLI::App& app);
  int Run();  // -1 when none of these was selected

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fricrom::app
