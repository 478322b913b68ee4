// Speed of the core engine on the lumped validation case (paper §4.1). Results and the machine
// they were measured on are recorded in benchmarks/README.md (scripts/run_benchmarks.sh).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>

#include "fricrom/blas_core.h"
#include "fricrom/blas_threads.h"
#include "fricrom/case_file.h"
#include "fricrom/contact_law.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"

namespace {

using namespace fricrom;

const Case& Baseline() {
  static const Case c = LoadCase(std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/baseline.toml");
  return c;
}

// A stick-slip state near resonance (the expensive branch of the contact law).
Eigen::VectorXd NearResonanceSolution(const HbmSystem& sys, const Eigen::VectorXd& alpha) {
  const auto pts = SolveAtFrequencies(sys, alpha, {260.0, 264.0, 266.0}, FrfOptions{});
  return pts.back().x;
}

void BM_ResidualAndJacobian(benchmark::State& state) {
  const int harmonics = static_cast<int>(state.range(0));
  const int samples = static_cast<int>(state.range(1));
  HbmSystem sys(Baseline().model, HbmOptions{harmonics, samples});
  const Eigen::VectorXd alpha = Eigen::Vector4d::Zero();
  const Eigen::VectorXd x = NearResonanceSolution(sys, alpha);
  HbmEvaluation e;
  for (auto _ : state) {
    sys.Evaluate(x, kTwoPi * 266.0, alpha, HbmRequest{true, false, false}, &e);
    benchmark::DoNotOptimize(e.jacobian.data());
  }
}
BENCHMARK(BM_ResidualAndJacobian)
    ->Args({1, 128})
    ->Args({1, 64})
    ->Args({3, 128})
    ->Args({5, 256})
    ->Unit(benchmark::kMicrosecond);

void BM_ResidualOnly(benchmark::State& state) {
  HbmSystem sys(Baseline().model, HbmOptions{1, 128});
  const Eigen::VectorXd alpha = Eigen::Vector4d::Zero();
  const Eigen::VectorXd x = NearResonanceSolution(sys, alpha);
  HbmEvaluation e;
  for (auto _ : state) {
    sys.Evaluate(x, kTwoPi * 266.0, alpha, HbmRequest{}, &e);
    benchmark::DoNotOptimize(e.residual.data());
  }
}
BENCHMARK(BM_ResidualOnly)->Unit(benchmark::kMicrosecond);

// 200 frequencies over the case range, each warm-started from the previous one.
void BM_Frf200Points(benchmark::State& state) {
  const Case& c = Baseline();
  HbmSystem sys(c.model, HbmOptions{1, 128});
  std::vector<double> f(200);
  for (int i = 0; i < 200; ++i) {
    f[i] = c.analysis.freq_min_hz + (c.analysis.freq_max_hz - c.analysis.freq_min_hz) * i / 199.0;
  }
  const Eigen::VectorXd alpha = Eigen::Vector4d::Zero();
  int failed = 0;
  for (auto _ : state) {
    const auto pts = SolveAtFrequencies(sys, alpha, f, FrfOptions{});
    failed = 0;
    for (const FrfPoint& p : pts) failed += p.status != SolverStatus::kConverged;
    benchmark::DoNotOptimize(pts.data());
  }
  state.counters["failed_points"] = failed;
}
BENCHMARK(BM_Frf200Points)->Unit(benchmark::kMillisecond);

// Arclength continuation over the case range (adaptive number of points).
void BM_FrfContinuation(benchmark::State& state) {
  const Case& c = Baseline();
  HbmSystem sys(c.model, HbmOptions{1, 128});
  FrfOptions opt;
  opt.max_step = 0.02;
  size_t points = 0;
  for (auto _ : state) {
    const FrfTrace tr =
        TraceFrf(sys, Eigen::Vector4d::Zero(), c.analysis.freq_min_hz, c.analysis.freq_max_hz, opt);
    points = tr.points.size();
    benchmark::DoNotOptimize(tr.points.data());
  }
  state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_FrfContinuation)->Unit(benchmark::kMillisecond);

// One contact law over 64 samples in the regimes the FE cascade's AFT meets (EvaluateContactLaw:
// ~8 % of its 50-point curve). First argument: derivatives off (0) or on (1); second: the
// motion — 0 stick-slip (α = 0.5, slips twice a period: the second period stops at
// the first repeated slip), 1 lift-off over part of the period, 2 stuck throughout (the closed
// form EvaluateStuckContactLaw, which the AFT tries first).
void BM_ContactLaw(benchmark::State& state) {
  const bool derivatives = state.range(0) != 0;
  const int motion = static_cast<int>(state.range(1));
  constexpr int kSamples = 64;
  const ContactLawParams p{3e5, 2e5, 0.5, 30.0};  // kn, kt [N/m], μ, N0 [N]
  Eigen::VectorXd u(kSamples), v(kSamples);
  const double ua = motion == 2 ? 1e-5 : 4e-4, va = motion == 1 ? 2e-4 : 2e-5;
  for (int k = 0; k < kSamples; ++k) {
    const double th = kTwoPi * k / kSamples;
    u[k] = ua * (std::cos(th) + 0.3 * std::sin(3 * th));
    v[k] = va * std::cos(th + 0.5);
  }
  ContactLawResult r;
  for (auto _ : state) {
    if (motion != 2 || !EvaluateStuckContactLaw(p, u, v, 0.5, derivatives, &r)) {
      EvaluateContactLaw(p, u, v, 0.5, derivatives, &r);
    }
    benchmark::DoNotOptimize(r.tangential.data());
  }
  state.SetLabel(ToString(ClassifyRegime(r.states)));
}
BENCHMARK(BM_ContactLaw)
    ->ArgsProduct({{0, 1}, {0, 1, 2}})
    ->ArgNames({"derivatives", "motion"})
    ->Unit(benchmark::kNanosecond);

}  // namespace

// One BLAS thread unless OPENBLAS_NUM_THREADS says otherwise: the CLI's setting for its
// harmonic-balance commands (fricrom/blas_threads.h), so the figures are the ones users get.
// OpenBLAS's kernels (and threads): the CLI's choice (fricrom/blas_core.h), as above.
int main(int argc, char** argv) {
  fricrom::RestartWithRecommendedBlasCore(argv);
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) fricrom::SetBlasThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
