#include "app/unit_runs.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
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

namespace {

// The points 0..n-1 dearest first by an earlier stage's wall time (the longest-processing-time
// rule: no worker starts a long point while the others run out of work; the results do not
// depend on the order). A time read back as null from a journal is NaN: it sorts last, keeping
// the order strict.
std::vector<int> DearestFirst(const std::vector<BoundsResult>& by) {
  const auto cost = [&](int i) { return std::isfinite(by[i].wall_s) ? by[i].wall_s : -1.0; };
  std::vector<int> order(by.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost(a) > cost(b); });
  return order;
}

}  // namespace

CurveUnitsRun RunCurveUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const HarmonicBalance& system,
                            const BalanceMaker& make_balance, const std::vector<double>& freqs,
                            const BoundCurveOptions& options,
                            const std::function<void(const CurveUnitsRun&)>& write_files) {
  using nlohmann::json;
  CurveUnitsRun run;
  const int n = static_cast<int>(freqs.size());
  const bool ranks = MpiSize() > 1;
  const bool two_passes = options.warm_start && n > 1;
  const std::vector<int> anchors = CurveAnchors(n, options.anchor_every);
  const std::vector<CurveChain> chains = CurveChains(anchors);
  std::vector<int> chain_ids(chains.size());
  std::iota(chain_ids.begin(), chain_ids.end(), 0);
  BalancePool pool(system, make_balance);
  // On the harmonic ladder the passes run at H = 1 (`search`) and a last stage refines each
  // point at H from its H = 1 optima (BoundCurveOptions, design.h).
  const bool ladder = UsesHarmonicLadder(system, options.bounds);
  BoundsOptions search = options.bounds;
  search.search_harmonics = 0;
  const auto at_search = [&](const BalancePool::Lease& lease) -> const HarmonicBalance& {
    return SearchBalance(lease.get(), options.bounds);
  };
  std::vector<BoundsResult> pass1(n);  // read back from records on every rank before pass 2
  std::vector<BoundsResult> pass2;     // the same before the refinement (ladder)
  const std::function<std::string(int)> first = [&](int i) {
    const BalancePool::Lease lease = pool.Borrow();
    return BoundsRecord(ComputeBounds(at_search(lease), freqs[i], search)).dump();
  };
  const std::function<std::string(int)> chain = [&](int c) {
    std::vector<double> f;
    for (int i : chains[c].points) f.push_back(freqs[i]);
    const BalancePool::Lease lease = pool.Borrow();
    json records = json::array();
    for (const BoundsResult& r :
         ContinueBounds(at_search(lease), pass1[chains[c].from], f, search)) {
      records.push_back(BoundsRecord(r));
    }
    return records.dump();
  };
  const std::function<std::string(int)> second = [&](int i) {
    const BalancePool::Lease lease = pool.Borrow();
    return BoundsRecord(RefineFromNeighbours(at_search(lease), pass1, i, search)).dump();
  };
  const std::function<std::string(int)> refine = [&](int i) {
    const BalancePool::Lease lease = pool.Borrow();
    return BoundsRecord(RefineBoundsAtHarmonics(lease.get(), pass2[i], options.bounds)).dump();
  };
  // Every rank holds the points `ids` of `stage` before the next stage (root broadcasts them).
  const auto share = [&](const std::vector<int>& ids, std::vector<BoundsResult>* stage) {
    json all = json::array();
    if (MpiRank() == 0) {
      for (int i : ids) all.push_back(BoundsRecord((*stage)[i]));
    }
    all = json::parse(BroadcastText(all.dump()));
    for (size_t k = 0; k < ids.size(); ++k) (*stage)[ids[k]] = BoundsFromRecord(all.at(k));
  };
  std::vector<int> every(n);
  std::iota(every.begin(), every.end(), 0);
  if (ranks && MpiRank() != 0) {  // a worker rank: units in, records out
    DistributeUnits({}, first, {});
    if (!chains.empty()) {
      share(anchors, &pass1);
      DistributeUnits({}, chain, {});
    }
    if (two_passes) {
      share(every, &pass1);
      DistributeUnits({}, second, {});
    }
    if (ladder) {
      pass2.resize(n);
      share(every, &pass2);
      DistributeUnits({}, refine, {});
    }
    run.worker = true;
    return run;
  }
  RunJournal journal(dir, "bounds", header, resume);
  // Journal keys: pass 1 at i, pass 2 at n + i, chain c at 2n + c, the ladder's refinement at
  // 2n + chains + i.
  const auto run_pass = [&](int offset, const std::vector<int>& ids,
                            const std::function<std::string(int)>& unit, const std::string& stage) {
    std::vector<int> pending;
    for (int i : ids) {
      if (journal.finished().count(offset + i) == 0) pending.push_back(i);
    }
    const int total = static_cast<int>(ids.size());
    int done = total - static_cast<int>(pending.size());
    run.resumed += done;
    // The stage's name shows at its start: a curve of one point (bounds --freq) would otherwise
    // show nothing during a minutes-long refinement.
    if (options.progress) options.progress(stage, done, total);
    const auto record = [&](int i, const std::string& text) {
      journal.Record(offset + i, json::parse(text));
      ++run.computed;
      if (options.progress) options.progress(stage, ++done, total);
    };
    if (ranks) {
      DistributeUnits(pending, unit, record);
    } else {
      std::map<int, std::string> texts;
      std::mutex lock;
      RunWorkUnits(
          pending, WorkerThreads(options.threads, total),
          [&](int i) {
            std::string t = unit(i);
            const std::lock_guard<std::mutex> g(lock);
            texts[i] = std::move(t);
          },
          [&](int i) { record(i, texts.at(i)); });
    }
  };
  run_pass(0, anchors, first, "frequencies");
  for (int i : anchors) pass1[i] = BoundsFromRecord(journal.finished().at(i));
  if (!chains.empty()) {
    if (ranks) share(anchors, &pass1);
    run_pass(2 * n, chain_ids, chain, "continuations");
    std::vector<std::vector<BoundsResult>> results(chains.size());
    for (size_t c = 0; c < chains.size(); ++c) {
      for (const json& r : journal.finished().at(2 * n + static_cast<int>(c))) {
        results[c].push_back(BoundsFromRecord(r));
      }
    }
    MergeChains(chains, results, search.objective, &pass1);
  }
  if (two_passes) {
    if (ranks) share(every, &pass1);
    // Pass 2 dearest point first, by its pass-1 time (near a resonance both passes are long), so
    // that no worker starts a long point while the others run out of work. The curve does not
    // depend on the order.
    run_pass(n, DearestFirst(pass1), second, "neighbour starts");
    run.points.resize(n);
    for (int i = 0; i < n; ++i) run.points[i] = BoundsFromRecord(journal.finished().at(n + i));
  } else {
    run.points = pass1;
  }
  if (ladder) {
    pass2 = run.points;
    if (ranks) share(every, &pass2);
    const int offset = 2 * n + static_cast<int>(chains.size());
    // Dearest first again, by the H = 1 passes' time.
    run_pass(offset, DearestFirst(pass2), refine, "harmonic refinement");
    for (int i = 0; i < n; ++i) {
      run.points[i] = BoundsFromRecord(journal.finished().at(offset + i));
    }
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
