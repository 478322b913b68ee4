// Text helpers shared by the text readers of src/io (DMIG punch, Abaqus, CalculiX, Matrix
// Market, CalculiX decks); defined in fe_model.cpp. Private to src/io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom::fe_text {

// Largest row/column count or index accepted from a file: exact in a double (HDF5 and JSON
// attributes) and safe from overflow. Compressed-column storage further needs Eigen's int index
// and the memory of 4 bytes per column (CheckStorage); the coordinate form needs neither.
constexpr int64_t kMaxDimension = int64_t{1} << 53;
// Largest DOF component accepted in a DOF map (6 for grids, more for user-defined DOFs).
constexpr int kMaxComponent = 30;

// One matrix entry as read from a text file; row/col are 0-based.
struct TextEntry {
  int64_t row = 0;
  int64_t col = 0;
  double re = 0;
  double im = 0;
  size_t line = 0;
};

enum class RealStatus { kOk, kEmpty, kBad, kNonFinite };

// Short quoted excerpt of s, non-printable bytes escaped (for error messages).
std::string Printable(std::string_view s);
// Throws FeReadError "file:line: what" (line 0: no line).
[[noreturn]] void Fail(const std::string& file, size_t line, const std::string& what);
std::string ReadWholeFile(const std::string& path, const std::string& what);
// ReadWholeFile for line-oriented exports (every exporter ends the last line with a line break):
// an empty file, or one whose last line has no line break, is a truncated file and an error.
// (A cut exactly at a line end cannot be seen this way; the readers check declared counts.)
std::string ReadCompleteTextFile(const std::string& path, const std::string& what);
// Next line of text from pos (without the line break); false at the end.
bool NextLine(std::string_view text, size_t& pos, std::string_view& line);
std::string_view Trim(std::string_view s);
std::string Upper(std::string_view s);
bool ParseInt(std::string_view s, int64_t& out);
// Whole (trimmed) field as a double; `nastran` accepts implicit exponents ("1.5-3").
RealStatus ParseReal(std::string_view s, double& out, bool nastran);
double RequireReal(std::string_view field, bool nastran, const std::string& file, size_t line,
                   const std::string& what);
int64_t RequireInt(std::string_view field, const std::string& file, size_t line,
                   const std::string& what);
// Whitespace- and comma-separated tokens of a line.
void SplitTokens(std::string_view line, std::vector<std::string_view>& tokens);
bool DofLess(const DofId& a, const DofId& b);
std::string DescribeDof(const DofId& d);
bool HasTransposePair(const std::vector<TextEntry>& entries);
void CheckUniqueDofs(const std::string& file, const std::vector<DofId>& dofs,
                     const std::vector<size_t>& lines);
// Fills m (m.rows, m.cols, m.is_complex, m.name set) from `entries`, in the storage `options`
// asks for; a matrix that options.only_matrix does not name is checked but not assembled.
void AssembleEntries(const std::string& file, const std::vector<TextEntry>& entries, bool symmetric,
                     FeMatrix& m, const std::function<std::string(int64_t, int64_t)>& describe,
                     const FeReadOptions& options);
// Largest storage of one matrix (options.memory_limit_bytes, else the physical memory).
uint64_t MemoryLimit(const FeReadOptions& options);
// Fails ("file: what") when matrix m with `stored` entries (after symmetric expansion) cannot be
// held in the storage `options` asks for: Eigen's index range, or more memory than the limit.
void CheckStorage(const std::string& file, const std::string& where, const FeMatrix& m,
                  uint64_t stored, const FeReadOptions& options);
// True when options.only_matrix keeps a matrix of this name.
bool Wanted(const FeReadOptions& options, const std::string& name);
// Drops the matrices options.only_matrix does not name; fails when none is left.
void KeepOnly(const std::string& file, const FeReadOptions& options, FeModel& model);
// DOF-map sidecar: header `node,component`, then one `node,component` line per row.
std::vector<DofId> ReadDofCsv(const std::string& path);
// Default DOF-map sidecar of a matrix file: same name, extension replaced by ".dof.csv".
std::string DefaultDofSidecar(const std::string& path);

}  // namespace fricrom::fe_text
