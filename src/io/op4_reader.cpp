// Nastran OUTPUT4 (.op4) reader: ASCII and binary files, little and big endian, 4- or 8-byte
// Fortran record markers, 32- or 64-bit integer words; dense, non-bigmat sparse and bigmat
// sparse columns; real and complex, single and double precision. See
// docs/formats-nastran-op4.md for the layout and the limits.
//
// Entries are checked as they are read (row/column ranges, ascending order, finite values) and
// each matrix is assembled only when its end record has been read; nothing is returned unless
// the whole file reads cleanly.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom {
namespace {

// Eigen's sparse matrices index with int.
constexpr int64_t kMaxEigenDim = std::numeric_limits<int>::max() - 1;
// The column count sizes the outer index arrays allocated up front (4 bytes per column, for the
// real and the imaginary part). Nastran writes sparse matrices of 10^7 columns with a handful of
// terms (pyyeti's nas_large_dim_bigmat_binary.op4), so the allowance is set by memory: 10^8
// columns (400 MB), as for the text formats; beyond it the file size must justify the count.
// Rows cost no memory of their own (the matrices are built column by column).
constexpr int64_t kFreeCols = 100'000'000;
constexpr uint64_t kColsPerFileByte = 8;
constexpr int64_t kFreeRows = int64_t{1} << 26;
constexpr uint64_t kRowsPerFileByte = 64;
// Non-bigmat sparse strings pack the row into the low 16 bits.
constexpr int64_t kBigmatRows = 65536;

std::string Printable(std::string_view s, size_t max_len = 40) {
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

// Header of one matrix, common to both encodings.
struct Header {
  std::string name;
  int64_t cols = 0;
  int64_t rows = 0;  // absolute value of the stored row count
  int form = 0;
  int type = 0;
  bool bigmat = false;
  bool Complex() const { return type >= 3; }
  // Words per stored number: double precision in 32-bit words takes two.
  int WordsPerNumber(bool wide_words) const { return (type == 2 || type == 4) && !wide_words ? 2 : 1; }
};

// Checks the header fields and fills `h`; returns an error text or "".
std::string CheckHeader(int64_t cols, int64_t rows, int64_t form, int64_t type, std::string name,
                        size_t file_size, Header& h) {
  auto limit = [file_size](int64_t free, uint64_t per_byte) {
    const auto max64 = static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
    const uint64_t by_size = file_size > max64 / per_byte
                                 ? max64
                                 : static_cast<uint64_t>(file_size) * per_byte;
    return std::min<int64_t>(kMaxEigenDim,
                             std::max<int64_t>(free, static_cast<int64_t>(by_size)));
  };
  const int64_t col_limit = limit(kFreeCols, kColsPerFileByte);
  const int64_t row_limit = limit(kFreeRows, kRowsPerFileByte);
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
  if (cols > col_limit || abs_rows > row_limit) {
    return who + "dimensions " + std::to_string(abs_rows) + " x " + std::to_string(cols) +
           " are implausible for a file of " + std::to_string(file_size) + " bytes (limits " +
           std::to_string(row_limit) + " rows, " + std::to_string(col_limit) + " columns)";
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

// Collects the entries of one matrix, checking that runs of rows stay inside the matrix, that
// columns ascend and that no row of a column is given twice.
class MatrixBuilder {
 public:
  explicit MatrixBuilder(Header h) : h_(std::move(h)) {}

  const Header& header() const { return h_; }

  // Starts (or continues) 1-based column `col`: in range, not before the current column.
  std::string StartColumn(int64_t col) {
    const std::string who = "matrix '" + h_.name + "': ";
    if (col < 1 || col > h_.cols) {
      return who + "column index " + std::to_string(col) + " out of range 1.." +
             std::to_string(h_.cols) + " (or " + std::to_string(h_.cols + 1) +
             " to end the matrix)";
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

  // A run of `count` entries of the current column starting at 1-based `row`.
  std::string BeginRun(int64_t row, int64_t count) {
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

  // Entries arrive sorted by column, then row (StartColumn/BeginRun enforce it).
  void Add(int64_t row, int64_t col, double re, double im) {
    if (re != 0.0) re_.push_back({static_cast<int>(row - 1), static_cast<int>(col - 1), re});
    if (im != 0.0) im_.push_back({static_cast<int>(row - 1), static_cast<int>(col - 1), im});
  }

  FeMatrix Finish(int precision_bits) {
    FeMatrix m;
    m.name = h_.name;
    m.rows = h_.rows;
    m.cols = h_.cols;
    m.symmetric = h_.form == 6;
    m.is_complex = h_.Complex();
    m.source_precision_bits = precision_bits;
    Build(re_, m.real);
    if (m.is_complex) Build(im_, m.imag);
    return m;
  }

 private:
  struct Entry {
    int row;
    int col;
    double value;
  };

  // Fills the compressed storage directly from the sorted entries: no transposed temporary,
  // so only the column count and the entry count cost memory.
  void Build(const std::vector<Entry>& e, Eigen::SparseMatrix<double>& out) const {
    out.resize(static_cast<Eigen::Index>(h_.rows), static_cast<Eigen::Index>(h_.cols));
    out.reserve(static_cast<Eigen::Index>(e.size()));
    size_t k = 0;
    for (int j = 0; j < static_cast<int>(h_.cols); ++j) {
      out.startVec(j);
      for (; k < e.size() && e[k].col == j; ++k) out.insertBack(e[k].row, j) = e[k].value;
    }
    out.finalize();
  }

  Header h_;
  int64_t col_ = 0;
  int64_t next_row_ = 1;
  std::vector<Entry> re_;
  std::vector<Entry> im_;
};

// ------------------------------------------------------------------------------------------
// Binary
// ------------------------------------------------------------------------------------------

struct BinaryLayout {
  bool big_endian = false;
  int marker_bytes = 4;  // Fortran record marker
  int int_bytes = 4;     // header/column integers, and the word size of the data
  int name_bytes = 8;
};

class BinaryOp4 {
 public:
  BinaryOp4(const std::string& path, std::string_view data, BinaryLayout layout)
      : path_(path), data_(data), layout_(layout) {}

  FeModel Read() {
    FeModel model;
    model.source = path_;
    model.format = "op4";
    while (pos_ < data_.size()) model.matrices.push_back(ReadMatrix());
    return model;
  }

  // Reads a marker of `bytes` bytes at `off` (caller checked the bounds).
  static int64_t Marker(std::string_view data, size_t off, int bytes, bool big) {
    const uint64_t u = Raw(data, off, bytes, big);
    return bytes == 4 ? static_cast<int64_t>(static_cast<int32_t>(static_cast<uint32_t>(u)))
                      : static_cast<int64_t>(u);
  }

 private:
  struct Record {
    size_t begin = 0;  // first payload byte
    size_t size = 0;   // payload bytes
  };

  static uint64_t Raw(std::string_view data, size_t off, int bytes, bool big) {
    uint64_t u = 0;
    for (int i = 0; i < bytes; ++i) {
      const auto b = static_cast<uint8_t>(data[off + static_cast<size_t>(i)]);
      if (big) {
        u = (u << 8) | b;
      } else {
        u |= static_cast<uint64_t>(b) << (8 * i);
      }
    }
    return u;
  }

  [[noreturn]] void Fail(size_t offset, const std::string& what) const {
    throw FeReadError(path_ + ": byte offset " + std::to_string(offset) + ": " + what);
  }

  int64_t Int(size_t off) const {
    return Marker(data_, off, layout_.int_bytes, layout_.big_endian);
  }

  double Real(size_t off, int bytes) const {
    const uint64_t u = Raw(data_, off, bytes, layout_.big_endian);
    if (bytes == 4) {
      float f;
      const auto u32 = static_cast<uint32_t>(u);
      std::memcpy(&f, &u32, sizeof f);
      return static_cast<double>(f);
    }
    double d;
    std::memcpy(&d, &u, sizeof d);
    return d;
  }

  Record NextRecord(const std::string& expected) {
    const auto m = static_cast<size_t>(layout_.marker_bytes);
    const size_t left = data_.size() - pos_;
    if (left < m) {
      Fail(pos_, "unexpected end of file (truncated?): expected the record marker of " + expected +
                     ", found " + std::to_string(left) + " bytes");
    }
    const int64_t n = Marker(data_, pos_, layout_.marker_bytes, layout_.big_endian);
    if (n < 0) {
      Fail(pos_, "bad record marker " + std::to_string(n) + " (negative length) for " + expected);
    }
    if (static_cast<uint64_t>(n) > left - m || left - m - static_cast<size_t>(n) < m) {
      Fail(pos_, "record marker says " + std::to_string(n) + " bytes for " + expected + " but only " +
                     std::to_string(left - m) +
                     " bytes follow (truncated file or bad record marker)");
    }
    const size_t end = pos_ + m + static_cast<size_t>(n);
    const int64_t tail = Marker(data_, end, layout_.marker_bytes, layout_.big_endian);
    if (tail != n) {
      Fail(end, "record end marker " + std::to_string(tail) + " does not match the start marker " +
                    std::to_string(n) + " at byte offset " + std::to_string(pos_) + " (" +
                    expected + ")");
    }
    Record r{pos_ + m, static_cast<size_t>(n)};
    pos_ = end + m;
    return r;
  }

  FeMatrix ReadMatrix() {
    const size_t header_at = pos_;
    const Record hr = NextRecord("a matrix header");
    const auto ib = static_cast<size_t>(layout_.int_bytes);
    const size_t want = 4 * ib + static_cast<size_t>(layout_.name_bytes);
    if (hr.size != want) {
      Fail(header_at, "expected a matrix header record of " + std::to_string(want) +
                          " bytes, found a record of " + std::to_string(hr.size) + " bytes");
    }
    const int64_t cols = Int(hr.begin);
    const int64_t rows = Int(hr.begin + ib);
    const int64_t form = Int(hr.begin + 2 * ib);
    const int64_t type = Int(hr.begin + 3 * ib);
    std::string name =
        TrimName(data_.substr(hr.begin + 4 * ib, static_cast<size_t>(layout_.name_bytes)));
    Header h;
    if (std::string err = CheckHeader(cols, rows, form, type, std::move(name), data_.size(), h);
        !err.empty()) {
      Fail(header_at, err);
    }
    MatrixBuilder b(h);

    const bool wide = layout_.int_bytes == 8;
    const auto w = static_cast<size_t>(layout_.int_bytes);         // bytes per word
    const int wpn = h.WordsPerNumber(wide);                          // words per number
    const int value_bytes = (h.type == 1 || h.type == 3) ? layout_.int_bytes : 8;
    const int64_t unit = static_cast<int64_t>(wpn) * (h.Complex() ? 2 : 1);  // words per entry
    const std::string what = "column record of matrix '" + h.name + "'";

    // Reads `count` entries at byte `p` into column `col` starting at row `row`.
    auto values = [&](size_t p, int64_t col, int64_t row, int64_t count) {
      const size_t step = static_cast<size_t>(unit) * w;
      for (int64_t k = 0; k < count; ++k, p += step) {
        const double re = Real(p, value_bytes);
        const double im = h.Complex() ? Real(p + static_cast<size_t>(value_bytes), value_bytes) : 0.0;
        if (!std::isfinite(re) || !std::isfinite(im)) {
          Fail(p, "matrix '" + h.name + "': expected a finite number at row " +
                      std::to_string(row + k) + ", column " + std::to_string(col) +
                      ", found NaN or infinity");
        }
        b.Add(row + k, col, re, im);
      }
    };

    for (;;) {
      const size_t rec_at = pos_;
      const Record r = NextRecord("a " + what);
      if (r.size < 3 * w) {
        Fail(rec_at, "expected a " + what + " of at least " + std::to_string(3 * w) +
                         " bytes, found " + std::to_string(r.size) + " bytes");
      }
      const int64_t icol = Int(r.begin);
      const int64_t irow = Int(r.begin + w);
      const int64_t nwords = Int(r.begin + 2 * w);
      if (icol == h.cols + 1) break;  // end-of-matrix record; its dummy value is not used
      if (std::string err = b.StartColumn(icol); !err.empty()) Fail(r.begin, err);
      const size_t data_bytes = r.size - 3 * w;
      if (nwords < 0 || data_bytes % w != 0 ||
          static_cast<uint64_t>(nwords) != data_bytes / w) {
        Fail(r.begin + 2 * w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                                  ": word count " + std::to_string(nwords) +
                                  " does not match the record length (" +
                                  std::to_string(data_bytes) + " data bytes, " +
                                  std::to_string(w) + " per word)");
      }
      size_t p = r.begin + 3 * w;
      if (irow > 0) {  // dense: consecutive rows from irow
        if (nwords % unit != 0) {
          Fail(r.begin + 2 * w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                                    ": word count " + std::to_string(nwords) +
                                    " is not a multiple of " + std::to_string(unit) +
                                    " words per entry");
        }
        const int64_t count = nwords / unit;
        if (std::string err = b.BeginRun(irow, count); !err.empty()) Fail(r.begin + w, err);
        values(p, icol, irow, count);
      } else if (irow == 0) {  // sparse: strings of consecutive rows
        int64_t left = nwords;
        while (left > 0) {
          const size_t string_at = p;
          int64_t words = 0;
          int64_t row = 0;
          int64_t head = 0;
          if (h.bigmat) {
            if (left < 2) {
              Fail(p, "matrix '" + h.name + "', column " + std::to_string(icol) +
                          ": expected a 2-word bigmat string header, only " +
                          std::to_string(left) + " word left in the record");
            }
            const int64_t len = Int(p);
            row = Int(p + w);
            words = len < 1 ? 0 : len - 1;  // len < 2 is rejected below
            head = 2;
          } else {
            const int64_t is = Int(p);
            if (is <= 0) {
              Fail(p, "matrix '" + h.name + "', column " + std::to_string(icol) +
                          ": bad sparse string header " + std::to_string(is));
            }
            words = (is >> 16) - 1;
            row = is & 0xFFFF;
            head = 1;
          }
          if (words < 1 || words > left - head || words % unit != 0) {
            Fail(string_at, "matrix '" + h.name + "', column " + std::to_string(icol) +
                                ": bad sparse string length " + std::to_string(words) +
                                " words (expected a positive multiple of " +
                                std::to_string(unit) + " within the " + std::to_string(left) +
                                " words left in the record)");
          }
          const int64_t count = words / unit;
          if (std::string err = b.BeginRun(row, count); !err.empty()) Fail(string_at, err);
          p += static_cast<size_t>(head) * w;
          values(p, icol, row, count);
          p += static_cast<size_t>(words) * w;
          left -= head + words;
        }
      } else {
        Fail(r.begin + w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                              ": negative row index " + std::to_string(irow));
      }
    }
    // 64-bit-word files store types 1 and 3 in 8-byte reals as well.
    return b.Finish(value_bytes == 4 ? 32 : 64);
  }

  const std::string& path_;
  std::string_view data_;
  BinaryLayout layout_;
  size_t pos_ = 0;
};

// Finds the binary layout from the first record: its length is 24 (4-byte integers, 8-byte
// name), 40 or 48 (8-byte integers, 8- or 16-byte name), in either byte order, with 4- or 8-byte
// markers. Returns nullopt when no layout matches; `near_miss` then describes a layout whose
// start marker matched but whose record did not (truncated header, mismatched end marker).
std::optional<BinaryLayout> DetectBinary(std::string_view data, std::string& near_miss) {
  for (const int m : {4, 8}) {
    for (const bool big : {false, true}) {
      if (data.size() < static_cast<size_t>(m)) continue;
      const int64_t n = BinaryOp4::Marker(data, 0, m, big);
      if (n != 24 && n != 40 && n != 48) continue;
      const size_t end = static_cast<size_t>(m) + static_cast<size_t>(n);
      if (data.size() < end + static_cast<size_t>(m)) {
        if (near_miss.empty()) {
          near_miss = "the first record marker announces a " + std::to_string(n) +
                      "-byte header but the file has only " + std::to_string(data.size()) +
                      " bytes (truncated)";
        }
        continue;
      }
      const int64_t tail = BinaryOp4::Marker(data, end, m, big);
      if (tail != n) {
        if (near_miss.empty()) {
          near_miss = "header record end marker at byte offset " + std::to_string(end) + " is " +
                      std::to_string(tail) + ", expected " + std::to_string(n);
        }
        continue;
      }
      BinaryLayout l;
      l.big_endian = big;
      l.marker_bytes = m;
      l.int_bytes = n == 24 ? 4 : 8;
      l.name_bytes = static_cast<int>(n) - 4 * l.int_bytes;
      return l;
    }
  }
  return std::nullopt;
}

// ------------------------------------------------------------------------------------------
// ASCII
// ------------------------------------------------------------------------------------------

class AsciiOp4 {
 public:
  AsciiOp4(const std::string& path, std::string_view data) : path_(path), data_(data) {}

  FeModel Read() {
    FeModel model;
    model.source = path_;
    model.format = "op4";
    for (;;) {
      std::string_view line;
      bool got = false;
      while ((got = NextLine(line)) && TrimSpaces(line).empty()) {
      }
      if (!got) break;
      model.matrices.push_back(ReadMatrix(line));
    }
    if (model.matrices.empty()) Fail(line_no_ + 1, "expected an OP4 matrix header, found no data");
    return model;
  }

 private:
  [[noreturn]] void Fail(int64_t line, const std::string& what) const {
    throw FeReadError(path_ + ": line " + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void Fail(const std::string& what) const { Fail(line_no_, what); }

  bool NextLine(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    size_t end = data_.find('\n', pos_);
    if (end == std::string_view::npos) end = data_.size();
    line = data_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++line_no_;
    return true;
  }

  std::string_view RequireLine(const std::string& expected) {
    std::string_view line;
    if (!NextLine(line)) {
      Fail(line_no_ + 1, "unexpected end of file (truncated?): expected " + expected);
    }
    return line;
  }

  // Integer in line[start, start+width) (width npos: to the end of the line).
  int64_t IntField(std::string_view line, size_t start, size_t width, const char* what) {
    const std::string_view raw = start < line.size() ? line.substr(start, width) : std::string_view();
    const std::string_view s = TrimSpaces(raw);
    int64_t v = 0;
    const char* first = s.data();
    const char* last = s.data() + s.size();
    if (!s.empty() && *first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (s.empty() || ec != std::errc() || ptr != last) {
      const std::string cols = width == std::string_view::npos
                                   ? "from column " + std::to_string(start + 1)
                                   : "in columns " + std::to_string(start + 1) + "-" +
                                         std::to_string(start + width);
      Fail("expected an integer (" + std::string(what) + ") " + cols + ", found '" +
           Printable(raw) + "'");
    }
    return v;
  }

  // Parses one fixed-width number field: Fortran E or D exponent, also the exponent without
  // its letter that Fortran writes for three-digit exponents (1.0-100).
  double Number(std::string_view raw, size_t field_index) {
    const std::string_view s = TrimSpaces(raw);
    char buf[80];
    size_t n = 0;
    bool ok = !s.empty() && s.size() < sizeof buf - 2;
    bool has_exp = false;
    for (size_t i = 0; ok && i < s.size(); ++i) {
      char c = s[i];
      if (c == 'D' || c == 'd' || c == 'E' || c == 'e') {
        c = 'E';
        has_exp = true;
      } else if ((c == '+' || c == '-') && i > 0 && !has_exp) {
        const char prev = s[i - 1];
        if ((prev >= '0' && prev <= '9') || prev == '.') {
          buf[n++] = 'E';
          has_exp = true;
        }
      }
      buf[n++] = c;
    }
    double v = 0.0;
    const char* first = buf;
    const char* last = buf + n;
    if (ok && first < last && *first == '+') ++first;
    if (ok) {
      const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
      ok = ec == std::errc() && ptr == last;
      if (ec == std::errc::result_out_of_range) {
        Fail("number " + std::to_string(field_index + 1) + " on the line, '" + Printable(s) +
             "', is out of double-precision range");
      }
    }
    if (!ok) {
      Fail("expected a number in field " + std::to_string(field_index + 1) + ", found '" +
           Printable(raw) + "'");
    }
    if (!std::isfinite(v)) {
      Fail("expected a finite number in field " + std::to_string(field_index + 1) + ", found '" +
           Printable(s) + "' (NaN or infinity)");
    }
    return v;
  }

  // Field `i` of a value line that should hold `k` numbers. Fortran writes every field in full
  // width (right-aligned), so a short field means a cut line.
  double Field(std::string_view line, size_t i, int64_t k, const std::string& what) {
    const size_t start = i * width_;
    if (start >= line.size() || TrimSpaces(line.substr(start)).empty()) {
      Fail("expected " + std::to_string(k) + " numbers of " + what + " on this line, found " +
           std::to_string(i));
    }
    if (line.size() - start < width_) {
      Fail("number field " + std::to_string(i + 1) + " of " + what + ", '" +
           Printable(line.substr(start)) + "', is shorter than the format's " +
           std::to_string(width_) + " characters (cut line?)");
    }
    return Number(line.substr(start, width_), i);
  }

  // Reads `count` numbers laid out `perline_` per line in fields of `width_` characters.
  void Numbers(int64_t count, std::vector<double>& out, const std::string& what) {
    out.clear();
    while (static_cast<int64_t>(out.size()) < count) {
      std::string_view line;
      if (!NextLine(line)) {  // message built only on failure: this is the hot loop
        Fail(line_no_ + 1, "unexpected end of file (truncated?): expected " +
                               std::to_string(count - static_cast<int64_t>(out.size())) +
                               " more numbers of " + what);
      }
      const int64_t k = std::min<int64_t>(perline_, count - static_cast<int64_t>(out.size()));
      for (int64_t i = 0; i < k; ++i) {
        out.push_back(Field(line, static_cast<size_t>(i), k, what));
      }
      const size_t used = static_cast<size_t>(k) * width_;
      if (used < line.size() && !TrimSpaces(line.substr(used)).empty()) {
        Fail("unexpected text after the " + std::to_string(k) + " numbers expected for " + what +
             ": '" + Printable(line.substr(used)) + "'");
      }
    }
  }

  // "1P,5E16.9", "3E23.16", "1P,3D21.14": numbers per line and field width.
  void ParseFormat(std::string_view fmt) {
    fmt = TrimSpaces(fmt);
    perline_ = 5;
    width_ = 16;
    if (fmt.empty()) return;
    std::string f;
    for (char c : fmt) {
      if (c != ' ' && c != '(' && c != ')') f += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    if (f.rfind("1P", 0) == 0) f.erase(0, f.size() > 2 && f[2] == ',' ? 3 : 2);
    const size_t e = f.find_first_of("ED");
    int64_t perline = 0;
    int64_t width = 0;
    bool ok = e != std::string::npos && e > 0;
    if (ok) {
      const auto r1 = std::from_chars(f.data(), f.data() + e, perline);
      const size_t dot = f.find('.', e);
      const size_t wend = dot == std::string::npos ? f.size() : dot;
      const auto r2 = std::from_chars(f.data() + e + 1, f.data() + wend, width);
      ok = r1.ec == std::errc() && r1.ptr == f.data() + e && r2.ec == std::errc() &&
           r2.ptr == f.data() + wend && perline >= 1 && perline <= 1000 && width >= 2 &&
           width <= 100;
    }
    if (!ok) {
      Fail("expected a number format like '1P,5E16.9' from column 41, found '" + Printable(fmt) +
           "'");
    }
    perline_ = perline;
    width_ = static_cast<size_t>(width);
  }

  FeMatrix ReadMatrix(std::string_view line) {
    const int64_t header_line = line_no_;
    const int64_t cols = IntField(line, 0, 8, "column count");
    const int64_t rows = IntField(line, 8, 8, "row count");
    const int64_t form = IntField(line, 16, 8, "form");
    const int64_t type = IntField(line, 24, 8, "type");
    std::string name = line.size() > 32 ? TrimName(line.substr(32, 8)) : std::string();
    ParseFormat(line.size() > 40 ? line.substr(40) : std::string_view());
    Header h;
    if (std::string err = CheckHeader(cols, rows, form, type, std::move(name), data_.size(), h);
        !err.empty()) {
      Fail(header_line, err);
    }
    MatrixBuilder b(h);
    const int cplx = h.Complex() ? 2 : 1;
    const int wpn = h.WordsPerNumber(false);
    const int64_t unit = static_cast<int64_t>(wpn) * cplx;  // sparse words per entry
    std::vector<double> nums;

    auto add = [&](int64_t col, int64_t row) {
      for (size_t k = 0; k * static_cast<size_t>(cplx) < nums.size(); ++k) {
        const double re = nums[k * static_cast<size_t>(cplx)];
        const double im = cplx == 2 ? nums[k * 2 + 1] : 0.0;
        b.Add(row + static_cast<int64_t>(k), col, re, im);
      }
    };

    for (;;) {
      line = RequireLine("a column header of matrix '" + h.name + "'");
      const int64_t icol = IntField(line, 0, 8, "column index");
      const int64_t irow = IntField(line, 8, 8, "row index");
      const int64_t nw = IntField(line, 16, 8, "word count");
      const std::string what = "matrix '" + h.name + "', column " + std::to_string(icol);
      if (icol == h.cols + 1) {  // end-of-matrix record: skip its dummy value line(s)
        if (nw < 0 || nw > 1000) Fail(what + ": bad word count " + std::to_string(nw) + " in the end-of-matrix record");
        // Only the first field of each line is checked: writers disagree on the count.
        for (int64_t i = 0; i < (nw + perline_ - 1) / perline_; ++i) {
          line = RequireLine("the dummy value of the end-of-matrix record of '" + h.name + "'");
          Field(line, 0, 1, "the end-of-matrix record of '" + h.name + "'");
        }
        break;
      }
      if (std::string err = b.StartColumn(icol); !err.empty()) Fail(err);
      if (nw < 0) Fail(what + ": negative word count " + std::to_string(nw));
      if (irow > 0) {  // dense: nw numbers (real, or real/imaginary pairs) from row irow
        if (nw % cplx != 0) Fail(what + ": odd number count " + std::to_string(nw) + " for a complex matrix");
        if (std::string err = b.BeginRun(irow, nw / cplx); !err.empty()) Fail(err);
        Numbers(nw, nums, what);
        add(icol, irow);
      } else if (irow == 0) {  // sparse: strings, nw counts words including string headers
        int64_t left = nw;
        while (left > 0) {
          line = RequireLine("a sparse string header of " + what);
          int64_t words = 0;
          int64_t row = 0;
          int64_t head = 0;
          if (h.bigmat) {
            const int64_t len = IntField(line, 0, 8, "string length");
            words = len < 1 ? 0 : len - 1;  // len < 2 is rejected below
            row = IntField(line, 8, std::string_view::npos, "string row");
            head = 2;
          } else {
            const int64_t is = IntField(line, 0, std::string_view::npos, "packed string header");
            if (is <= 0) Fail(what + ": bad sparse string header " + std::to_string(is));
            words = (is >> 16) - 1;
            row = is & 0xFFFF;
            head = 1;
          }
          if (words < 1 || words > left - head || words % unit != 0) {
            Fail(what + ": bad sparse string length " + std::to_string(words) +
                 " words (expected a positive multiple of " + std::to_string(unit) +
                 " within the " + std::to_string(left) + " words left in the column)");
          }
          if (std::string err = b.BeginRun(row, words / unit); !err.empty()) Fail(err);
          Numbers(words / wpn, nums, what);
          add(icol, row);
          left -= head + words;
        }
      } else {
        Fail(what + ": negative row index " + std::to_string(irow));
      }
    }
    return b.Finish(h.type == 1 || h.type == 3 ? 32 : 64);
  }

  const std::string& path_;
  std::string_view data_;
  size_t pos_ = 0;
  int64_t line_no_ = 0;
  int64_t perline_ = 5;
  size_t width_ = 16;
};

bool LooksBinary(std::string_view data) {
  const size_t n = std::min<size_t>(data.size(), 256);
  for (size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(data[i]);
    if (c == '\n' || c == '\r' || c == '\t') continue;
    if (c < 0x20 || c >= 0x7f) return true;
  }
  return false;
}

}  // namespace

FeModel ReadOp4(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw FeReadError(path + ": cannot open file for reading");
  const std::streamoff size = in.tellg();
  if (size < 0) throw FeReadError(path + ": cannot determine the file size");
  std::string data(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(data.data(), size)) throw FeReadError(path + ": read error");
  if (data.empty()) {
    throw FeReadError(path + ": byte offset 0: empty file, expected an OP4 matrix header");
  }
  std::string near_miss;
  if (const auto layout = DetectBinary(data, near_miss)) {
    return BinaryOp4(path, data, *layout).Read();
  }
  if (!near_miss.empty() || LooksBinary(data)) {
    throw FeReadError(path + ": byte offset 0: not a readable OP4 file: " +
                      (near_miss.empty()
                           ? std::string("expected a Fortran record marker of 24, 40 or 48 "
                                         "(binary header record) or an ASCII header line")
                           : near_miss));
  }
  return AsciiOp4(path, data).Read();
}

}  // namespace fricrom
