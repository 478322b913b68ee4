#include "app/unit_runs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>

#include "app/bounds_record.h"
#include "app/mpi_units.h"
#include "app/run_journal.h"
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

namespace {

// The curve's stages (ComputeBoundCurve) over this rank's threads or the MPI ranks, through the
// journal: a unit an earlier run finished is read back, every other one is recorded as it ends,
// and every result goes through its record, so a resumed or distributed run gives the serial
// run's curve bit for bit. Over ranks every rank calls Run alike: rank 0 hands the units out and
// broadcasts the stage's records, which every rank reads back.
class JournalStageRunner : public CurveStageRunner {
 public:
  JournalStageRunner(int threads, const std::function<void(const std::string&, int, int)>& progress,
                     RunJournal* journal, CurveUnitsRun* run)
      : threads_(threads), progress_(progress), journal_(journal), run_(run) {}

  std::map<int, std::vector<BoundsResult>> Run(const CurveStageSpec& stage,
                                               const std::vector<int>& units,
                                               const Unit& unit) override {
    const auto text = [&](int u) { return ToText(stage, unit(u)).dump(); };
    const bool ranks = MpiSize() > 1;
    nlohmann::json records = nlohmann::json::array();
    if (ranks && MpiRank() != 0) {
      DistributeUnits({}, text, {});
    } else {
      Compute(stage, units, text);
      for (int u : units) records.push_back(journal_->finished().at(stage.key + u));
    }
    if (ranks) records = nlohmann::json::parse(BroadcastText(records.dump()));
    std::map<int, std::vector<BoundsResult>> out;
    for (size_t k = 0; k < units.size(); ++k) out[units[k]] = FromText(stage, records.at(k));
    return out;
  }

 private:
  static nlohmann::json ToText(const CurveStageSpec& stage, const std::vector<BoundsResult>& r) {
    if (!stage.many) return BoundsRecord(r.at(0));
    nlohmann::json a = nlohmann::json::array();
    for (const BoundsResult& b : r) a.push_back(BoundsRecord(b));
    return a;
  }
  static std::vector<BoundsResult> FromText(const CurveStageSpec& stage, const nlohmann::json& j) {
    if (!stage.many) return {BoundsFromRecord(j)};
    std::vector<BoundsResult> out;
    for (const nlohmann::json& r : j) out.push_back(BoundsFromRecord(r));
    return out;
  }

  // Rank 0 (or the only one): the stage's units not in the journal yet, on threads or over the
  // ranks, each recorded as it ends.
  void Compute(const CurveStageSpec& stage, const std::vector<int>& units,
               const std::function<std::string(int)>& text) {
    std::vector<int> pending;
    for (int u : units) {
      if (journal_->finished().count(stage.key + u) == 0) pending.push_back(u);
    }
    const int total = static_cast<int>(units.size());
    int done = total - static_cast<int>(pending.size());
    run_->resumed += done;
    const auto t0 = std::chrono::steady_clock::now();
    // The stage's name shows at its start: a curve of one point (bounds --freq) would otherwise
    // show nothing during a minutes-long refinement.
    if (progress_) progress_(stage.name, done, total);
    const auto record = [&](int u, const std::string& t) {
      journal_->Record(stage.key + u, nlohmann::json::parse(t));
      ++run_->computed;
      if (progress_) progress_(stage.name, ++done, total);
    };
    if (MpiSize() > 1) {
      DistributeUnits(pending, text, record);
    } else {
      std::map<int, std::string> texts;
      std::mutex lock;
      RunWorkUnits(
          pending, WorkerThreads(threads_, total),
          [&](int u) {
            std::string t = text(u);
            const std::lock_guard<std::mutex> g(lock);
            texts[u] = std::move(t);
          },
          [&](int u) { record(u, texts.at(u)); });
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run_->stages.push_back({stage.name, total, static_cast<int>(pending.size()), wall_s});
  }

  const int threads_;
  const std::function<void(const std::string&, int, int)>& progress_;
  RunJournal* journal_;
  CurveUnitsRun* run_;
};

}  // namespace

CurveUnitsRun RunCurveUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const HarmonicBalance& system,
                            const BalanceMaker& make_balance, const std::vector<double>& freqs,
                            const BoundCurveOptions& options,
                            const std::function<void(const CurveUnitsRun&)>& write_files) {
  CurveUnitsRun run;
  const bool worker = MpiSize() > 1 && MpiRank() != 0;
  std::unique_ptr<RunJournal> journal;
  if (!worker) journal = std::make_unique<RunJournal>(dir, "bounds", header, resume);
  BoundCurveOptions o = options;
  o.progress = worker ? nullptr : options.progress;
  JournalStageRunner runner(options.threads, o.progress, journal.get(), &run);
  run.points = ComputeBoundCurve(system, freqs, o, make_balance, runner).points;
  if (worker) {
    run.worker = true;
    return run;
  }
  write_files(run);
  journal->Complete();
  return run;
}

std::vector<std::string> RunTextUnits(int n, int threads,
                                      const std::function<std::string(int)>& unit,
                                      const DesignProgress& progress) {
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  std::vector<std::string> texts(n);
  int done = 0;
  if (MpiSize() > 1) {
    DistributeUnits(all, unit, [&](int i, const std::string& text) {
      texts[i] = text;
      if (progress) progress(++done, n);
    });
    if (MpiRank() != 0) texts.clear();
    return texts;
  }
  RunWorkUnits(
      all, WorkerThreads(threads, n), [&](int i) { texts[i] = unit(i); },
      [&](int) {
        if (progress) progress(++done, n);
      });
  return texts;
}

}  // namespace fricrom::app
