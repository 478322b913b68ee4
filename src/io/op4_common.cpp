// OUTPUT4 header checks and matrix assembly, shared by the binary and ASCII readers.
#include "op4_common.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "fe_text.h"

namespace fricrom::op4 {

std::string Printable(std::string_view s, size_t max_len) {
  std::string out;
  for (size_t i = 0; i < s.size() && i < max_len; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char* kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (s.size() > max_len) out += "...";
  return out;
}

std::string_view TrimSpaces(std::string_view s) {
  size_t b = 0;
  while (b < s.size() && (s[b] == ' ' || s[b] == '\t')) ++b;
  size_t e = s.size();
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t')) --e;
  return s.substr(b, e - b);
}

std::string TrimName(std::string_view s) {
  size_t e = s.size();
  while (e > 0 && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
  return std::string(s.substr(0, e));
}

std::string CheckHeader(int64_t cols, int64_t rows, int64_t form, int64_t type, std::string name,
                        Header& h) {
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f) {
      return "matrix name '" + Printable(name) + "' has non-printable characters";
    }
  }
  const std::string who = "matrix '" + name + "': ";
  if (type < 1 || type > 4) {
    return who + "unknown type code " + std::to_string(type) +
           " (expected 1 real single, 2 real double, 3 complex single, 4 complex double)";
  }
  if (form < 1 || form > 15) {
    return who + "unknown form code " + std::to_string(form) + " (expected 1..15)";
  }
  if (cols < 0) return who + "negative column count " + std::to_string(cols);
  if (rows == std::numeric_limits<int64_t>::min()) return who + "absurd row count";
  const int64_t abs_rows = rows < 0 ? -rows : rows;
  if (cols > fe_text::kMaxDimension || abs_rows > fe_text::kMaxDimension) {
    return who + "dimensions " + std::to_string(abs_rows) + " x " + std::to_string(cols) +
           " are beyond the supported 2^53 (a corrupt header)";
  }
  if (form == 6 && abs_rows != cols) {
    return who + "form 6 (symmetric) but not square: " + std::to_string(abs_rows) + " x " +
           std::to_string(cols);
  }
  h.name = std::move(name);
  h.cols = cols;
  h.rows = abs_rows;
  h.form = static_cast<int>(form);
  h.type = static_cast<int>(type);
  h.bigmat = rows < 0 || abs_rows >= kBigmatRows;
  return "";
}

std::string MatrixBuilder::StartColumn(int64_t col) {
  const std::string who = "matrix '" + h_.name + "': ";
  if (col < 1 || col > h_.cols) {
    return who + "column index " + std::to_string(col) + " out of range 1.." +
           std::to_string(h_.cols) + " (or " + std::to_string(h_.cols + 1) + " to end the matrix)";
  }
  if (col < col_) {
    return who + "column " + std::to_string(col) + " follows column " + std::to_string(col_) +
           " (columns must ascend)";
  }
  if (col > col_) {
    col_ = col;
    next_row_ = 1;
  }
  return "";
}

std::string MatrixBuilder::BeginRun(int64_t row, int64_t count) {
  const std::string who = "matrix '" + h_.name + "': ";
  if (count < 0) return who + "negative value count";
  if (row < 1 || row > h_.rows) {
    return who + "row " + std::to_string(row) + " of column " + std::to_string(col_) +
           " out of range 1.." + std::to_string(h_.rows);
  }
  if (count > h_.rows - row + 1) {
    return who + "column " + std::to_string(col_) + ": " + std::to_string(count) +
           " values starting at row " + std::to_string(row) + " run past row " +
           std::to_string(h_.rows);
  }
  if (row < next_row_) {
    return who + "column " + std::to_string(col_) + ": row " + std::to_string(row) +
           " given again (rows must ascend within a column)";
  }
  next_row_ = row + count;
  return "";
}

FeMatrix MatrixBuilder::Finish(int precision_bits, const FeReadOptions& options,
                               const std::string& file, const std::string& where) const {
  FeMatrix m;
  m.name = h_.name;
  m.rows = h_.rows;
  m.cols = h_.cols;
  m.symmetric = h_.form == 6;
  m.is_complex = h_.Complex();
  m.source_precision_bits = precision_bits;
  fe_text::CheckStorage(file, where, m, std::max(re_.size(), im_.size()), options);
  if (m.symmetric) {
    const std::string why = Asymmetry(re_, "");
    const std::string why_im = why.empty() && m.is_complex ? Asymmetry(im_, "imaginary ") : "";
    if (!why.empty() || !why_im.empty()) {
      throw FeReadError(file + ": " + where + "matrix '" + m.name + "' is form 6 (symmetric) but " +
                        (why.empty() ? why_im : why));
    }
  }
  if (options.coordinate) {
    BuildCoordinates(m.coo);
    m.coordinate = true;
    return m;
  }
  Build(re_, m.real);
  if (m.is_complex) Build(im_, m.imag);
  return m;
}

// Form 6 promises A = Aᵀ, and OP4 stores both triangles: every stored entry needs its mirror
// within round-off (Nastran's own files differ in the last digits: inboard.op4's KXX by 6e-16
// relative), or the file contradicts its own header. The tolerance is the reduction's
// (relative 1e-8 of the largest entry); a zero is not stored, so a missing mirror is a zero.
// Binary search in the sorted entries: no memory by the columns.
std::string MatrixBuilder::Asymmetry(const std::vector<Entry>& e, const std::string& part) const {
  const auto describe = [&](const Entry& x, double other) {
    std::ostringstream s;
    s.precision(17);
    s << part << "entry (" << x.row + 1 << ", " << x.col + 1 << ") = " << x.value << " and ("
      << x.col + 1 << ", " << x.row + 1 << ") = " << other << " differ by more than "
      << kSymmetryTolerance << " of the largest entry";
    return s.str();
  };
  double largest = 0.0;
  for (const Entry& x : e) largest = std::max(largest, std::abs(x.value));
  const double tolerance = kSymmetryTolerance * largest;
  // The stored columns (by what the file holds, not by its declared size) with their first
  // entry. Visiting the entries column by column, the rows sought in any one mirror column only
  // ascend, so a cursor per column walks each column once.
  std::vector<int64_t> cols;
  std::vector<size_t> begin;
  for (size_t k = 0; k < e.size(); ++k) {
    if (k == 0 || e[k].col != e[k - 1].col) {
      cols.push_back(e[k].col);
      begin.push_back(k);
    }
  }
  std::vector<size_t> cursor = begin;
  begin.push_back(e.size());
  for (const Entry& x : e) {
    if (x.row == x.col) continue;
    double other = 0.0;  // a mirror that is not stored is a zero
    const auto c = std::lower_bound(cols.begin(), cols.end(), x.row);
    if (c != cols.end() && *c == x.row) {
      const size_t k = static_cast<size_t>(c - cols.begin());
      size_t& p = cursor[k];
      while (p < begin[k + 1] && e[p].row < x.col) ++p;
      if (p < begin[k + 1] && e[p].row == x.col) other = e[p].value;
    }
    if (!(std::abs(x.value - other) <= tolerance)) return describe(x, other);
  }
  return "";
}

// Fills the compressed storage directly from the sorted entries: no transposed temporary, so
// only the column count and the entry count cost memory.
void MatrixBuilder::Build(const std::vector<Entry>& e, Eigen::SparseMatrix<double>& out) const {
  out.resize(static_cast<Eigen::Index>(h_.rows), static_cast<Eigen::Index>(h_.cols));
  out.reserve(static_cast<Eigen::Index>(e.size()));
  size_t k = 0;
  for (int j = 0; j < static_cast<int>(h_.cols); ++j) {
    out.startVec(j);
    for (; k < e.size() && e[k].col == j; ++k) {
      out.insertBack(static_cast<int>(e[k].row), j) = e[k].value;
    }
  }
  out.finalize();
}

// Merges the real and imaginary entries (both sorted by column, then row) into one list of the
// positions where either part is stored.
void MatrixBuilder::BuildCoordinates(FeCoordinates& c) const {
  const bool complex = h_.Complex();
  size_t a = 0, b = 0;
  const auto before = [](const Entry& x, const Entry& y) {
    return x.col != y.col ? x.col < y.col : x.row < y.row;
  };
  while (a < re_.size() || (complex && b < im_.size())) {
    const bool take_re = a < re_.size() && (!complex || b >= im_.size() || !before(im_[b], re_[a]));
    const bool take_im = complex && b < im_.size() && (a >= re_.size() || !before(re_[a], im_[b]));
    const Entry& at = take_re ? re_[a] : im_[b];
    c.row.push_back(at.row);
    c.col.push_back(at.col);
    c.re.push_back(take_re ? re_[a++].value : 0.0);
    if (complex) c.im.push_back(take_im ? im_[b++].value : 0.0);
  }
}

}  // namespace fricrom::op4
