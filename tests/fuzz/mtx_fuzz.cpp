// libFuzzer target for ReadMatrixMarket and, on what it accepts, the WriteMatrixMarket ->
// ReadMatrixMarket round trip (which must give back the same bits).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/mtx_fuzz.cpp src/io/*.cpp -o mtx_fuzz
//   ./mtx_fuzz -max_total_time=30 CORPUS_DIR tests/data/mtx
// Input: the .mtx bytes, optionally followed by "@@\n" and a DOF-map CSV.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "fricrom/fe_model.h"
#include "fuzz_util.h"

using namespace fricrom_fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string_view> parts = Parts(data, size);
  const std::string mtx = TempDir() + "/m.mtx", csv = TempDir() + "/m.csv";
  const std::string out = TempDir() + "/out.mtx", out_csv = TempDir() + "/out.csv";
  WriteFile(mtx, parts[0]);
  if (parts.size() > 1) WriteFile(csv, parts[1]);
  fricrom::FeModel model;
  try {
    model = fricrom::ReadMatrixMarket(mtx, parts.size() > 1 ? csv : "", Options());
  } catch (const fricrom::FeReadError&) {
    return 0;
  }
  CheckModel(model);
  const fricrom::FeMatrix& m = model.matrices.at(0);
  {
    fricrom::WriteMatrixMarket(m, out, out_csv);
    const bool has_map = !m.row_dofs.empty();
    const fricrom::FeMatrix back =
        fricrom::ReadMatrixMarket(out, has_map ? out_csv : "").matrices.at(0);
    Check(back.rows == m.rows && back.cols == m.cols, "round trip shape");
    Check(back.is_complex == m.is_complex, "round trip complex flag");
    Check(back.real.nonZeros() == m.real.nonZeros(), "round trip pattern");
    for (int64_t j = 0; j < m.real.outerSize(); ++j) {
      Eigen::SparseMatrix<double>::InnerIterator a(m.real, j), b(back.real, j);
      for (; a && b; ++a, ++b) {
        const double x = a.value(), y = b.value();
        Check(a.row() == b.row() && std::memcmp(&x, &y, sizeof x) == 0, "round trip bits");
      }
    }
    Check(back.row_dofs == m.row_dofs, "round trip row DOFs");
    if (m.rows != m.cols || m.col_dofs == m.row_dofs) {
      Check(back.col_dofs == m.col_dofs, "round trip column DOFs");
    }
  }
  CheckCoordinatesAgree(model,
                        fricrom::ReadMatrixMarket(mtx, parts.size() > 1 ? csv : "", Options(true)));
  // Truncation (issue 9): Matrix Market declares its entry count, so no cut may read as another
  // matrix, not even one exactly at a line end.
  CheckCuts(
      parts[0], model,
      [&](std::string_view cut) {
        WriteFile(mtx, cut);
        return fricrom::ReadMatrixMarket(mtx, parts.size() > 1 ? csv : "", Options());
      },
      false);
  return 0;
}
