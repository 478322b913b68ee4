// Abaqus *MATRIX GENERATE / *MATRIX OUTPUT text files (.mtx):
//  - node-DOF form, lines `rownode,rowdof, colnode,coldof, value` (internal nodes have negative
//    labels), usually one triangle of a symmetric matrix;
//  - COORDINATE form, lines `row col value` (1-based equation numbers), with an optional DOF map
//    in the sidecar `<name>.dof.csv` (node,component).
// Format notes and the rules chosen here: docs/formats-abaqus-calculix-mtx.md.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <numeric>
#include <string_view>
#include <system_error>

#include "fe_text.h"
#include "fricrom/fe_model.h"

namespace fricrom {

namespace {

using fe_text::Fail;

// Dense ids for the (node, dof) pairs of a node-DOF file, in order of first appearance (an
// open-addressing hash table: one probe per lookup instead of sorting every pair read).
class DofIds {
 public:
  int64_t Id(const DofId& d) {
    if (2 * (dofs_.size() + 1) > slots_.size()) Grow();
    size_t i = Hash(d) & mask_;
    while (slots_[i] != 0) {
      if (dofs_[slots_[i] - 1] == d) return static_cast<int64_t>(slots_[i] - 1);
      i = (i + 1) & mask_;
    }
    dofs_.push_back(d);
    slots_[i] = dofs_.size();
    return static_cast<int64_t>(dofs_.size() - 1);
  }
  const std::vector<DofId>& dofs() const { return dofs_; }

 private:
  static size_t Hash(const DofId& d) {
    uint64_t h = static_cast<uint64_t>(d.node) * 0x9E3779B97F4A7C15ull +
                 static_cast<uint64_t>(static_cast<uint32_t>(d.component));
    h ^= h >> 32;
    h *= 0xD6E8FEB86659FD93ull;
    h ^= h >> 32;
    return static_cast<size_t>(h);
  }
  void Grow() {
    const size_t size = std::max<size_t>(1024, 2 * slots_.size());
    slots_.assign(size, 0);
    mask_ = size - 1;
    for (size_t k = 0; k < dofs_.size(); ++k) {
      size_t i = Hash(dofs_[k]) & mask_;
      while (slots_[i] != 0) i = (i + 1) & mask_;
      slots_[i] = k + 1;
    }
  }

