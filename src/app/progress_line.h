// The progress of long CLI runs on stderr: done/total, elapsed time, rate and ETA. On a terminal
// one line updated in place; otherwise (a batch job's log) a full line at most every 10 s, so
// short runs stay silent and a Slurm log shows how far a long one got.
#pragma once

#include <chrono>
#include <memory>
#include <string>

namespace fricrom::app {

struct Progress {
  bool enabled;  // the caller decides (not --quiet)
  std::string label;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  bool terminal = IsTerminal();
  // Shared by copies of this object, which report together (the callers serialise the calls).
  struct State {
    double last_line_s = 0.0;  // last line written off a terminal
    double last_call_s = 0.0;  // last report, printed or not
    std::string stage;         // the stage reported last
    double stage_t0_s = 0.0;   // when it began: the previous stage's last report
  };
  std::shared_ptr<State> state = std::make_shared<State>();
  static bool IsTerminal();
  void operator()(int done, int total) const { (*this)("", done, total); }
  void operator()(const std::string& stage, int done, int total) const;
  void Done() const;  // ends the line (on a terminal)
};

}  // namespace fricrom::app
