// Shared pieces of the FE-reader libFuzzer targets: a private temp directory, invariants every
// accepted model must satisfy, and splitting one input into several files at "@@\n".
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom_fuzz {

inline const std::string& TempDir() {
  static const std::string path = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "fricrom-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    return tmpl;
  }();
  return path;
}

inline void Check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

inline void CheckModel(const fricrom::FeModel& model) {
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
inline std::vector<std::string_view> Parts(const uint8_t* data, size_t size) {
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

inline void WriteFile(const std::string& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace fricrom_fuzz
