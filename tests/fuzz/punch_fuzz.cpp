// libFuzzer target for ReadNastranPunch (DMIG, GRID, CORD2R, EXTRN cards).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/punch_fuzz.cpp src/io/*.cpp -o punch_fuzz
//   ./punch_fuzz -max_total_time=30 -dict=... CORPUS_DIR tests/data/dmig tests/data/extseout
// The input bytes are written to a temporary .pch file; any exception other than FeReadError,
// a crash, a sanitizer report or a broken invariant of the result is a finding.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fricrom/fe_model.h"

namespace {

const std::string& TempPath() {
  static const std::string path = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "fricrom-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    return tmpl + "/input.pch";
  }();
  return path;
}

void Check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

void CheckModel(const fricrom::FeModel& model) {
  for (const fricrom::FeMatrix& m : model.matrices) {
    Check(m.real.rows() == m.rows && m.real.cols() == m.cols, "real part shape");
    Check(!m.is_complex || (m.imag.rows() == m.rows && m.imag.cols() == m.cols), "imag shape");
    Check(m.row_dofs.empty() || static_cast<int64_t>(m.row_dofs.size()) == m.rows, "row DOFs");
    Check(m.col_dofs.empty() || static_cast<int64_t>(m.col_dofs.size()) == m.cols, "col DOFs");
    for (int64_t j = 0; j < m.real.outerSize(); ++j) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(m.real, j); it; ++it) {
        Check(std::isfinite(it.value()), "finite values");
        if (m.symmetric) Check(m.real.coeff(it.col(), it.row()) == it.value(), "symmetry");
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  {
    std::ofstream out(TempPath(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    CheckModel(fricrom::ReadNastranPunch(TempPath()));
  } catch (const fricrom::FeReadError&) {
  }
  return 0;
}
