// Pieces of the Nastran OUTPUT4 reader shared by its binary (op4_reader.cpp) and ASCII
// (op4_ascii.cpp) halves: the matrix header check and the matrix builder. Private to src/io.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom::op4 {

// A form-6 matrix must be symmetric to this share of its largest entry (the reduction's rule).
constexpr double kSymmetryTolerance = 1e-8;
// Non-bigmat sparse strings pack the row into the low 16 bits.
constexpr int64_t kBigmatRows = 65536;

std::string Printable(std::string_view s, size_t max_len = 40);
std::string_view TrimSpaces(std::string_view s);
std::string TrimName(std::string_view s);

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
  int WordsPerNumber(bool wide_words) const {
    return (type == 2 || type == 4) && !wide_words ? 2 : 1;
  }
};

// Checks the header fields and fills `h`; returns an error text or "". Dimensions are not
// limited here beyond 2^53: memory is checked when a matrix is assembled (MatrixBuilder::Finish),
// by the entries it holds.
std::string CheckHeader(int64_t cols, int64_t rows, int64_t form, int64_t type, std::string name,
                        Header& h);

// Collects the entries of one matrix, checking that runs of rows stay inside the matrix, that
// columns ascend and that no row of a column is given twice. A matrix that is not `keep` (not
// the one asked for) is checked the same way but its entries are not stored.
class MatrixBuilder {
 public:
  MatrixBuilder(Header h, bool keep) : h_(std::move(h)), keep_(keep) {}

  const Header& header() const { return h_; }
  bool keep() const { return keep_; }

  // Starts (or continues) 1-based column `col`: in range, not before the current column.
  std::string StartColumn(int64_t col);
  // A run of `count` entries of the current column starting at 1-based `row`.
  std::string BeginRun(int64_t row, int64_t count);
  // Entries arrive sorted by column, then row (StartColumn/BeginRun enforce it).
  void Add(int64_t row, int64_t col, double re, double im) {
    if (!keep_) return;
    if (re != 0.0) re_.push_back({row - 1, col - 1, re});
    if (im != 0.0) im_.push_back({row - 1, col - 1, im});
  }
  // The assembled matrix in the storage `options` asks for; throws FeReadError("file: where...")
  // when it does not fit (CheckStorage). Only for a kept matrix.
  FeMatrix Finish(int precision_bits, const FeReadOptions& options, const std::string& file,
                  const std::string& where) const;

 private:
  struct Entry {
    int64_t row;
    int64_t col;
    double value;
  };
  void Build(const std::vector<Entry>& e, Eigen::SparseMatrix<double>& out) const;
  // "" when the sorted entries are symmetric within kSymmetryTolerance, else which pair differs
  // (`part`: "imaginary ").
  std::string Asymmetry(const std::vector<Entry>& e, const std::string& part) const;
  void BuildCoordinates(FeCoordinates& c) const;

  Header h_;
  bool keep_ = true;
  int64_t col_ = 0;
  int64_t next_row_ = 1;
  std::vector<Entry> re_;
  std::vector<Entry> im_;
};

// Stand-in for a matrix read for errors only (not the one asked for): just its name.
inline FeMatrix Skipped(const std::string& name) {
  FeMatrix m;
  m.name = name;
  return m;
}

// The ASCII reader (op4_ascii.cpp).
FeModel ReadAscii(const std::string& path, std::string_view data, const FeReadOptions& options);

}  // namespace fricrom::op4
