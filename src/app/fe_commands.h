// CLI commands on FE matrix files: info (what a file holds) and convert (Matrix Market, HDF5).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

namespace fricrom::app {

class FeCommands {
 public:
  FeCommands();
  ~FeCommands();
  void Register(CLI::App& app);
  int Run();  // −1 when none of these was selected

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fricrom::app
