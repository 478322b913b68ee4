// CLI commands of the bounds and robust-design workflow: bounds, sweep, noa, verify.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

namespace fricrom::app {

class DesignCommands {
 public:
  DesignCommands();
  ~DesignCommands();
  void Register(CLI::App& app);
  // Runs the selected command; returns −1 when none of these was selected.
  int Run();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fricrom::app
