// Speed of dense::Lu on the condensed balance's pattern (issue 11): n = 975 unknowns (the coarse
// cascade at H = 1), of which 450 columns are unit outside 325 "mean" rows — as the harmonics of
// fully stuck contacts at the bounds. The same matrix with those columns made dense (a tiny
// entry in every row) cannot be split: the A/B of the Schur elimination, single precision as the
// GMRES preconditioner uses it. Results and the machine: benchmarks/README.md.
#include <benchmark/benchmark.h>

#include "fricrom/blas_threads.h"
#include "linear/dense_lapack.h"
#include "test_models.h"

namespace {

using namespace fricrom;

Eigen::MatrixXd CondensedPattern(bool splittable) {
  constexpr int kN = 975, kMean = 325, kStuck = 450;
  Eigen::MatrixXd a =
      testing::SeededRandom(kN, kN, 41) + 0.5 * kN * Eigen::MatrixXd::Identity(kN, kN);
  for (int c = kMean; c < kMean + kStuck; ++c) {
    const double d = a(c, c);
    a.col(c).tail(kN - kMean).setConstant(splittable ? 0.0 : 1e-9);
    a(c, c) = d;
  }
  return a;
}

void BM_LuFactor(benchmark::State& state) {
  SetBlasThreads(1);
  const Eigen::MatrixXd a = CondensedPattern(state.range(0) != 0);
  dense::Lu lu;
  for (auto _ : state) {
    lu.Compute(a, dense::LuPrecision::kSingle);
    benchmark::DoNotOptimize(lu.rcond());
  }
  state.counters["split_columns"] = static_cast<double>(lu.num_unit_columns());
  state.counters["fill_rows"] = static_cast<double>(lu.num_fill_rows());
}
BENCHMARK(BM_LuFactor)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One preconditioner application, as in each GMRES iteration (direct and transposed).
void BM_LuSolve(benchmark::State& state) {
  SetBlasThreads(1);
  const Eigen::MatrixXd a = CondensedPattern(state.range(0) != 0);
  const dense::Lu lu(a, dense::LuPrecision::kSingle);
  const Eigen::VectorXd b = testing::SeededRandom(a.rows(), 1, 42);
  const bool transposed = state.range(1) != 0;
  for (auto _ : state) {
    const Eigen::VectorXd x = lu.Solve(b, transposed);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["split_columns"] = static_cast<double>(lu.num_unit_columns());
}
BENCHMARK(BM_LuSolve)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
