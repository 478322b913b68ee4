// libFuzzer target for ReadCalculix (prefix.dof, prefix.sti, prefix.mas).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/calculix_fuzz.cpp src/io/*.cpp \
//     -o calculix_fuzz
//   ./calculix_fuzz -max_total_time=30 CORPUS_DIR
// Input: the .dof bytes, then "@@\n" and the .sti bytes, then "@@\n" and the .mas bytes (a
// missing part means a missing file).
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

namespace {

const std::string& TempDir() {
  static const std::string path = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "fricrom-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    return tmpl;
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

// Splits the input at "@@\n" separators (several files from one input).
std::vector<std::string_view> Parts(const uint8_t* data, size_t size) {
  std::string_view all(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> parts;
  while (true) {
    const size_t at = all.find("@@\n");
    parts.push_back(all.substr(0, at));
    if (at == std::string_view::npos) break;
    all.remove_prefix(at + 3);
  }
  return parts;
}

void WriteFile(const std::string& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string_view> parts = Parts(data, size);
  const std::string prefix = TempDir() + "/c";
  const char* ext[3] = {".dof", ".sti", ".mas"};
  for (size_t i = 0; i < 3; ++i) {
    std::error_code ec;
    std::filesystem::remove(prefix + ext[i], ec);
    if (i < parts.size()) WriteFile(prefix + ext[i], parts[i]);
  }
  try {
    CheckModel(fricrom::ReadCalculix(prefix));
  } catch (const fricrom::FeReadError&) {
  }
  return 0;
}
