// Nastran OUTPUT4 ASCII files: a header line per matrix (columns, rows, form, type, name, Fortran
// number format), then per column a header line (column, row, word count) and the numbers in
// fixed-width fields; sparse columns hold strings of consecutive rows. See
// docs/formats-nastran-op4.md.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "fe_text.h"
#include "fricrom/fe_model.h"
#include "op4_common.h"

namespace fricrom::op4 {
namespace {

class AsciiOp4 {
 public:
  AsciiOp4(const std::string& path, std::string_view data, const FeReadOptions& options)
      : path_(path), data_(data), options_(options) {}

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
      model.matrices.push_back(ReadMatrix(line));  // a named stand-in if not asked for
    }
    if (model.matrices.empty()) Fail(line_no_ + 1, "expected an OP4 matrix header, found no data");
    fe_text::KeepOnly(path_, options_, model);
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
    const std::string_view raw =
        start < line.size() ? line.substr(start, width) : std::string_view();
    const std::string_view s = TrimSpaces(raw);
    int64_t v = 0;
    const char* first = s.data();
    const char* last = s.data() + s.size();
    if (!s.empty() && *first == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (s.empty() || ec != std::errc() || ptr != last) {
      const std::string cols =
          width == std::string_view::npos
              ? "from column " + std::to_string(start + 1)
              : "in columns " + std::to_string(start + 1) + "-" + std::to_string(start + width);
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
      if (c != ' ' && c != '(' && c != ')')
        f += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
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
    // Nastran writes the column and row counts in 16 characters, and says so with a trailing
    // "|I16" on the format, when a count needs more than 8 (pyyeti's nas_large_dim_*_ascii.op4).
    std::string_view trimmed = TrimSpaces(line);
    const bool wide = trimmed.size() >= 4 && (trimmed.substr(trimmed.size() - 4) == "|I16" ||
                                              trimmed.substr(trimmed.size() - 4) == "|i16");
    const size_t w = wide ? 16 : 8;
    const int64_t cols = IntField(line, 0, w, "column count");
    const int64_t rows = IntField(line, w, w, "row count");
    const int64_t form = IntField(line, 2 * w, 8, "form");
    const int64_t type = IntField(line, 2 * w + 8, 8, "type");
    const size_t at = 2 * w + 16;  // name, then the number format
    std::string name = line.size() > at ? TrimName(line.substr(at, 8)) : std::string();
    std::string_view format = line.size() > at + 8 ? line.substr(at + 8) : std::string_view();
    if (wide) format = TrimSpaces(format).substr(0, TrimSpaces(format).size() - 4);
    ParseFormat(format);
    Header h;
    if (std::string err = op4::CheckHeader(cols, rows, form, type, std::move(name), h);
        !err.empty()) {
      Fail(header_line, err);
    }
    MatrixBuilder b(h, fe_text::Wanted(options_, h.name));
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
        if (nw < 0 || nw > 1000)
          Fail(what + ": bad word count " + std::to_string(nw) + " in the end-of-matrix record");
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
        if (nw % cplx != 0)
          Fail(what + ": odd number count " + std::to_string(nw) + " for a complex matrix");
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
    if (!b.keep()) return Skipped(h.name);
    return b.Finish(h.type == 1 || h.type == 3 ? 32 : 64, options_, path_,
                    "line " + std::to_string(header_line) + ": ");
  }

  const std::string& path_;
  std::string_view data_;
  const FeReadOptions& options_;
  size_t pos_ = 0;
  int64_t line_no_ = 0;
  int64_t perline_ = 5;
  size_t width_ = 16;
};

}  // namespace

FeModel ReadAscii(const std::string& path, std::string_view data, const FeReadOptions& options) {
  return AsciiOp4(path, data, options).Read();
}

}  // namespace fricrom::op4
