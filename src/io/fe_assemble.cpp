// Matrix assembly shared by the text readers (declared in fe_text.h): entry checks (range,
// duplicates, both triangles of a symmetric matrix), then compressed columns or the coordinate
// form, sized by what the file holds; the storage and memory checks also used by OUTPUT4.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <new>
#include <numeric>
#include <string>
#include <vector>

#include "fe_text.h"
#include "fricrom/fe_model.h"

namespace fricrom::fe_text {

namespace {

std::string Megabytes(uint64_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB";
}

// Sorts entry numbers by key (row, col) or, when symmetric, (min, max), keeping file order on
// ties. Skipped when the file is already in key order; otherwise a stable two-pass counting sort
// (O(n + dimension)) unless the dimension is large compared with the entry count.
std::vector<uint32_t> KeyOrder(const std::vector<TextEntry>& entries, bool symmetric,
                               const FeMatrix& m) {
  const auto primary = [&](uint32_t k) {
    const TextEntry& e = entries[k];
    return symmetric ? std::min(e.row, e.col) : e.row;
  };
  const auto secondary = [&](uint32_t k) {
    const TextEntry& e = entries[k];
    return symmetric ? std::max(e.row, e.col) : e.col;
  };
  const auto key = [&](uint32_t k) { return std::make_pair(primary(k), secondary(k)); };
  const size_t n = entries.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), uint32_t{0});
  bool in_order = true;
  for (size_t k = 1; k < n && in_order; ++k) {
    in_order = !(key(static_cast<uint32_t>(k)) < key(static_cast<uint32_t>(k - 1)));
  }
  if (in_order) return order;
  const auto secondary_range = static_cast<uint64_t>(symmetric ? m.rows : m.cols);
  const auto primary_range = static_cast<uint64_t>(m.rows);
  if (std::max(primary_range, secondary_range) > 2 * n + 4096) {
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    return order;
  }
  std::vector<uint32_t> count, by_secondary(n);
  const auto counting_sort = [&](const std::vector<uint32_t>& in, std::vector<uint32_t>& out,
                                 size_t range, const auto& bucket) {
    count.assign(range + 1, 0);
    for (const uint32_t k : in) ++count[static_cast<size_t>(bucket(k)) + 1];
    for (size_t i = 0; i < range; ++i) count[i + 1] += count[i];
    for (const uint32_t k : in) out[count[static_cast<size_t>(bucket(k))]++] = k;
  };
  counting_sort(order, by_secondary, static_cast<size_t>(secondary_range), secondary);
  counting_sort(by_secondary, order, static_cast<size_t>(primary_range), primary);
  return order;
}

// Fails on the first key given twice in `order` (the later line is the one reported).
void CheckDuplicates(const std::string& file, const std::vector<TextEntry>& entries,
                     const std::vector<uint32_t>& order, bool symmetric,
                     const std::function<std::string(int64_t, int64_t)>& where) {
  const auto key = [&](uint32_t k) {
    const TextEntry& e = entries[k];
    return symmetric ? std::make_pair(std::min(e.row, e.col), std::max(e.row, e.col))
                     : std::make_pair(e.row, e.col);
  };
  for (size_t k = 1; k < order.size(); ++k) {
    if (key(order[k]) != key(order[k - 1])) continue;
    const TextEntry& first = entries[order[k - 1]];
    const TextEntry& second = entries[order[k]];
    const TextEntry& later = first.line > second.line ? first : second;
    const TextEntry& earlier = first.line > second.line ? second : first;
    if (symmetric && first.row != second.row) {
      Fail(file, later.line,
           "symmetric matrix has entry " + where(later.row, later.col) +
               " in both triangles (its transpose is on line " + std::to_string(earlier.line) +
               "); give each off-diagonal term once, in either triangle");
    }
    Fail(file, later.line,
         "entry " + where(later.row, later.col) + " given twice (also on line " +
             std::to_string(earlier.line) + ")");
  }
}