  std::vector<DofId> dofs_;
  std::vector<size_t> slots_;  // 0: empty, else 1 + index into dofs_
  size_t mask_ = 0;
};

bool IsSeparator(char c) { return c == ' ' || c == '\t' || c == ','; }

// Fast path for a well-formed data line (`t` trimmed): exactly N integers and then one real,
// separated by blanks, tabs and/or commas, each as std::from_chars reads it whole (no leading
// '+', no 'D' exponent, finite). False for anything else; the checked path then reads the line
// and reports the error, so a line accepted here gives the same values the checked path would.
template <size_t N>
bool FastFields(std::string_view t, int64_t (&ints)[N], double& value) {
  const char* p = t.data();
  const char* const end = p + t.size();
  for (size_t i = 0; i < N; ++i) {
    while (p < end && IsSeparator(*p)) ++p;
    const auto [q, ec] = std::from_chars(p, end, ints[i]);
    if (ec != std::errc() || (q < end && !IsSeparator(*q))) return false;
    p = q;
  }
  while (p < end && IsSeparator(*p)) ++p;
  const auto [q, ec] = std::from_chars(p, end, value, std::chars_format::general);
  if (ec != std::errc() || !std::isfinite(value)) return false;
  for (p = q; p < end; ++p) {
    if (!IsSeparator(*p)) return false;
  }
  return true;
}

bool ValidDof(int64_t node, int64_t dof) {
  return node != 0 && dof >= 1 && dof <= fe_text::kMaxComponent;
}

DofId ReadDof(std::string_view node, std::string_view dof, const std::string& path, size_t line,
              const char* which) {
  DofId d;
  d.node = fe_text::RequireInt(node, path, line, std::string(which) + " node label");
  if (d.node == 0) {
    Fail(path, line,
         std::string("expected a non-zero ") + which +
             " node label (internal nodes are negative), got 0");
  }
  const int64_t c = fe_text::RequireInt(dof, path, line, std::string(which) + " degree of freedom");
  if (c < 1 || c > fe_text::kMaxComponent) {
    Fail(path, line,
         std::string("expected a ") + which + " degree of freedom 1.." +
             std::to_string(fe_text::kMaxComponent) + ", got " + std::to_string(c));
  }
  d.component = static_cast<int>(c);
  return d;
}

// What the entry lines give: the entries, with node-DOF ids (5 fields) or 0-based equation
// numbers (3 fields), and what the checked path needs to tell a line apart from the first.
struct Scan {
  std::vector<fe_text::TextEntry> entries;  // node-DOF form: row, col are ids from `dof_ids`
  DofIds dof_ids;
  int64_t max_index = 0;  // largest 1-based equation number (3 fields)
  size_t columns = 0;     // fields per line, set by the first entry line
  size_t first_line = 0;
  std::vector<std::string_view> tokens;
};

// Checked path: the first entry line (it sets the field count), and any line the fast path
// does not take; reports the error of a bad line.
void ReadCheckedLine(const std::string& path, std::string_view t, size_t number, Scan& s,
                     fe_text::TextEntry& e) {
  std::vector<std::string_view>& tokens = s.tokens;
  fe_text::SplitTokens(t, tokens);
  if (s.columns == 0) {
    if (tokens.size() != 5 && tokens.size() != 3) {
      Fail(path, number,
           "expected 5 fields 'rownode,rowdof, colnode,coldof, value' or 3 fields 'row col "
           "value', got " +
               std::to_string(tokens.size()) + " fields");
    }
    s.columns = tokens.size();
    s.first_line = number;
  } else if (tokens.size() != s.columns) {
    Fail(path, number,
         "expected " + std::to_string(s.columns) + " fields as on line " +
             std::to_string(s.first_line) + ", got " + std::to_string(tokens.size()) +
             (tokens.size() < s.columns ? " (truncated line?)" : ""));
  }
  if (s.columns == 5) {
    const DofId row = ReadDof(tokens[0], tokens[1], path, number, "row");
    const DofId col = ReadDof(tokens[2], tokens[3], path, number, "column");
    e.re = fe_text::RequireReal(tokens[4], false, path, number, "the matrix value");
    e.row = s.dof_ids.Id(row);
    e.col = s.dof_ids.Id(col);
    s.entries.push_back(e);
  } else {
    e.row = fe_text::RequireInt(tokens[0], path, number, "a row number") - 1;
    e.col = fe_text::RequireInt(tokens[1], path, number, "a column number") - 1;
    if (e.row < 0 || e.col < 0 || e.row >= fe_text::kMaxDimension ||
        e.col >= fe_text::kMaxDimension) {
      Fail(path, number,
           "entry index out of range: row " + std::to_string(e.row + 1) + ", column " +
               std::to_string(e.col + 1) + " (expected 1-based indices 1.." +
               std::to_string(fe_text::kMaxDimension) + ")");
    }
    e.re = fe_text::RequireReal(tokens[2], false, path, number, "the matrix value");
    s.max_index = std::max({s.max_index, e.row + 1, e.col + 1});
    s.entries.push_back(e);
  }
}

// Every entry line of the file, through the fast path when it reads the line.
void ScanEntries(const std::string& path, std::string_view text, Scan& s) {
  size_t pos = 0, number = 0;
  std::string_view line;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = fe_text::Trim(line);
    if (t.empty() || t.substr(0, 2) == "**") continue;  // blank line or Abaqus comment
    if (t.front() == '*') {
      Fail(path, number,
           "unexpected keyword line " + fe_text::Printable(t) +
               " (expected matrix entries; comments start with **)");
    }
    fe_text::TextEntry e;
    e.line = number;
    if (s.columns == 5) {
      int64_t v[4];
      if (FastFields(t, v, e.re) && ValidDof(v[0], v[1]) && ValidDof(v[2], v[3])) {
        e.row = s.dof_ids.Id(DofId{v[0], static_cast<int>(v[1])});
        e.col = s.dof_ids.Id(DofId{v[2], static_cast<int>(v[3])});
        s.entries.push_back(e);
        continue;
      }
    } else if (s.columns == 3) {
      int64_t v[2];
      if (FastFields(t, v, e.re) && v[0] >= 1 && v[0] <= fe_text::kMaxDimension && v[1] >= 1 &&
          v[1] <= fe_text::kMaxDimension) {
        e.row = v[0] - 1;
        e.col = v[1] - 1;
        s.max_index = std::max({s.max_index, v[0], v[1]});
        s.entries.push_back(e);
        continue;
      }
    }
    ReadCheckedLine(path, t, number, s, e);
  }
  if (s.columns == 0) Fail(path, number, "no matrix entries (empty file)");
}

// Node-DOF form: the DOF map is every (node, dof) that appears, sorted by signed node label then
// dof; the entries' ids become indices into it.
void NumberNodeDofs(Scan& s, FeMatrix& m) {
  const std::vector<DofId>& seen = s.dof_ids.dofs();
  std::vector<size_t> by_dof(seen.size());
  std::iota(by_dof.begin(), by_dof.end(), size_t{0});
  std::sort(by_dof.begin(), by_dof.end(),
            [&](size_t a, size_t b) { return fe_text::DofLess(seen[a], seen[b]); });
  std::vector<DofId> dofs(seen.size());
  std::vector<int64_t> rank(seen.size());
  for (size_t k = 0; k < by_dof.size(); ++k) {
    dofs[k] = seen[by_dof[k]];
    rank[by_dof[k]] = static_cast<int64_t>(k);
  }
  for (fe_text::TextEntry& e : s.entries) {
    e.row = rank[static_cast<size_t>(e.row)];
    e.col = rank[static_cast<size_t>(e.col)];
  }
  m.rows = m.cols = static_cast<int64_t>(dofs.size());
  m.row_dofs = m.col_dofs = dofs;
}

// Coordinate form: the size and DOF map come from the sidecar when there is one, else the size
// is the largest equation number used.
void SizeCoordinateMatrix(const std::string& path, int64_t max_index, FeMatrix& m) {
  const std::string sidecar = fe_text::DefaultDofSidecar(path);
  if (std::filesystem::exists(sidecar)) {
    std::vector<DofId> dofs = fe_text::ReadDofCsv(sidecar);
    if (static_cast<int64_t>(dofs.size()) < max_index) {
      Fail(sidecar, 0,
           "DOF map has " + std::to_string(dofs.size()) + " entries but the matrix " + path +
               " uses index " + std::to_string(max_index) +
               " (expected one node,component line per matrix row)");
    }
    m.row_dofs = m.col_dofs = dofs;
    m.rows = m.cols = static_cast<int64_t>(dofs.size());
  } else {
    m.rows = m.cols = max_index;
  }
}

}  // namespace

