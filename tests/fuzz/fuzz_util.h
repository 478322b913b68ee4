// Shared pieces of the FE-reader libFuzzer targets: a private temp directory, invariants every
// accepted model must satisfy (including the truncation invariant of issue 9: a cut file fails or
// reads as the same matrices), and splitting one input into several files at "@@\n".
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
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
    // Declared symmetric: square, and symmetric to 1e-8 of the largest entry (storage expanded
    // from one triangle is exact; OP4 keeps both triangles as written, round-off included).
    if (m.symmetric) Check(m.rows == m.cols, "a symmetric matrix is square");
    double largest = 0.0;
    for (int64_t j = 0; j < m.real.outerSize(); ++j) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(m.real, j); it; ++it) {
        Check(std::isfinite(it.value()), "finite values");
        largest = std::max(largest, std::abs(it.value()));
      }
    }
    for (int64_t j = 0; m.symmetric && j < m.real.outerSize(); ++j) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(m.real, j); it; ++it) {
        Check(std::abs(m.real.coeff(it.col(), it.row()) - it.value()) <= 1e-8 * largest,
              "symmetry");
      }
    }
  }
}

// Reader options of every target: a memory allowance well under libFuzzer's -malloc_limit_mb, so
// a header declaring 2^31 columns is refused by the reader's memory check, not by libFuzzer.
inline fricrom::FeReadOptions Options(bool coordinate = false) {
  fricrom::FeReadOptions o;
  o.memory_limit_bytes = 256u << 20;
  o.coordinate = coordinate;
  return o;
}

inline bool SameMatrix(const fricrom::FeMatrix& a, const fricrom::FeMatrix& b) {
  // Entry by entry, not through x − y: Eigen reserves 2·max(rows, cols) entries for a sparse
  // expression, which a header declaring ~5·10⁷ columns of a few entries (accepted: its column
  // index fits the reader's memory allowance) turned into a 1.2 GB allocation (op4 fuzz smoke,
  // 2026-11-29; tests/fuzz/regressions/op4/huge_columns_few_entries.op4).
  const auto same = [](const Eigen::SparseMatrix<double>& x, const Eigen::SparseMatrix<double>& y) {
    if (x.rows() != y.rows() || x.cols() != y.cols() || x.nonZeros() != y.nonZeros()) return false;
    for (Eigen::Index c = 0; c < x.outerSize(); ++c) {
      Eigen::SparseMatrix<double>::InnerIterator i(x, c), j(y, c);
      for (; i && j; ++i, ++j) {
        if (i.index() != j.index() || !(i.value() == j.value())) return false;
      }
      if (i || j) return false;
    }
    return true;
  };
  return a.rows == b.rows && a.cols == b.cols && a.is_complex == b.is_complex &&
         a.row_dofs == b.row_dofs && a.col_dofs == b.col_dofs && same(a.real, b.real) &&
         (!a.is_complex || same(a.imag, b.imag));
}

// The coordinate form holds the same entries as the compressed columns (positions where the real
// or the imaginary part is stored, sorted by column then row).
inline void CheckCoordinatesAgree(const fricrom::FeModel& csc, const fricrom::FeModel& coo) {
  Check(csc.matrices.size() == coo.matrices.size(), "coordinate read: matrix count");
  for (size_t i = 0; i < csc.matrices.size(); ++i) {
    const fricrom::FeMatrix& a = csc.matrices[i];
    const fricrom::FeMatrix& b = coo.matrices[i];
    Check(b.coordinate && b.rows == a.rows && b.cols == a.cols, "coordinate read: shape");
    const size_t n = b.coo.re.size();
    Check(b.coo.row.size() == n && b.coo.col.size() == n, "coordinate read: array lengths");
    for (size_t k = 1; k < n; ++k) {
      Check(std::make_pair(b.coo.col[k - 1], b.coo.row[k - 1]) <
                std::make_pair(b.coo.col[k], b.coo.row[k]),
            "coordinate read: sorted, no repeats");
    }
    double diff = 0.0;
    for (size_t k = 0; k < n; ++k) {
      diff += std::abs(a.real.coeff(b.coo.row[k], b.coo.col[k]) - b.coo.re[k]);
    }
    Check(diff == 0.0 && a.real.nonZeros() <= static_cast<int64_t>(n), "coordinate read: values");
  }
}

// Truncation invariant (issue 9): the accepted input `whole` cut at every offset (at most 96,
// spread over the input, plus every line end for inputs under 4 KB) must fail with FeReadError or
// read as matrices each identical to the whole read's matrix of the same name (a cut may drop
// whole matrices). `line_end_ok`: a format without declared counts (Abaqus .mtx, between DMIG
// columns), where a cut exactly at a line end may read as a smaller matrix (documented as
// undetectable in principle); such cuts must still read a valid model.
inline void CheckCuts(std::string_view whole, const fricrom::FeModel& full,
                      const std::function<fricrom::FeModel(std::string_view)>& read_cut,
                      bool line_end_ok) {
  // By name and occurrence: a file may hold two matrices of one name (an OP4 with two "R2"),
  // and the k-th of a name in the cut must be the k-th of that name in the whole file.
  std::map<std::string, std::vector<const fricrom::FeMatrix*>> by_name;
  for (const fricrom::FeMatrix& m : full.matrices) by_name[m.name].push_back(&m);
  std::vector<size_t> cuts;
  const size_t step = whole.size() / 96 + 1;
  for (size_t off = 0; off < whole.size(); off += step) cuts.push_back(off);
  for (size_t off = 1; off < whole.size() && whole.size() < 4096; ++off) {
    if (whole[off - 1] == '\n') cuts.push_back(off);
  }
  for (const size_t off : cuts) {
    fricrom::FeModel cut;
    try {
      cut = read_cut(whole.substr(0, off));
    } catch (const fricrom::FeReadError&) {
      continue;
    }
    CheckModel(cut);
    if (line_end_ok && off > 0 && whole[off - 1] == '\n') continue;
    std::map<std::string, size_t> seen;
    for (const fricrom::FeMatrix& m : cut.matrices) {
      const auto it = by_name.find(m.name);
      const size_t k = seen[m.name]++;
      Check(it != by_name.end() && k < it->second.size() && SameMatrix(m, *it->second[k]),
            "a truncated file read as a different matrix");
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
