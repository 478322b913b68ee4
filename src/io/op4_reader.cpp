// Nastran OUTPUT4 (.op4) reader: ASCII and binary files, little and big endian, 4- or 8-byte
// Fortran record markers, 32- or 64-bit integer words; dense, non-bigmat sparse and bigmat
// sparse columns; real and complex, single and double precision. See
// docs/formats-nastran-op4.md for the layout and the limits.
//
// Entries are checked as they are read (row/column ranges, ascending order, finite values) and
// each matrix is assembled only when its end record has been read; nothing is returned unless
// the whole file reads cleanly.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fe_text.h"
#include "fricrom/fe_model.h"
#include "op4_common.h"

namespace fricrom {
namespace {

using op4::Header;
using op4::MatrixBuilder;
using op4::Skipped;

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
  BinaryOp4(const std::string& path, std::string_view data, BinaryLayout layout,
            const FeReadOptions& options)
      : path_(path), data_(data), layout_(layout), options_(options) {}

  FeModel Read() {
    FeModel model;
    model.source = path_;
    model.format = "op4";
    // A matrix not asked for is read for errors but never assembled (a stand-in with its name
    // until KeepOnly).
    while (pos_ < data_.size()) model.matrices.push_back(ReadMatrix());
    fe_text::KeepOnly(path_, options_, model);
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

  // A 16-byte name of a 64-bit-word file: Nastran puts 4 characters in each 8-byte word
  // ("MATD    T       " is MATDT); otherwise the bytes as they are.
  static std::string Name(std::string_view raw) {
    const auto blank = [](std::string_view s) {
      return s.find_first_not_of(std::string_view(" \0", 2)) == std::string_view::npos;
    };
    if (raw.size() == 16 && blank(raw.substr(4, 4)) && blank(raw.substr(12, 4))) {
      return op4::TrimName(std::string(raw.substr(0, 4)) + std::string(raw.substr(8, 4)));
    }
    return op4::TrimName(raw);
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
      Fail(pos_, "record marker says " + std::to_string(n) + " bytes for " + expected +
                     " but only " + std::to_string(left - m) +
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

  // How the column records of one matrix store their numbers.
  struct ColumnFormat {
    const Header& h;
    size_t w;          // bytes per word
    int value_bytes;   // bytes per real number
    int64_t unit;      // words per entry (complex: two numbers)
    std::string what;  // "column record of matrix 'NAME'", for errors
  };

  // The header record of the matrix starting at `header_at` (the current position).
  Header ReadHeader(size_t header_at) {
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
        Name(data_.substr(hr.begin + 4 * ib, static_cast<size_t>(layout_.name_bytes)));
    Header h;
    if (std::string err = op4::CheckHeader(cols, rows, form, type, std::move(name), h);
        !err.empty()) {
      Fail(header_at, err);
    }
    return h;
  }

  // Reads `count` entries at byte `p` into column `col` starting at row `row`.
  void Values(const ColumnFormat& f, MatrixBuilder& b, size_t p, int64_t col, int64_t row,
              int64_t count) const {
    const size_t step = static_cast<size_t>(f.unit) * f.w;
    for (int64_t k = 0; k < count; ++k, p += step) {
      const double re = Real(p, f.value_bytes);
      const double im =
          f.h.Complex() ? Real(p + static_cast<size_t>(f.value_bytes), f.value_bytes) : 0.0;
      if (!std::isfinite(re) || !std::isfinite(im)) {
        Fail(p, "matrix '" + f.h.name + "': expected a finite number at row " +
                    std::to_string(row + k) + ", column " + std::to_string(col) +
                    ", found NaN or infinity");
      }
      b.Add(row + k, col, re, im);
    }
  }

  // The strings of consecutive rows of a sparse column record: `nwords` words from byte `p`.
  void SparseStrings(const ColumnFormat& f, MatrixBuilder& b, size_t p, int64_t icol,
                     int64_t nwords) const {
    const Header& h = f.h;
    const size_t w = f.w;
    int64_t left = nwords;
    while (left > 0) {
      const size_t string_at = p;
      int64_t words = 0;
      int64_t row = 0;
      int64_t head = 0;
      if (h.bigmat) {
        if (left < 2) {
          Fail(p, "matrix '" + h.name + "', column " + std::to_string(icol) +
                      ": expected a 2-word bigmat string header, only " + std::to_string(left) +
                      " word left in the record");
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
      if (words < 1 || words > left - head || words % f.unit != 0) {
        Fail(string_at, "matrix '" + h.name + "', column " + std::to_string(icol) +
                            ": bad sparse string length " + std::to_string(words) +
                            " words (expected a positive multiple of " + std::to_string(f.unit) +
                            " within the " + std::to_string(left) + " words left in the record)");
      }
      const int64_t count = words / f.unit;
      if (std::string err = b.BeginRun(row, count); !err.empty()) Fail(string_at, err);
      p += static_cast<size_t>(head) * w;
      Values(f, b, p, icol, row, count);
      p += static_cast<size_t>(words) * w;
      left -= head + words;
    }
  }

  // One column record, dense or sparse; false for the end-of-matrix record (its dummy value is
  // not used).
  bool ReadColumn(const ColumnFormat& f, MatrixBuilder& b) {
    const Header& h = f.h;
    const size_t w = f.w;
    const size_t rec_at = pos_;
    const Record r = NextRecord("a " + f.what);
    if (r.size < 3 * w) {
      Fail(rec_at, "expected a " + f.what + " of at least " + std::to_string(3 * w) +
                       " bytes, found " + std::to_string(r.size) + " bytes");
    }
    const int64_t icol = Int(r.begin);
    const int64_t irow = Int(r.begin + w);
    const int64_t nwords = Int(r.begin + 2 * w);
    if (icol == h.cols + 1) return false;
    if (std::string err = b.StartColumn(icol); !err.empty()) Fail(r.begin, err);
    const size_t data_bytes = r.size - 3 * w;
    if (nwords < 0 || data_bytes % w != 0 || static_cast<uint64_t>(nwords) != data_bytes / w) {
      Fail(r.begin + 2 * w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                                ": word count " + std::to_string(nwords) +
                                " does not match the record length (" + std::to_string(data_bytes) +
                                " data bytes, " + std::to_string(w) + " per word)");
    }
    const size_t p = r.begin + 3 * w;
    if (irow > 0) {  // dense: consecutive rows from irow
      if (nwords % f.unit != 0) {
        Fail(r.begin + 2 * w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                                  ": word count " + std::to_string(nwords) +
                                  " is not a multiple of " + std::to_string(f.unit) +
                                  " words per entry");
      }
      const int64_t count = nwords / f.unit;
      if (std::string err = b.BeginRun(irow, count); !err.empty()) Fail(r.begin + w, err);
      Values(f, b, p, icol, irow, count);
    } else if (irow == 0) {  // sparse: strings of consecutive rows
      SparseStrings(f, b, p, icol, nwords);
    } else {
      Fail(r.begin + w, "matrix '" + h.name + "', column " + std::to_string(icol) +
                            ": negative row index " + std::to_string(irow));
    }
    return true;
  }

  FeMatrix ReadMatrix() {
    const size_t header_at = pos_;
    const Header h = ReadHeader(header_at);
    MatrixBuilder b(h, fe_text::Wanted(options_, h.name));
    const bool wide = layout_.int_bytes == 8;
    const int wpn = h.WordsPerNumber(wide);  // words per number
    const ColumnFormat f{h, static_cast<size_t>(layout_.int_bytes),
                         (h.type == 1 || h.type == 3) ? layout_.int_bytes : 8,
                         static_cast<int64_t>(wpn) * (h.Complex() ? 2 : 1),
                         "column record of matrix '" + h.name + "'"};
    while (ReadColumn(f, b)) {
    }
    if (!b.keep()) return Skipped(h.name);
    // 64-bit-word files store types 1 and 3 in 8-byte reals as well.
    return b.Finish(f.value_bytes == 4 ? 32 : 64, options_, path_,
                    "byte offset " + std::to_string(header_at) + ": ");
  }

  const std::string& path_;
  std::string_view data_;
  BinaryLayout layout_;
  const FeReadOptions& options_;
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

FeModel ReadOp4(const std::string& path, const FeReadOptions& options) {
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
    return BinaryOp4(path, data, *layout, options).Read();
  }
  if (!near_miss.empty() || LooksBinary(data)) {
    throw FeReadError(path + ": byte offset 0: not a readable OP4 file: " +
                      (near_miss.empty()
                           ? std::string("expected a Fortran record marker of 24, 40 or 48 "
                                         "(binary header record) or an ASCII header line")
                           : near_miss));
  }
  return op4::ReadAscii(path, data, options);
}

}  // namespace fricrom