// Compressed column storage built directly (no duplicates are left to sum): O(cols + nnz) time
// and memory. Scattering the entries in key order leaves the rows of every column ascending: for
// (row, col) keys directly; for symmetric (min, max) keys, column j first receives the rows
// i < j (from keys (i, j), ascending i), then the rows i >= j (from keys (j, i), ascending i).
void BuildColumns(const std::vector<TextEntry>& entries, const std::vector<uint32_t>& order,
                  bool symmetric, size_t stored, FeMatrix& m) {
  Eigen::SparseMatrix<double>& a = m.real;
  a.resize(static_cast<Eigen::Index>(m.rows), static_cast<Eigen::Index>(m.cols));  // in place
  a.resizeNonZeros(static_cast<Eigen::Index>(stored));
  int* outer = a.outerIndexPtr();
  int* inner = a.innerIndexPtr();
  double* value = a.valuePtr();
  for (const TextEntry& e : entries) {
    ++outer[e.col + 1];
    if (symmetric && e.row != e.col) ++outer[e.row + 1];
  }
  for (int64_t j = 0; j < m.cols; ++j) outer[j + 1] += outer[j];
  // outer[c] serves as column c's insertion point, restored by one shift afterwards: no second
  // per-column array.
  std::vector<double> imag(m.is_complex ? stored : 0);
  const auto put = [&](int64_t r, int64_t c, const TextEntry& e) {
    const int p = outer[c]++;
    inner[p] = static_cast<int>(r);
    value[p] = e.re;
    if (m.is_complex) imag[static_cast<size_t>(p)] = e.im;
  };
  for (const uint32_t k : order) {
    const TextEntry& e = entries[k];
    put(e.row, e.col, e);
    if (symmetric && e.row != e.col) put(e.col, e.row, e);
  }
  for (int64_t j = m.cols; j > 0; --j) outer[j] = outer[j - 1];
  outer[0] = 0;
  if (m.is_complex) {
    m.imag = a;
    std::copy(imag.begin(), imag.end(), m.imag.valuePtr());
  } else {
    m.imag = Eigen::SparseMatrix<double>();
  }
}

// Coordinate form sorted by (column, row): memory by entries only, whatever the dimensions.
void BuildCoordinates(const std::vector<TextEntry>& entries, bool symmetric, size_t stored,
                      FeMatrix& m) {
  struct Slot {
    int64_t row, col;
    uint32_t k;
  };
  std::vector<Slot> slots;
  slots.reserve(stored);
  for (size_t k = 0; k < entries.size(); ++k) {
    const TextEntry& e = entries[k];
    slots.push_back({e.row, e.col, static_cast<uint32_t>(k)});
    if (symmetric && e.row != e.col) slots.push_back({e.col, e.row, static_cast<uint32_t>(k)});
  }
  std::sort(slots.begin(), slots.end(), [](const Slot& a, const Slot& b) {
    return a.col != b.col ? a.col < b.col : a.row < b.row;
  });
  FeCoordinates& c = m.coo;
  c = FeCoordinates();
  c.row.reserve(stored);
  c.col.reserve(stored);
  c.re.reserve(stored);
  if (m.is_complex) c.im.reserve(stored);
  for (const Slot& s : slots) {
    c.row.push_back(s.row);
    c.col.push_back(s.col);
    c.re.push_back(entries[s.k].re);
    if (m.is_complex) c.im.push_back(entries[s.k].im);
  }
  m.coordinate = true;
  m.real = Eigen::SparseMatrix<double>();
  m.imag = Eigen::SparseMatrix<double>();
}

}  // namespace

uint64_t MemoryLimit(const FeReadOptions& options) {
  if (options.memory_limit_bytes > 0) return options.memory_limit_bytes;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return uint64_t{1} << 34;  // unknown: 16 GB
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page);
}

void CheckStorage(const std::string& file, const std::string& where, const FeMatrix& m,
                  uint64_t stored, const FeReadOptions& options) {
  const std::string shape = std::to_string(m.rows) + " x " + std::to_string(m.cols);
  const uint64_t parts = m.is_complex ? 2 : 1;
  uint64_t bytes = 0;
  if (options.coordinate) {
    bytes = stored * (8 * (2 + parts));  // row, col, values
  } else {
    constexpr int64_t kEigenMax = std::numeric_limits<int>::max() - 1;
    if (m.rows > kEigenMax || m.cols > kEigenMax) {
      throw FeReadError(file + ": " + where + "matrix '" + m.name + "' is " + shape +
                        ": compressed-column storage indexes rows and columns up to " +
                        std::to_string(kEigenMax) +
                        " (fricrom info/convert read it in coordinate form)");
    }
    bytes = parts * (4 * (static_cast<uint64_t>(m.cols) + 1) + 12 * stored);
  }
  const uint64_t limit = MemoryLimit(options);
  if (bytes > limit) {
    throw FeReadError(file + ": " + where + "matrix '" + m.name + "' (" + shape + ", " +
                      std::to_string(stored) + " stored entries) needs " + Megabytes(bytes) +
                      (options.coordinate ? "" : " in compressed columns (4 bytes per column)") +
                      ", more than the " + Megabytes(limit) + " allowed" +
                      (options.memory_limit_bytes > 0 ? "" : " (the physical memory)"));
  }
}

