// Speed of the condensed harmonic balance on FE-like contact assemblies (issue 10):
// testing::ContactStrip(pairs) - 6·pairs DOFs, `pairs` node-to-node contacts. Results and the
// machine: benchmarks/README.md.
#include <benchmark/benchmark.h>

#include <memory>

#include "fricrom/condensed_system.h"
#include "fricrom/frf.h"
#include "fricrom/hbm_system.h"
#include "fricrom/units.h"
#include "test_models.h"

namespace {

using namespace fricrom;
constexpr double kFreq = 1000.0;

// Residual + exact Jacobian at a converged state, frequency unchanged (receptance reused).
void BM_CondensedResidualJacobian(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  CondensedSystem sys(testing::ContactStrip(pairs), HbmOptions{h, 64});
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  const FrfPoint p = SolveAtFrequency(sys, alpha, kFreq, Eigen::VectorXd(), FrfOptions{});
  // Two points in turn: the system keeps the last point's contact forces, and the same x every
  // time would leave the AFT out of the measurement.
  const Eigen::VectorXd xs[2] = {p.x, 1.0001 * p.x};
  HbmEvaluation e;
  int k = 0;
  for (auto _ : state) {
    sys.Evaluate(xs[k++ % 2], kTwoPi * kFreq, alpha, HbmRequest{true, false, false}, &e);
    benchmark::DoNotOptimize(e.jacobian.data());
  }
  state.counters["unknowns"] = sys.num_unknowns();
  state.counters["converged"] = p.status == SolverStatus::kConverged;
}
BENCHMARK(BM_CondensedResidualJacobian)
    ->Args({50, 1})
    ->Args({100, 1})
    ->Args({200, 1})
    ->Args({100, 3})
    ->Unit(benchmark::kMillisecond);

// One converged solve at one frequency from the stick start (receptance factorised inside).
void BM_CondensedSolve(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  CondensedSystem sys(testing::ContactStrip(pairs), HbmOptions{h, 64});
  int converged = 0;
  for (auto _ : state) {
    CondensedSystem fresh(testing::ContactStrip(pairs), HbmOptions{h, 64});  // cold receptance
    const FrfPoint p = SolveAtFrequency(fresh, alpha, kFreq, Eigen::VectorXd(), FrfOptions{});
    converged = p.status == SolverStatus::kConverged;
    benchmark::DoNotOptimize(p.amplitude);
  }
  state.counters["converged"] = converged;
}
BENCHMARK(BM_CondensedSolve)
    ->Args({50, 1})
    ->Args({100, 1})
    ->Args({200, 1})
    ->Args({100, 3})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// The same cold solve with the modal receptance (one eigen-decomposition inside).
void BM_CondensedSolveModal(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  const HbmOptions options{h, 64, ReceptanceMethod::kModal};
  int converged = 0;
  for (auto _ : state) {
    CondensedSystem fresh(testing::ContactStrip(pairs), options);
    const FrfPoint p = SolveAtFrequency(fresh, alpha, kFreq, Eigen::VectorXd(), FrfOptions{});
    converged = p.status == SolverStatus::kConverged;
    benchmark::DoNotOptimize(p.amplitude);
  }
  state.counters["converged"] = converged;
}
BENCHMARK(BM_CondensedSolveModal)
    ->Args({50, 1})
    ->Args({100, 1})
    ->Args({200, 1})
    ->Args({400, 1})
    ->Args({100, 3})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// One converged solve at a new frequency on a model set up once (modal receptance: the
// eigen-decomposition is the model's, done once; the receptance at ω, the fixed-load responses
// and Newton from the stick start are the solve's). Alternating frequencies force G_h(ω) anew.
void BM_CondensedSolveNewFrequency(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  CondensedSystem sys(testing::ContactStrip(pairs), HbmOptions{h, 64, ReceptanceMethod::kModal});
  int converged = 0, k = 0;
  for (auto _ : state) {
    const double f = kFreq + ((k++ % 2) ? 1.0 : 0.0);
    const FrfPoint p = SolveAtFrequency(sys, alpha, f, Eigen::VectorXd(), FrfOptions{});
    converged = p.status == SolverStatus::kConverged;
    benchmark::DoNotOptimize(p.amplitude);
  }
  state.counters["converged"] = converged;
}
BENCHMARK(BM_CondensedSolveNewFrequency)
    ->Args({50, 1})
    ->Args({100, 1})
    ->Args({200, 1})
    ->Args({400, 1})
    ->Args({100, 3})
    ->Unit(benchmark::kMillisecond);

// A continuation in frequency's work per corrector step (modal receptance), from a converged
// state: the residual and ∂R/∂ω at a new ω, the matrix-free Jacobian there and five products
// (GMRES). Since the twenty-second session no G_h is formed for it (products through the modes)
// and no Z_h solved (∂x̃/∂ω in modal coordinates).
void BM_FrequencyFamilyStep(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  CondensedSystem sys(testing::ContactStrip(pairs), HbmOptions{h, 64, ReceptanceMethod::kModal});
  const FrfPoint p = SolveAtFrequency(sys, alpha, kFreq, Eigen::VectorXd(), FrfOptions{});
  const HbmFrequencyFamily family(sys, alpha);
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(p.x.size(), -1.0, 1.0);
  Eigen::VectorXd r, dr, jv;
  int k = 0;
  for (auto _ : state) {
    const double w = kTwoPi * (kFreq + 1e-3 * (1 + k++ % 64));  // a new ω every step
    family.Evaluate(p.x, w, &r, nullptr, &dr);
    const std::unique_ptr<JacobianOperator> op = family.Linearize(p.x, w, &dr);
    for (int m = 0; m < 5; ++m) op->Apply(v, m % 2 == 1, &jv);
    benchmark::DoNotOptimize(jv.data());
  }
  state.counters["unknowns"] = sys.num_unknowns();
  state.counters["converged"] = p.status == SolverStatus::kConverged;
}
BENCHMARK(BM_FrequencyFamilyStep)
    ->Args({100, 1})
    ->Args({200, 1})
    ->Args({100, 3})
    ->Unit(benchmark::kMillisecond);

// The same solve through the full (uncondensed) balance, for the ratio.
void BM_FullSolve(benchmark::State& state) {
  const int pairs = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(pairs, -0.9, 0.9);
  HbmSystem sys(testing::ContactStrip(pairs), HbmOptions{h, 64});
  for (auto _ : state) {
    const FrfPoint p = SolveAtFrequency(sys, alpha, kFreq, Eigen::VectorXd(), FrfOptions{});
    benchmark::DoNotOptimize(p.amplitude);
  }
}
BENCHMARK(BM_FullSolve)
    ->Args({50, 1})
    ->Args({100, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace
