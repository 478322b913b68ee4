// Matrix Market coordinate format (real, integer or complex; general or symmetric), reader and
// writer, with the DOF-map sidecar CSV (`node,component` header, one line per row).
// Format notes and the rules chosen here: docs/formats-abaqus-calculix-mtx.md.
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <tuple>
#include <vector>

#include "fe_text.h"
#include "fricrom/fe_model.h"

namespace fricrom {

namespace {

using fe_text::Fail;

// Whitespace-separated tokens (Matrix Market uses blanks only).
void SplitBlanks(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  const size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= n) break;
    const size_t start = i;
    while (i < n && line[i] != ' ' && line[i] != '\t') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
}

constexpr std::string_view kNameComment = "% name:";

// Where the reader is in the text: `line` is line `number` (1-based) of it.
struct Cursor {
  std::string_view text;
  size_t pos = 0;
  size_t number = 0;
  std::string_view line;
  std::vector<std::string_view> tok;

  bool Next() {
    if (!fe_text::NextLine(text, pos, line)) return false;
    ++number;
    return true;
  }
};

// Line 1: "%%MatrixMarket matrix coordinate <field> <symmetry>"; sets m.is_complex, m.symmetric.
void ReadBanner(const std::string& path, Cursor& c, FeMatrix& m) {
  if (!c.Next()) {
    Fail(path, 1,
         "empty file: expected the banner '%%MatrixMarket matrix coordinate real general'");
  }
  std::vector<std::string_view>& tok = c.tok;
  SplitBlanks(c.line, tok);
  if (tok.size() != 5 || fe_text::Upper(tok[0]) != "%%MATRIXMARKET") {
    Fail(path, 1,
         "expected the banner '%%MatrixMarket matrix coordinate <field> <symmetry>', got " +
             fe_text::Printable(c.line));
  }
  const std::string object = fe_text::Upper(tok[1]), format = fe_text::Upper(tok[2]),
                    field = fe_text::Upper(tok[3]), symmetry = fe_text::Upper(tok[4]);
  if (object != "MATRIX") {
    Fail(path, 1, "expected object 'matrix', got " + fe_text::Printable(tok[1]));
  }
  if (format != "COORDINATE") {
    Fail(path, 1,
         "expected format 'coordinate' (sparse), got " + fe_text::Printable(tok[2]) +
             " (the dense 'array' format is not supported)");
  }
  if (field == "PATTERN") {
    Fail(path, 1,
         "a 'pattern' matrix has no values: expected field 'real', 'integer' or "
         "'complex'");
  }
  if (field != "REAL" && field != "INTEGER" && field != "COMPLEX") {
    Fail(path, 1,
         "expected field 'real', 'integer' or 'complex', got " + fe_text::Printable(tok[3]));
  }
  if (symmetry != "GENERAL" && symmetry != "SYMMETRIC") {
    Fail(path, 1,
         "expected symmetry 'general' or 'symmetric', got " + fe_text::Printable(tok[4]) +
             " (skew-symmetric and hermitian are not supported)");
  }
  m.is_complex = field == "COMPLEX";
  m.symmetric = symmetry == "SYMMETRIC";
}

// Checks the dimensions and the entry count of the size line (line `number`).
void CheckSize(const std::string& path, size_t number, const FeMatrix& m, int64_t nnz) {
  if (m.rows < 0 || m.cols < 0 || m.rows > fe_text::kMaxDimension ||
      m.cols > fe_text::kMaxDimension) {
    Fail(path, number,
         "matrix size " + std::to_string(m.rows) + " x " + std::to_string(m.cols) +
             " out of range (expected 0.." + std::to_string(fe_text::kMaxDimension) + ")");
  }
  if (m.symmetric && m.rows != m.cols) {
    Fail(path, number,
         "dimension mismatch: a symmetric matrix must be square, got " + std::to_string(m.rows) +
             " x " + std::to_string(m.cols));
  }
  // rows * cols saturating (dimensions reach 2^53; only the entries cost memory).
  const auto times = [](int64_t x, int64_t y) {
    return x != 0 && y > std::numeric_limits<int64_t>::max() / x
               ? std::numeric_limits<int64_t>::max()
               : x * y;
  };
  const int64_t capacity = m.symmetric ? times(m.rows, m.rows + 1) / 2 : times(m.rows, m.cols);
  if (nnz < 0 || nnz > capacity) {
    Fail(path, number,
         "expected 0.." + std::to_string(capacity) + " entries for a " + std::to_string(m.rows) +
             " x " + std::to_string(m.cols) + " " + (m.symmetric ? "symmetric " : "") +
             "matrix, got " + std::to_string(nnz));
  }
}

// Comments (a "% name:" one renames the matrix), then the size line "rows columns entries":
// sets m.rows, m.cols and returns the entry count.
int64_t ReadSizeLine(const std::string& path, Cursor& c, FeMatrix& m) {
  while (c.Next()) {
    const std::string_view t = fe_text::Trim(c.line);
    if (t.empty()) continue;
    if (t.front() == '%') {
      if (t.substr(0, kNameComment.size()) == kNameComment) {
        const std::string_view name = fe_text::Trim(t.substr(kNameComment.size()));
        if (!name.empty()) m.name = std::string(name);
      }
      continue;
    }
    SplitBlanks(t, c.tok);
    if (c.tok.size() != 3) {
      Fail(path, c.number,
           "expected the size line 'rows columns entries', got " + fe_text::Printable(t));
    }
    m.rows = fe_text::RequireInt(c.tok[0], path, c.number, "the number of rows");
    m.cols = fe_text::RequireInt(c.tok[1], path, c.number, "the number of columns");
    const int64_t nnz = fe_text::RequireInt(c.tok[2], path, c.number, "the number of entries");
    CheckSize(path, c.number, m, nnz);
    return nnz;
  }
  Fail(path, c.number, "truncated file: expected the size line 'rows columns entries'");
}

// The `nnz` entry lines after the size line (0-based indices, not yet range-checked).
std::vector<fe_text::TextEntry> ReadEntries(const std::string& path, Cursor& c, const FeMatrix& m,
                                            int64_t nnz) {
  // The hot loop works on locals (position, token buffer) rather than on the cursor, so that they
  // can stay in registers.
  const std::string_view text = c.text;
  size_t pos = c.pos, number = c.number;
  std::string_view line;
  std::vector<std::string_view> tok;
  tok.swap(c.tok);
  std::vector<fe_text::TextEntry> entries;
  // Each entry line has at least 6 bytes: never trust the header beyond what the file can hold.
  entries.reserve(
      static_cast<size_t>(std::min<int64_t>(nnz, static_cast<int64_t>(text.size() / 6))));
  const size_t fields = m.is_complex ? 4 : 3;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = fe_text::Trim(line);
    if (t.empty() || t.front() == '%') continue;
    if (static_cast<int64_t>(entries.size()) == nnz) {
      Fail(path, number,
           "more entries than the " + std::to_string(nnz) + " declared on the size line");
    }
    SplitBlanks(t, tok);
    if (tok.size() != fields) {
      Fail(path, number,
           "expected '" + std::string(m.is_complex ? "row column real imag" : "row column value") +
               "', got " + std::to_string(tok.size()) + " fields" +
               (tok.size() < fields ? " (truncated line?)" : ""));
    }
    fe_text::TextEntry e;
    e.row = fe_text::RequireInt(tok[0], path, number, "a row index") - 1;
    e.col = fe_text::RequireInt(tok[1], path, number, "a column index") - 1;
    e.re = fe_text::RequireReal(tok[2], false, path, number, "the matrix value");
    if (m.is_complex)
      e.im = fe_text::RequireReal(tok[3], false, path, number, "the imaginary part");
    e.line = number;
    entries.push_back(e);
  }
  if (static_cast<int64_t>(entries.size()) != nnz) {
    Fail(path, number,
         "truncated file: the size line declares " + std::to_string(nnz) + " entries, found " +
             std::to_string(entries.size()));
  }
  c.pos = pos;
  c.number = number;
  return entries;
}

// DOF-map sidecar: one line per row (a square matrix: rows and columns alike), or rows then
// columns.
void AttachDofMap(const std::string& dof_csv, const std::string& path, FeMatrix& m) {
  std::vector<DofId> dofs = fe_text::ReadDofCsv(dof_csv);
  const int64_t n = static_cast<int64_t>(dofs.size());
  if (n == m.rows && m.rows == m.cols) {
    m.row_dofs = dofs;
    m.col_dofs = std::move(dofs);
  } else if (n == m.rows + m.cols && n > 0) {
    m.row_dofs.assign(dofs.begin(), dofs.begin() + m.rows);
    m.col_dofs.assign(dofs.begin() + m.rows, dofs.end());
  } else if (n == m.rows) {
    m.row_dofs = std::move(dofs);
  } else {
    Fail(dof_csv, 0,
         "DOF map has " + std::to_string(n) + " entries but the matrix " + path + " is " +
             std::to_string(m.rows) + " x " + std::to_string(m.cols) + " (expected " +
             std::to_string(m.rows) + " lines for the rows" +
             (m.rows == m.cols
                  ? ""
                  : ", or " + std::to_string(m.rows + m.cols) + " for rows then columns") +
             ")");
  }
}

}  // namespace

FeModel ReadMatrixMarket(const std::string& path, const std::string& dof_csv,
                         const FeReadOptions& options) {
  const std::string text = fe_text::ReadCompleteTextFile(path, "Matrix Market file");
  FeModel model;
  model.source = path;
  model.format = "matrix-market";
  // Filled in place: moving a FeMatrix copies Eigen's per-column index (O(cols) memory).
  FeMatrix& m = model.matrices.emplace_back();
  m.name = std::filesystem::path(path).stem().string();

  Cursor c;
  c.text = text;
  ReadBanner(path, c, m);
  const int64_t nnz = ReadSizeLine(path, c, m);
  const std::vector<fe_text::TextEntry> entries = ReadEntries(path, c, m, nnz);
  fe_text::AssembleEntries(path, entries, m.symmetric, m, {}, options);
  if (!dof_csv.empty()) AttachDofMap(dof_csv, path, m);
  fe_text::KeepOnly(path, options, model);
  return model;
}

namespace {

// Writes `fill` into a sibling temporary file; the caller renames it into place.
class TempFile {
 public:
  explicit TempFile(const std::string& target)
      : target_(target), tmp_(target + ".tmp-" + std::to_string(::getpid())) {
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (!file_) throw std::runtime_error("cannot write " + tmp_);
  }
  ~TempFile() {
    if (file_) std::fclose(file_);
    if (!committed_) {
      std::error_code ec;
      std::filesystem::remove(tmp_, ec);
    }
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  std::FILE* get() { return file_; }
  void Close() {
    const bool bad = std::ferror(file_) != 0;
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (bad || rc != 0) throw std::runtime_error("error while writing " + tmp_);
  }
  void Commit() {
    std::error_code ec;
    std::filesystem::rename(tmp_, target_, ec);
    if (ec) {
      throw std::runtime_error("cannot move " + tmp_ + " to " + target_ + ": " + ec.message());
    }
    committed_ = true;
  }

 private:
  std::string target_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

using Entry = std::tuple<int64_t, int64_t, double, double>;  // row, col, re, im

// Every stored entry of either storage, sorted by column then row (the union of the real and
// imaginary patterns).
std::vector<Entry> SortedEntries(const FeMatrix& m) {
  std::vector<Entry> out;
  if (m.coordinate) {
    out.reserve(m.coo.re.size());
    for (size_t k = 0; k < m.coo.re.size(); ++k) {
      out.emplace_back(m.coo.row[k], m.coo.col[k], m.coo.re[k], m.is_complex ? m.coo.im[k] : 0.0);
    }
    return out;
  }
  Eigen::SparseMatrix<double> re = m.real, im;
  re.makeCompressed();
  if (m.is_complex) {
    im = m.imag;
    im.makeCompressed();
  }
  out.reserve(static_cast<size_t>(re.nonZeros()));
  for (Eigen::Index j = 0; j < re.outerSize(); ++j) {
    if (!m.is_complex) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(re, j); it; ++it) {
        out.emplace_back(it.row(), j, it.value(), 0.0);
      }
      continue;
    }
    Eigen::SparseMatrix<double>::InnerIterator a(re, j), b(im, j);
    while (a || b) {
      int64_t row;
      double vr = 0, vi = 0;
      if (a && (!b || a.row() <= b.row())) {
        row = a.row();
        vr = a.value();
        if (b && b.row() == row) {
          vi = b.value();
          ++b;
        }
        ++a;
      } else {
        row = b.row();
        vi = b.value();
        ++b;
      }
      out.emplace_back(row, j, vr, vi);
    }
  }
  return out;
}

// Every entry has its transpose with the same bits (entries sorted by column, then row).
bool ExactlySymmetric(const std::vector<Entry>& e) {
  const auto by_col_row = [](const Entry& x, const std::pair<int64_t, int64_t>& key) {
    return std::make_pair(std::get<1>(x), std::get<0>(x)) < key;
  };
  for (const auto& [r, c, vr, vi] : e) {
    if (r == c) continue;
    const auto it = std::lower_bound(e.begin(), e.end(), std::make_pair(r, c), by_col_row);
    if (it == e.end() || std::get<0>(*it) != c || std::get<1>(*it) != r || std::get<2>(*it) != vr ||
        std::get<3>(*it) != vi) {
      return false;
    }
  }
  return true;
}

void CheckDofs(const std::vector<DofId>& dofs, const char* what) {
  for (const DofId& d : dofs) {
    if (d.component < 0 || d.component > fe_text::kMaxComponent) {
      throw std::invalid_argument(std::string("WriteMatrixMarket: ") + what + " DOF " +
                                  fe_text::DescribeDof(d) + " has a component outside 0.." +
                                  std::to_string(fe_text::kMaxComponent));
    }
  }
}

}  // namespace

void WriteMatrixMarket(const FeMatrix& matrix, const std::string& path,
                       const std::string& dof_csv) {
  const FeMatrix& m = matrix;
  if (!m.coordinate && (m.real.rows() != m.rows || m.real.cols() != m.cols)) {
    throw std::invalid_argument("WriteMatrixMarket: matrix " + m.name + " is declared " +
                                std::to_string(m.rows) + " x " + std::to_string(m.cols) +
                                " but stores " + std::to_string(m.real.rows()) + " x " +
                                std::to_string(m.real.cols()));
  }
  if (!m.coordinate && m.is_complex && (m.imag.rows() != m.rows || m.imag.cols() != m.cols)) {
    throw std::invalid_argument("WriteMatrixMarket: imaginary part of " + m.name +
                                " has the wrong shape");
  }
  const size_t n = m.coo.re.size();
  if (m.coordinate && (m.coo.row.size() != n || m.coo.col.size() != n ||
                       m.coo.im.size() != (m.is_complex ? n : 0))) {
    throw std::invalid_argument("WriteMatrixMarket: coordinate arrays of " + m.name +
                                " differ in length");
  }
  const bool has_rows = !m.row_dofs.empty(), has_cols = !m.col_dofs.empty();
  if ((has_rows && static_cast<int64_t>(m.row_dofs.size()) != m.rows) ||
      (has_cols && static_cast<int64_t>(m.col_dofs.size()) != m.cols)) {
    throw std::invalid_argument("WriteMatrixMarket: DOF map of " + m.name +
                                " does not match its size");
  }
  if (!has_rows && has_cols) {
    throw std::invalid_argument("WriteMatrixMarket: " + m.name +
                                " has column DOFs but no row DOFs; the sidecar cannot hold that");
  }
  CheckDofs(m.row_dofs, "row");
  CheckDofs(m.col_dofs, "column");

  std::vector<Entry> all = SortedEntries(m);
  const bool symmetric = m.symmetric && m.rows == m.cols && ExactlySymmetric(all);
  // Entries to write: one triangle (row >= col) when symmetric.
  std::vector<Entry> lower;
  if (symmetric) {
    for (const Entry& e : all) {
      if (std::get<0>(e) >= std::get<1>(e)) lower.push_back(e);
    }
    all.swap(lower);
  }
  const std::vector<Entry>& out = all;

  TempFile mtx(path);
  std::FILE* f = mtx.get();
  std::fprintf(f, "%%%%MatrixMarket matrix coordinate %s %s\n", m.is_complex ? "complex" : "real",
               symmetric ? "symmetric" : "general");
  bool printable_name = !m.name.empty();
  for (char c : m.name) printable_name = printable_name && c > ' ' && c < 127;
  if (printable_name) std::fprintf(f, "%s %s\n", kNameComment.data(), m.name.c_str());
  std::fprintf(f, "%" PRId64 " %" PRId64 " %zu\n", m.rows, m.cols, out.size());
  for (const auto& [r, c, vr, vi] : out) {
    if (m.is_complex) {
      std::fprintf(f, "%" PRId64 " %" PRId64 " %.17g %.17g\n", r + 1, c + 1, vr, vi);
    } else {
      std::fprintf(f, "%" PRId64 " %" PRId64 " %.17g\n", r + 1, c + 1, vr);
    }
  }
  mtx.Close();

  if (!has_rows) {
    mtx.Commit();
    return;
  }
  const std::string csv_path = dof_csv.empty() ? fe_text::DefaultDofSidecar(path) : dof_csv;
  TempFile csv(csv_path);
  std::fprintf(csv.get(), "node,component\n");
  const auto write = [&](const std::vector<DofId>& dofs) {
    for (const DofId& d : dofs) std::fprintf(csv.get(), "%" PRId64 ",%d\n", d.node, d.component);
  };
  write(m.row_dofs);
  const bool same = m.rows == m.cols && (!has_cols || m.col_dofs == m.row_dofs);
  if (has_cols && !same) write(m.col_dofs);
  csv.Close();
  mtx.Commit();
  csv.Commit();
}

}  // namespace fricrom
