// One cyclic sector against the explicit ring it stands for, on the same FRF: the disk24 sector
// coupled as a ring of 6 at EO 1 (its cyclic contacts keep the disk's geometry and take the
// phase 2π/6: a ring small enough to hold explicitly), condensed balance, points over a range
// each warm-started from the last. The ring is solved at the α that put it on the sector's
// solution (RingContactAlpha, per point), so both solve the same response; the counter
// max_rel_diff is their largest relative difference in amplitude. Results and the machine:
// benchmarks/README.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fricrom/case_file.h"
#include "fricrom/condensed_system.h"
#include "fricrom/cyclic.h"
#include "fricrom/frf.h"
#include "fricrom/units.h"

namespace {

using namespace fricrom;

const Case& DiskSectorOfSix() {
  static const Case c = [] {
    Case d = LoadCase(std::string(FRICROM_SOURCE_DIR) + "/meshes/disk24/coarse.toml");
    d.model.cyclic.sectors = 6;
    d.model.cyclic.engine_order = 1;
    for (Contact& ct : d.model.contacts) {
      if (ct.cyclic()) ct.phase_b = d.model.cyclic.phase();
    }
    return d;
  }();
  return c;
}

std::vector<double> Frequencies() {
  std::vector<double> f;
  for (int i = 0; i <= 10; ++i) f.push_back(1110.0 + 2.0 * i);  // 1110-1130 Hz, 11 points
  return f;
}

HbmOptions Options(int harmonics, ReceptanceMethod receptance) {
  HbmOptions o{harmonics, 96};  // 96 samples: the delay of 1/6 period is 16 samples
  o.receptance = receptance;
  return o;
}

struct SectorFrf {
  std::vector<FrfPoint> points;
  std::vector<Eigen::VectorXd> ring_alpha;  // per point
};

SectorFrf SolveSector(const CondensedSystem& sector, const Eigen::VectorXd& contact_alpha) {
  const Model& m = DiskSectorOfSix().model;
  SectorFrf out;
  out.points = SolveAtFrequencies(sector, contact_alpha, Frequencies(), FrfOptions{});
  for (const FrfPoint& p : out.points) {
    const double w = kTwoPi * p.freq_hz;
    out.ring_alpha.push_back(
        RingContactAlpha(m, sector.ContactHistories(p.x, w, contact_alpha), contact_alpha));
  }
  return out;
}

Eigen::VectorXd SectorAlpha() {
  const Model& m = DiskSectorOfSix().model;
  return m.ContactAlpha(Eigen::VectorXd::LinSpaced(m.num_alpha(), -0.8, 0.8));
}

// The sector's FRF (dense receptance: a cyclic sector's stuck modes differ per harmonic).
void BM_CyclicSectorFrf(benchmark::State& state) {
  const int h = static_cast<int>(state.range(0));
  const Eigen::VectorXd alpha = SectorAlpha();
  int failed = 0;
  double unknowns = 0;
  for (auto _ : state) {
    const CondensedSystem sector(DiskSectorOfSix().model, Options(h, ReceptanceMethod::kDense));
    const std::vector<FrfPoint> pts =
        SolveAtFrequencies(sector, alpha, Frequencies(), FrfOptions{});
    failed = static_cast<int>(std::count_if(pts.begin(), pts.end(), [](const FrfPoint& p) {
      return p.status != SolverStatus::kConverged;
    }));
    unknowns = sector.num_unknowns();
    benchmark::DoNotOptimize(pts.data());
  }
  state.counters["failed_points"] = failed;
  state.counters["unknowns"] = unknowns;
}
BENCHMARK(BM_CyclicSectorFrf)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->Iterations(1);

// The explicit ring's FRF on the same response (dense receptance: the ring's contacts to the next
// sector read it in that sector's rotated frame, which the modal receptance does not take).
void BM_CyclicRingFrf(benchmark::State& state) {
  const int h = static_cast<int>(state.range(0));
  const CondensedSystem sector(DiskSectorOfSix().model, Options(h, ReceptanceMethod::kDense));
  const SectorFrf ref = SolveSector(sector, SectorAlpha());
  const Model ring = ExpandCyclicRing(DiskSectorOfSix().model);
  int failed = 0;
  double worst = 0.0, unknowns = 0;
  for (auto _ : state) {
    const CondensedSystem full(ring, Options(h, ReceptanceMethod::kDense));
    Eigen::VectorXd x;
    worst = 0.0;
    failed = 0;
    for (size_t i = 0; i < ref.points.size(); ++i) {
      const FrfPoint p =
          SolveAtFrequency(full, ref.ring_alpha[i], ref.points[i].freq_hz, x, FrfOptions{});
      if (p.status != SolverStatus::kConverged) {
        ++failed;
        continue;
      }
      x = p.x;
      worst = std::max(worst,
                       std::abs(p.amplitude - ref.points[i].amplitude) / ref.points[i].amplitude);
    }
    unknowns = full.num_unknowns();
  }
  state.counters["failed_points"] = failed;
  state.counters["max_rel_diff"] = worst;
  state.counters["unknowns"] = unknowns;
}
BENCHMARK(BM_CyclicRingFrf)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
