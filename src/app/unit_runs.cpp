#include "app/unit_runs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
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

using Unit = std::function<std::string(int)>;

// The bound curve as units of work, stage after stage: pass 1 (anchors), the continuations
// between anchors, pass 2 from the neighbours' optima, the harmonic ladder's refinement.
class CurveUnits {
 public:
  CurveUnits(const HarmonicBalance& system, const BalanceMaker& make_balance,
             const std::vector<double>& freqs, const BoundCurveOptions& options)
      : freqs_(freqs),
        options_(options),
        n_(static_cast<int>(freqs.size())),
        ranks_(MpiSize() > 1),
        two_passes_(options.warm_start && n_ > 1),
        sweeps_(two_passes_ && options.neighbour_pass == BoundCurveOptions::kSweeps),
        anchors_(CurveAnchors(n_, options.anchor_every)),
        chains_(CurveChains(anchors_)),
        pool_(system, make_balance),
        // On the harmonic ladder the passes run at H = 1 (`search_`) and a last stage refines
        // each point at H from its H = 1 optima (BoundCurveOptions, design.h).
        ladder_(UsesHarmonicLadder(system, options.bounds)),
        search_(options.bounds),
        pass1_(n_),
        every_(n_) {
    search_.search_harmonics = 0;
    std::iota(every_.begin(), every_.end(), 0);
  }

  // A worker rank: units in, records out, stage after stage as rank 0 runs them.
  CurveUnitsRun RunAsWorker() {
    DistributeUnits({}, first_, {});
    if (!chains_.empty()) {
      Share(anchors_, &pass1_);
      DistributeUnits({}, chain_, {});
    }
    if (two_passes_) {
      Share(every_, &pass1_);
      DistributeUnits({}, sweeps_ ? sweep_ : second_, {});
    }
    if (ladder_) {
      pass2_.resize(n_);
      Share(every_, &pass2_);
      DistributeUnits({}, refine_, {});
    }
    CurveUnitsRun run;
    run.worker = true;
    return run;
  }

  // Rank 0 (or the only one): every stage through the journal, which keeps pass 1 at i, pass 2
  // at n + i (its sweeps up and down at n and n + 1), chain c at 2n + c, the ladder's refinement
  // at 2n + chains + i.
  CurveUnitsRun Run(RunJournal* journal) {
    journal_ = journal;
    RunStage(0, anchors_, first_, "frequencies");
    for (int i : anchors_) pass1_[i] = BoundsFromRecord(journal_->finished().at(i));
    if (!chains_.empty()) Continue();
    if (two_passes_) {
      if (ranks_) Share(every_, &pass1_);
      if (sweeps_) {
        RunStage(n_, {0, 1}, sweep_, "sweeps");
        run_.points = MergeSweeps(ReadSweep(n_), ReadSweep(n_ + 1), pass1_, search_.objective);
      } else {
        // Pass 2 dearest point first, by its pass-1 time (near a resonance both passes are
        // long), so that no worker starts a long point while the others run out of work. The
        // curve does not depend on the order.
        RunStage(n_, DearestFirst(pass1_), second_, "neighbour starts");
        run_.points = Read(n_);
      }
    } else {
      run_.points = pass1_;
    }
    if (ladder_) {
      pass2_ = run_.points;
      if (ranks_) Share(every_, &pass2_);
      const int offset = 2 * n_ + static_cast<int>(chains_.size());
      // Dearest first again, by the H = 1 passes' time.
      RunStage(offset, DearestFirst(pass2_), refine_, "harmonic refinement");
      run_.points = Read(offset);
    }
    return std::move(run_);
  }

 private:
  const HarmonicBalance& AtSearch(const BalancePool::Lease& lease) const {
    return SearchBalance(lease.get(), options_.bounds);
  }

  // A sweep's record: one point record per frequency, in the points' order.
  std::vector<BoundsResult> ReadSweep(int key) const {
    std::vector<BoundsResult> out;
    for (const nlohmann::json& r : journal_->finished().at(key)) out.push_back(BoundsFromRecord(r));
    if (static_cast<int>(out.size()) != n_) {
      throw std::runtime_error("bounds: the journal's sweep holds " + std::to_string(out.size()) +
                               " points, the curve has " + std::to_string(n_));
    }
    return out;
  }

  std::vector<BoundsResult> Read(int offset) const {
    std::vector<BoundsResult> out(n_);
    for (int i = 0; i < n_; ++i) out[i] = BoundsFromRecord(journal_->finished().at(offset + i));
    return out;
  }

  // The continuations from the anchors, merged into pass 1.
  void Continue() {
    if (ranks_) Share(anchors_, &pass1_);
    std::vector<int> chain_ids(chains_.size());
    std::iota(chain_ids.begin(), chain_ids.end(), 0);
    RunStage(2 * n_, chain_ids, chain_, "continuations");
    std::vector<std::vector<BoundsResult>> results(chains_.size());
    for (size_t c = 0; c < chains_.size(); ++c) {
      for (const nlohmann::json& r : journal_->finished().at(2 * n_ + static_cast<int>(c))) {
        results[c].push_back(BoundsFromRecord(r));
      }
    }
    MergeChains(chains_, results, search_.objective, &pass1_);
  }

