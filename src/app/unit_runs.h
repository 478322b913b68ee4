// The units of work of the CLI commands, run on threads or MPI ranks: the values of a sweep (with
// the journal that makes them resumable) and the alpha samples of verify.
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

#include "app/result_files.h"
#include "fricrom/case_file.h"
#include "fricrom/design.h"

namespace fricrom::app {

struct SweepUnitsRun {
  SweepColumns columns;  // every value, in order
  int computed = 0;      // values computed by this run
  int resumed = 0;       // values read back from the journal of an earlier run
  bool worker = false;   // an MPI rank other than 0: it computed units, rank 0 has the result
};

// The sweep's values as units of work: on the calling rank's threads (SweepOptions::threads), or
// over MPI ranks when there are several. Rank 0 journals each finished value in `dir` (resumable
// after a kill; `header` must match for a journal to be resumed), then calls write_files with
// every value's columns while it still holds the folder's lock, and only then drops the journal.
SweepUnitsRun RunSweepUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const Model& model, const std::vector<double>& values,
                            const SweepOptions& options, const BalanceFactory& factory,
                            const DesignProgress& progress,
                            const std::function<void(const SweepUnitsRun&)>& write_files);

// Amplitude of the harmonic-balance solution at every α (NaN where it did not converge), solved
// on `threads` threads; each thread builds its own balance with make_balance (a balance caches
// per-frequency data), the first one uses `system`.
std::vector<double> SolveAlphaSamples(
    const HarmonicBalance& system,
    const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance,
    const std::vector<Eigen::VectorXd>& alphas, double freq_hz, int threads);

}  // namespace fricrom::app
