#include "app/progress_line.h"

#include <unistd.h>

#include <iomanip>
#include <iostream>

namespace fricrom::app {

bool Progress::IsTerminal() { return isatty(STDERR_FILENO) != 0; }

void Progress::operator()(const std::string& stage, int done, int total) const {
  if (!enabled) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!terminal) {
    if (t - *last_line_s < 10.0) return;
    *last_line_s = t;
  }
  std::cerr << (terminal ? "\r" : "") << label << ": " << (stage.empty() ? "" : stage + " ")
            << done;
  if (total > 0) std::cerr << "/" << total;
  std::cerr << "  (" << std::fixed << std::setprecision(1) << t << " s";
  // Rate and time left from the units finished so far (units differ in cost: an estimate).
  if (total > 0 && done > 0 && done < total && t > 0.0) {
    const double rate = done / t;
    std::cerr << ", " << std::setprecision(rate < 1.0 ? 3 : 1) << rate << "/s, ETA "
              << std::setprecision(0) << (total - done) / rate << " s";
  }
  std::cerr << (terminal ? ")   " : ")\n") << std::flush;
}

void Progress::Done() const {
  if (enabled && terminal) std::cerr << "\n";
}

}  // namespace fricrom::app