FeModel ReadAbaqusMatrix(const std::string& path, const FeReadOptions& options) {
  const std::string text = fe_text::ReadCompleteTextFile(path, "Abaqus matrix file");
  FeModel model;
  model.source = path;
  model.format = "abaqus";
  // Filled in place: moving a FeMatrix copies Eigen's per-column index (O(cols) memory).
  FeMatrix& m = model.matrices.emplace_back();
  m.name = std::filesystem::path(path).stem().string();

  Scan s;
  ScanEntries(path, text, s);
  if (s.columns == 5) {
    NumberNodeDofs(s, m);
  } else {
    SizeCoordinateMatrix(path, s.max_index, m);
  }
  // One triangle of a symmetric matrix unless some entry also appears transposed (then the file
  // holds a full, possibly unsymmetric, matrix and is taken as it is).
  m.symmetric = !fe_text::HasTransposePair(s.entries);
  std::function<std::string(int64_t, int64_t)> describe;
  if (!m.row_dofs.empty()) {
    describe = [&](int64_t r, int64_t c) {
      return "(row " + fe_text::DescribeDof(m.row_dofs[static_cast<size_t>(r)]) + ", column " +
             fe_text::DescribeDof(m.col_dofs[static_cast<size_t>(c)]) + ")";
    };
  }
  fe_text::AssembleEntries(path, s.entries, m.symmetric, m, describe, options);
  fe_text::KeepOnly(path, options, model);
  return model;
}

}  // namespace fricrom
