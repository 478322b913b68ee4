// The units of work of the CLI commands, run on threads or MPI ranks: the values of a sweep and the
// frequencies of a bound curve (with the journals that make them resumable), and the units of
// verify (bounds, alpha samples, time integrations).
#pragma once

#include <Eigen/Dense>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/result_files.h"
#include "fricrom/balance_pool.h"
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

// One stage of a curve run as this run saw it: where a curve spends its time.
struct CurveStage {
  std::string name;     // "frequencies", "continuations", "neighbour starts", ...
  int units = 0;        // units of the stage
  int computed = 0;     // of them computed by this run (the rest resumed from the journal)
  double wall_s = 0.0;  // this run's wall time in the stage (0 when everything was resumed)
};

struct CurveUnitsRun {
  std::vector<BoundsResult> points;  // every frequency, in order, after both passes
  int computed = 0;                  // units (point passes) computed by this run
  int resumed = 0;                   // units read back from the journal of an earlier run
  std::vector<CurveStage> stages;    // in the order run (rank 0)
  bool worker = false;               // an MPI rank other than 0
};

// The library's bound curve (ComputeBoundCurve, design.h) with its stages' units on the calling
// rank's threads (options.threads, extra balances from make_balance) or over MPI ranks when
// there are several, through a journal in `dir` (name "bounds", keyed as the stages say).
// Rank 0 calls write_files with the points while it holds the folder's lock, and then drops the
// journal. Every result goes through its journal record, so a resumed or distributed run gives
// the serial run's curve bit for bit.
CurveUnitsRun RunCurveUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const HarmonicBalance& system,
                            const BalanceMaker& make_balance, const std::vector<double>& freqs,
                            const BoundCurveOptions& options,
                            const std::function<void(const CurveUnitsRun&)>& write_files);

// Units 0..n-1 of any command as text results: on `threads` threads of this rank, or over MPI
// ranks when there are several (then each rank computes one unit at a time). Rank 0 gets every
// unit's text, in unit order; the other ranks an empty vector. progress(done, n) on rank 0.
std::vector<std::string> RunTextUnits(int n, int threads,
                                      const std::function<std::string(int)>& unit,
                                      const DesignProgress& progress);

}  // namespace fricrom::app
