#include "app/progress_line.h"

#include <unistd.h>

#include <iomanip>
#include <iostream>

namespace fricrom::app {

bool Progress::IsTerminal() { return isatty(STDERR_FILENO) != 0; }

void Progress::operator()(const std::string& stage, int done, int total) const {
  if (!enabled) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  State& s = *state;
  if (stage != s.stage) {  // a new stage (e.g. a curve's pass 2): its rate starts afresh
    s.stage = stage;
    s.stage_t0_s = s.last_call_s;
  }
  s.last_call_s = t;
  if (!terminal) {
    if (t - s.last_line_s < 10.0) return;
    s.last_line_s = t;
  }
  std::cerr << (terminal ? "\r" : "") << label << ": " << (stage.empty() ? "" : stage + " ")
            << done;
  if (total > 0) std::cerr << "/" << total;
  std::cerr << "  (" << std::fixed << std::setprecision(1) << t << " s";
  // Rate and time left from the stage's units finished so far (units differ in cost: an
  // estimate).
  const double stage_s = t - s.stage_t0_s;
  if (total > 0 && done > 0 && done < total && stage_s > 0.0) {
    const double rate = done / stage_s;
    std::cerr << ", " << std::setprecision(rate < 1.0 ? 3 : 1) << rate << "/s, ETA "
              << std::setprecision(0) << (total - done) / rate << " s";
  }
  std::cerr << (terminal ? ")   " : ")\n") << std::flush;
}

void Progress::Done() const {
  if (enabled && terminal) std::cerr << "\n";
}

}  // namespace fricrom::app