  // Every rank holds the points `ids` of `stage` before the next stage (root broadcasts them).
  void Share(const std::vector<int>& ids, std::vector<BoundsResult>* stage) const {
    nlohmann::json all = nlohmann::json::array();
    if (MpiRank() == 0) {
      for (int i : ids) all.push_back(BoundsRecord((*stage)[i]));
    }
    all = nlohmann::json::parse(BroadcastText(all.dump()));
    for (size_t k = 0; k < ids.size(); ++k) (*stage)[ids[k]] = BoundsFromRecord(all.at(k));
  }

  // The units `ids` of one stage not in the journal yet, on threads or over the ranks.
  void RunStage(int offset, const std::vector<int>& ids, const Unit& unit,
                const std::string& stage) {
    std::vector<int> pending;
    for (int i : ids) {
      if (journal_->finished().count(offset + i) == 0) pending.push_back(i);
    }
    const int total = static_cast<int>(ids.size());
    int done = total - static_cast<int>(pending.size());
    run_.resumed += done;
    const auto t0 = std::chrono::steady_clock::now();
    // The stage's name shows at its start: a curve of one point (bounds --freq) would otherwise
    // show nothing during a minutes-long refinement.
    if (options_.progress) options_.progress(stage, done, total);
    const auto record = [&](int i, const std::string& text) {
      journal_->Record(offset + i, nlohmann::json::parse(text));
      ++run_.computed;
      if (options_.progress) options_.progress(stage, ++done, total);
    };
    if (ranks_) {
      DistributeUnits(pending, unit, record);
    } else {
      std::map<int, std::string> texts;
      std::mutex lock;
      RunWorkUnits(
          pending, WorkerThreads(options_.threads, total),
          [&](int i) {
            std::string t = unit(i);
            const std::lock_guard<std::mutex> g(lock);
            texts[i] = std::move(t);
          },
          [&](int i) { record(i, texts.at(i)); });
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run_.stages.push_back({stage, total, static_cast<int>(pending.size()), wall_s});
  }

  const std::vector<double>& freqs_;
  const BoundCurveOptions& options_;
  const int n_;
  const bool ranks_;
  const bool two_passes_;
  const bool sweeps_;  // pass 2 as two sweeps (BoundCurveOptions::kSweeps)
  const std::vector<int> anchors_;
  const std::vector<CurveChain> chains_;
  BalancePool pool_;
  const bool ladder_;
  BoundsOptions search_;
  std::vector<BoundsResult> pass1_;  // read back from records on every rank before pass 2
  std::vector<BoundsResult> pass2_;  // the same before the refinement (ladder)
  std::vector<int> every_;
  RunJournal* journal_ = nullptr;
  CurveUnitsRun run_;

  // The units of each stage: unit i is point i (chain c for the continuations), as a record.
  const Unit first_ = [this](int i) {
    const BalancePool::Lease lease = pool_.Borrow();
    return BoundsRecord(SearchLevels(AtSearch(lease), freqs_[i], search_, options_.levels)).dump();
  };
  const Unit chain_ = [this](int c) {
    std::vector<double> f;
    for (int i : chains_[c].points) f.push_back(freqs_[i]);
    const BalancePool::Lease lease = pool_.Borrow();
    nlohmann::json records = nlohmann::json::array();
    for (const BoundsResult& r :
         ContinueBounds(AtSearch(lease), pass1_[chains_[c].from], f, search_)) {
      records.push_back(BoundsRecord(r));
    }
    return records.dump();
  };
  const Unit second_ = [this](int i) {
    const BalancePool::Lease lease = pool_.Borrow();
    return BoundsRecord(RefineFromNeighbours(AtSearch(lease), pass1_, i, search_)).dump();
  };
  // Pass 2's sweep up (unit 0) or down (unit 1) the curve, as one record per point.
  const Unit sweep_ = [this](int d) {
    const BalancePool::Lease lease = pool_.Borrow();
    nlohmann::json records = nlohmann::json::array();
    for (const BoundsResult& r : SweepBounds(AtSearch(lease), pass1_, d == 0, search_)) {
      records.push_back(BoundsRecord(r));
    }
    return records.dump();
  };
  const Unit refine_ = [this](int i) {
    const BalancePool::Lease lease = pool_.Borrow();
    return BoundsRecord(
               RefineLevelsAtHarmonics(lease.get(), pass2_[i], options_.bounds, options_.levels))
        .dump();
  };
};

}  // namespace

CurveUnitsRun RunCurveUnits(const std::filesystem::path& dir, const nlohmann::json& header,
                            bool resume, const HarmonicBalance& system,
                            const BalanceMaker& make_balance, const std::vector<double>& freqs,
                            const BoundCurveOptions& options,
                            const std::function<void(const CurveUnitsRun&)>& write_files) {
  CurveUnits units(system, make_balance, freqs, options);
  if (MpiSize() > 1 && MpiRank() != 0) return units.RunAsWorker();
  RunJournal journal(dir, "bounds", header, resume);
  const CurveUnitsRun run = units.Run(&journal);
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
