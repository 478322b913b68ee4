#include "app/unit_runs.h"

#include <cmath>
#include <numeric>

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

CurveUnitsRun RunCurveUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const HarmonicBalance& system,
                            const BalanceMaker& make_balance, const std::vector<double>& freqs,
                            const BoundCurveOptions& options,
                            const std::function<void(const CurveUnitsRun&)>& write_files) {
  CurveUnitsRun run;
  const int n = static_cast<int>(freqs.size());
  const bool ranks = MpiSize() > 1;
  const bool two_passes = options.warm_start && n > 1;
  BalancePool pool(system, make_balance);
  std::vector<BoundsResult> pass1(n);  // read back from records on every rank before pass 2
  const std::function<std::string(int)> first = [&](int i) {
    const BalancePool::Lease lease = pool.Borrow();
    return BoundsRecord(ComputeBounds(lease.get(), freqs[i], options.bounds)).dump();
  };
  const std::function<std::string(int)> second = [&](int i) {
    const BalancePool::Lease lease = pool.Borrow();
    return BoundsRecord(RefineFromNeighbours(lease.get(), pass1, i, options.bounds)).dump();
  };
  if (ranks && MpiRank() != 0) {  // a worker rank: units in, records out
    DistributeUnits({}, first, {});
    if (two_passes) {
      const nlohmann::json all = nlohmann::json::parse(BroadcastText(""));
      for (int i = 0; i < n; ++i) pass1[i] = BoundsFromRecord(all.at(i));
      DistributeUnits({}, second, {});
    }
    run.worker = true;
    return run;
  }
  RunJournal journal(dir, "bounds", header, resume);
  const auto run_pass = [&](int offset, const std::function<std::string(int)>& unit,
                            const std::string& stage) {
    std::vector<int> pending;
    for (int i = 0; i < n; ++i) {
      if (journal.finished().count(offset + i) == 0) pending.push_back(i);
    }
    int done = n - static_cast<int>(pending.size());
    run.resumed += done;
    const auto record = [&](int i, const std::string& text) {
      journal.Record(offset + i, nlohmann::json::parse(text));
      ++run.computed;
      if (options.progress) options.progress(stage, ++done, n);
    };
    if (ranks) {
      DistributeUnits(pending, unit, record);
    } else {
      std::vector<std::string> texts(n);
      RunWorkUnits(
          pending, WorkerThreads(options.threads, n), [&](int i) { texts[i] = unit(i); },
          [&](int i) { record(i, texts[i]); });
    }
    std::vector<BoundsResult> out(n);
    for (int i = 0; i < n; ++i) out[i] = BoundsFromRecord(journal.finished().at(offset + i));
    return out;
  };
  pass1 = run_pass(0, first, "frequencies");
  if (two_passes) {
    if (ranks) {
      nlohmann::json all = nlohmann::json::array();
      for (int i = 0; i < n; ++i) all.push_back(journal.finished().at(i));
      BroadcastText(all.dump());
    }
    run.points = run_pass(n, second, "neighbour starts");
  } else {
    run.points = pass1;
  }
  write_files(run);
  journal.Complete();
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
