// Speed of the bounds and robust-design layer on the lumped case (paper §4). Results and the
// machine are recorded in benchmarks/README.md.
#include <benchmark/benchmark.h>

#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/design.h"
#include "fricrom/hbm_system.h"

namespace {

using namespace fricrom;

Case Load(const std::vector<ParameterOverride>& o = {}) {
  return LoadCase(std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/baseline.toml", o);
}

BoundsOptions Method(int m) {
  BoundsOptions o;
  o.method = m == 0 ? BoundsOptions::kFullSpace : BoundsOptions::kReducedSpace;
  return o;
}

// Bounds at one frequency near resonance; arg0: 0 = Ipopt full space, 1 = reduced space;
// arg1: gamma × 100.
void BM_BoundsOneFrequency(benchmark::State& state) {
  const Case c = Load({{"gamma", state.range(1) / 100.0}});
  HbmSystem sys(c.model, HbmOptions{1, 128});
  const BoundsOptions o = Method(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const BoundsResult b = ComputeBounds(sys, 266.0, o);
    benchmark::DoNotOptimize(b.min.amplitude);
  }
}
BENCHMARK(BM_BoundsOneFrequency)
    ->ArgNames({"reduced", "gamma_pct"})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 30})
    ->Args({1, 30})
    ->Unit(benchmark::kMillisecond);

// The whole §4 reproduction: bound curve (101 frequencies), both sweeps (44 and 41 values) and
// both NOA runs, at 266 Hz, reduced space (as the main job).
void BM_PaperReproduction(benchmark::State& state) {
  const Case c = Load();
  HbmSystem sys(c.model, HbmOptions{1, 128});
  BoundsOptions bo = Method(1);
  SweepOptions so;
  so.bounds = bo;
  so.reference_freq_hz = 266.0;
  auto factory = [](const std::string& p) {
    return BalanceFactory([p](double v) {
      return MakeBalance(Load({{p, v}}).model, HbmOptions{1, 128}, BalanceKind::kFull);
    });
  };
  for (auto _ : state) {
    const BoundsResult* prev = nullptr;
    std::vector<BoundsResult> curve;
    curve.reserve(101);
    for (int i = 0; i < 101; ++i) {
      BoundsOptions o = bo;
      o.alpha_seeds = DefaultAlphaSeeds(4);
      if (prev) {
        o.alpha_seeds.push_back(prev->min.alpha);
        o.alpha_seeds.push_back(prev->max.alpha);
      }
      curve.push_back(ComputeBounds(sys, 240.0 + 0.5 * i, o));
      prev = &curve.back();
    }
    std::vector<double> g, b;
    for (int i = 0; i < 44; ++i) g.push_back(0.43 * i / 43);
    for (int i = 0; i < 41; ++i) b.push_back(0.2 * i / 40);
    benchmark::DoNotOptimize(SweepRobustness(factory("gamma"), g, so).data());
    benchmark::DoNotOptimize(SweepRobustness(factory("beta"), b, so).data());
    NoaOptions no;
    no.inner = so;
    no.upper = 0.43;
    benchmark::DoNotOptimize(RunNoa(factory("gamma"), no).p_opt);
    no.upper = 0.2;
    benchmark::DoNotOptimize(RunNoa(factory("beta"), no).p_opt);
  }
}
BENCHMARK(BM_PaperReproduction)->Unit(benchmark::kSecond)->Iterations(2);

}  // namespace
