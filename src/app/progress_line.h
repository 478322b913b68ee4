// The progress line of long CLI runs on stderr: done/total, elapsed time, rate and ETA.
#pragma once

#include <chrono>
#include <string>

namespace fricrom::app {

struct Progress {
  bool enabled;  // the caller decides (a terminal, not --quiet)
  std::string label;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  void operator()(int done, int total) const { (*this)("", done, total); }
  void operator()(const std::string& stage, int done, int total) const;
  void Done() const;  // ends the line
};

}  // namespace fricrom::app