bool Wanted(const FeReadOptions& options, const std::string& name) {
  return options.only_matrix.empty() || Upper(options.only_matrix) == Upper(name);
}

void KeepOnly(const std::string& file, const FeReadOptions& options, FeModel& model) {
  if (options.only_matrix.empty()) return;
  std::string names;
  for (const FeMatrix& m : model.matrices) names += (names.empty() ? "" : ", ") + m.name;
  std::erase_if(model.matrices, [&](const FeMatrix& m) { return !Wanted(options, m.name); });
  if (model.matrices.empty()) {
    Fail(file, 0,
         "no matrix '" + options.only_matrix +
             "' (the file holds: " + (names.empty() ? std::string("no matrices") : names) + ")");
  }
  if (model.matrices.size() > 1) {  // e.g. an OP4 written with one datablock name twice
    Fail(file, 0,
         std::to_string(model.matrices.size()) + " matrices are named '" + options.only_matrix +
             "': selecting by that name is ambiguous (the file holds: " + names + ")");
  }
}

// Errors: an index out of range, an entry given twice, and, when `symmetric`, an off-diagonal
// entry given in both triangles. Symmetric storage is expanded to both triangles.
void AssembleEntries(const std::string& file, const std::vector<TextEntry>& entries, bool symmetric,
                     FeMatrix& m, const std::function<std::string(int64_t, int64_t)>& describe,
                     const FeReadOptions& options) {
  const auto where = [&](int64_t r, int64_t c) {
    if (describe) return describe(r, c);
    return "(row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1) + ")";
  };
  if (m.rows < 0 || m.cols < 0 || m.rows > kMaxDimension || m.cols > kMaxDimension) {
    Fail(file, 0,
         "matrix size " + std::to_string(m.rows) + " x " + std::to_string(m.cols) +
             " out of the supported range (0.." + std::to_string(kMaxDimension) + ")");
  }
  if (symmetric && m.rows != m.cols) {
    Fail(file, 0,
         "a symmetric matrix must be square, got " + std::to_string(m.rows) + " x " +
             std::to_string(m.cols));
  }
  if (entries.size() > static_cast<size_t>(std::numeric_limits<int>::max() / 2)) {
    Fail(file, 0, "too many matrix entries (" + std::to_string(entries.size()) + ")");
  }
  for (const TextEntry& e : entries) {
    if (e.row < 0 || e.row >= m.rows || e.col < 0 || e.col >= m.cols) {
      Fail(file, e.line,
           "entry index out of range: row " + std::to_string(e.row + 1) + ", column " +
               std::to_string(e.col + 1) + " in a " + std::to_string(m.rows) + " x " +
               std::to_string(m.cols) + " matrix (expected 1.." + std::to_string(m.rows) + ", 1.." +
               std::to_string(m.cols) + ")");
    }
  }
  size_t stored = 0;
  for (const TextEntry& e : entries) stored += symmetric && e.row != e.col ? 2 : 1;
  const bool wanted = Wanted(options, m.name);
  if (wanted) CheckStorage(file, "", m, stored, options);
  try {
    const std::vector<uint32_t> order = KeyOrder(entries, symmetric, m);
    CheckDuplicates(file, entries, order, symmetric, where);
    if (!wanted) return;  // checked, never assembled: KeepOnly drops it
    if (options.coordinate) {
      BuildCoordinates(entries, symmetric, stored, m);
    } else {
      BuildColumns(entries, order, symmetric, stored, m);
    }
  } catch (const std::bad_alloc&) {
    Fail(file, 0,
         "not enough memory for a " + std::to_string(m.rows) + " x " + std::to_string(m.cols) +
             " matrix with " + std::to_string(entries.size()) + " entries");
  }
}

}  // namespace fricrom::fe_text
