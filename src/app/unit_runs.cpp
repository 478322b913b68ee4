#include "app/unit_runs.h"

#include <cmath>
#include <mutex>
#include <numeric>

#include "app/mpi_units.h"
#include "app/run_journal.h"
#include "fricrom/frf.h"
#include "fricrom/work_queue.h"

namespace fricrom::app {

SweepUnitsRun RunSweepUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const Model& model, const std::vector<double>& values,
                            const SweepOptions& options, const BalanceFactory& factory,
                            const DesignProgress& progress,
                            const std::function<void(const SweepUnitsRun&)>& write_files) {
  SweepUnitsRun run;
  const int n = static_cast<int>(values.size());
  // One value on one thread, as a journal row: the unit an MPI rank computes.
  const auto compute_row = [&](int i) {
    SweepOptions one = options;
    one.threads = 1;
    return SweepRowJson(model, SweepRobustness(factory, {values[i]}, one).front()).dump();
  };
  const bool ranks = MpiSize() > 1;
  if (ranks && MpiRank() != 0) {  // a worker rank: units in, rows out; rank 0 writes
    DistributeUnits({}, compute_row, {});
    run.worker = true;
    return run;
  }
  // Each finished value goes to the journal at once, so a killed run resumes where it stopped.
  RunJournal journal(dir, "sweep", header, resume);
  std::vector<bool> finished(n, false);
  std::vector<int> pending;
  for (int i = 0; i < n; ++i) {
    finished[i] = journal.finished().count(i) > 0;
    if (!finished[i]) pending.push_back(i);
  }
  run.resumed = n - static_cast<int>(pending.size());
  if (ranks) {
    int done = run.resumed;
    DistributeUnits(pending, compute_row, [&](int i, const std::string& row) {
      journal.Record(i, nlohmann::json::parse(row));
      ++run.computed;
      if (progress) progress(++done, n);
    });
  } else {
    SweepRobustness(
        factory, values, options, progress,
        [&](int i, const RobustnessPoint& pt) {
          journal.Record(i, SweepRowJson(model, pt));
          ++run.computed;
        },
        finished);
  }
  for (int i = 0; i < n; ++i) AppendSweepRow(journal.finished().at(i), &run.columns);
  write_files(run);
  journal.Complete();
  return run;
}

std::vector<double> SolveAlphaSamples(
    const HarmonicBalance& system,
    const std::function<std::unique_ptr<HarmonicBalance>()>& make_balance,
    const std::vector<Eigen::VectorXd>& alphas, double freq_hz, int threads) {
  const int n = static_cast<int>(alphas.size());
  std::vector<double> amplitude(n, NAN);
  // Free balances; a null entry stands for `system` (lent to one worker at a time).
  std::mutex lock;
  std::vector<std::unique_ptr<HarmonicBalance>> pool;
  pool.push_back(nullptr);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  RunWorkUnits(
      all, threads,
      [&](int i) {
        std::unique_ptr<HarmonicBalance> own;
        bool lent = false;
        {
          const std::lock_guard<std::mutex> g(lock);
          if (!pool.empty()) {
            own = std::move(pool.back());
            pool.pop_back();
            lent = own == nullptr;
          }
        }
        if (!own && !lent) own = make_balance();
        const FrfPoint p = SolveAtFrequency(lent ? system : *own, alphas[i], freq_hz,
                                            Eigen::VectorXd(), FrfOptions{});
        if (p.status == SolverStatus::kConverged) amplitude[i] = p.amplitude;
        const std::lock_guard<std::mutex> g(lock);
        pool.push_back(std::move(own));
      },
      [](int) {});
  return amplitude;
}

}  // namespace fricrom::app
