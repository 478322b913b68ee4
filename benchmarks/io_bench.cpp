// Reading speed of the ASCII FE formats on generated files of ~10⁶ stored entries (goal: I/O
// bound, ≥ 100 MB/s). Results in benchmarks/README.md.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "fricrom/fe_model.h"

namespace {

namespace fs = std::filesystem;

// A banded symmetric matrix with ~n_entries stored entries (one triangle), random values.
fricrom::FeMatrix Banded(int64_t n, int band) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int64_t j = 0; j < n; ++j) {
    for (int64_t i = j; i < std::min(n, j + band); ++i) {
      const double v = i == j ? 10.0 + u(rng) : u(rng) * 1e5;
      t.emplace_back(i, j, v);
      if (i != j) t.emplace_back(j, i, v);
    }
  }
  fricrom::FeMatrix m;
  m.name.assign(1, 'K');  // (GCC 12 -Wrestrict false positive on = "K")
  m.rows = m.cols = n;
  m.symmetric = true;
  m.real.resize(n, n);
  m.real.setFromTriplets(t.begin(), t.end());
  return m;
}

const fs::path& MatrixMarketFile() {
  static const fs::path path = [] {
    const fs::path p = fs::temp_directory_path() / "fricrom_bench_1e6.mtx";
    fricrom::WriteMatrixMarket(Banded(100000, 10), p.string());  // 10⁶ stored entries
    return p;
  }();
  return path;
}

// Abaqus *MATRIX GENERATE form (node,dof, node,dof, value), one triangle.
const fs::path& AbaqusFile() {
  static const fs::path path = [] {
    const fs::path p = fs::temp_directory_path() / "fricrom_bench_1e6_abaqus.mtx";
    const fricrom::FeMatrix m = Banded(99996, 10);
    std::FILE* f = std::fopen(p.c_str(), "w");
    for (int k = 0; k < m.real.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(m.real, k); it; ++it) {
        if (it.row() < it.col()) continue;
        std::fprintf(f, "%lld,%lld, %lld,%lld, %.17g\n", static_cast<long long>(it.row() / 6 + 1),
                     static_cast<long long>(it.row() % 6 + 1), static_cast<long long>(it.col() / 6 + 1),
                     static_cast<long long>(it.col() % 6 + 1), it.value());
      }
    }
    std::fclose(f);
    return p;
  }();
  return path;
}

void BM_ReadMatrixMarket(benchmark::State& state) {
  const fs::path& p = MatrixMarketFile();
  for (auto _ : state) {
    const fricrom::FeModel m = fricrom::ReadMatrixMarket(p.string());
    benchmark::DoNotOptimize(m.matrices.front().real.nonZeros());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fs::file_size(p)));
}
BENCHMARK(BM_ReadMatrixMarket)->Unit(benchmark::kMillisecond);

void BM_ReadAbaqusMatrix(benchmark::State& state) {
  const fs::path& p = AbaqusFile();
  for (auto _ : state) {
    const fricrom::FeModel m = fricrom::ReadAbaqusMatrix(p.string());
    benchmark::DoNotOptimize(m.matrices.front().real.nonZeros());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fs::file_size(p)));
}
BENCHMARK(BM_ReadAbaqusMatrix)->Unit(benchmark::kMillisecond);

}  // namespace
