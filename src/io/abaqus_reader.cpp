// Abaqus *MATRIX GENERATE / *MATRIX OUTPUT text files (.mtx):
//  - node-DOF form, lines `rownode,rowdof, colnode,coldof, value` (internal nodes have negative
//    labels), usually one triangle of a symmetric matrix;
//  - COORDINATE form, lines `row col value` (1-based equation numbers), with an optional DOF map
//    in the sidecar `<name>.dof.csv` (node,component).
// Format notes and the rules chosen here: docs/formats-abaqus-calculix-mtx.md.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <string_view>

#include "fricrom/fe_model.h"

namespace fricrom {

// Shared text helpers, defined in fe_model.cpp.
namespace fe_text {
constexpr int64_t kMaxDimension = 100'000'000;
constexpr int kMaxComponent = 30;
struct TextEntry {
  int64_t row = 0;
  int64_t col = 0;
  double re = 0;
  double im = 0;
  size_t line = 0;
};
std::string Printable(std::string_view s);
[[noreturn]] void Fail(const std::string& file, size_t line, const std::string& what);
std::string ReadWholeFile(const std::string& path, const std::string& what);
bool NextLine(std::string_view text, size_t& pos, std::string_view& line);
std::string_view Trim(std::string_view s);
double RequireReal(std::string_view field, bool nastran, const std::string& file, size_t line,
                   const std::string& what);
int64_t RequireInt(std::string_view field, const std::string& file, size_t line,
                   const std::string& what);
void SplitTokens(std::string_view line, std::vector<std::string_view>& tokens);
bool DofLess(const DofId& a, const DofId& b);
std::string DescribeDof(const DofId& d);
bool HasTransposePair(const std::vector<TextEntry>& entries);
void AssembleEntries(const std::string& file, const std::vector<TextEntry>& entries, bool symmetric,
                     FeMatrix& m, const std::function<std::string(int64_t, int64_t)>& describe);
std::vector<DofId> ReadDofCsv(const std::string& path);
std::string DefaultDofSidecar(const std::string& path);
}  // namespace fe_text

namespace {

using fe_text::Fail;

struct NodeDofLine {
  DofId row, col;
  double value = 0;
  size_t line = 0;
};

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

}  // namespace

FeModel ReadAbaqusMatrix(const std::string& path) {
  const std::string text = fe_text::ReadWholeFile(path, "Abaqus matrix file");
  FeModel model;
  model.source = path;
  model.format = "abaqus";
  FeMatrix m;
  m.name = std::filesystem::path(path).stem().string();

  std::vector<std::string_view> tokens;
  size_t pos = 0, number = 0, columns = 0, first_line = 0;
  std::string_view line;
  std::vector<NodeDofLine> node_lines;
  std::vector<fe_text::TextEntry> entries;
  int64_t max_index = 0;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = fe_text::Trim(line);
    if (t.empty() || t.substr(0, 2) == "**") continue;  // blank line or Abaqus comment
    if (t.front() == '*') {
      Fail(path, number,
           "unexpected keyword line " + fe_text::Printable(t) +
               " (expected matrix entries; comments start with **)");
    }
    fe_text::SplitTokens(t, tokens);
    if (columns == 0) {
      if (tokens.size() != 5 && tokens.size() != 3) {
        Fail(path, number,
             "expected 5 fields 'rownode,rowdof, colnode,coldof, value' or 3 fields 'row col "
             "value', got " +
                 std::to_string(tokens.size()) + " fields");
      }
      columns = tokens.size();
      first_line = number;
    } else if (tokens.size() != columns) {
      Fail(path, number,
           "expected " + std::to_string(columns) + " fields as on line " +
               std::to_string(first_line) + ", got " + std::to_string(tokens.size()) +
               (tokens.size() < columns ? " (truncated line?)" : ""));
    }
    if (columns == 5) {
      NodeDofLine e;
      e.row = ReadDof(tokens[0], tokens[1], path, number, "row");
      e.col = ReadDof(tokens[2], tokens[3], path, number, "column");
      e.value = fe_text::RequireReal(tokens[4], false, path, number, "the matrix value");
      e.line = number;
      node_lines.push_back(e);
    } else {
      fe_text::TextEntry e;
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
      e.line = number;
      max_index = std::max({max_index, e.row + 1, e.col + 1});
      entries.push_back(e);
    }
  }
  if (columns == 0) Fail(path, number, "no matrix entries (empty file)");

  if (columns == 5) {
    // DOF map: every (node, dof) that appears, sorted by signed node label then dof.
    std::vector<DofId> dofs;
    dofs.reserve(2 * node_lines.size());
    for (const NodeDofLine& e : node_lines) {
      dofs.push_back(e.row);
      dofs.push_back(e.col);
    }
    std::sort(dofs.begin(), dofs.end(), fe_text::DofLess);
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
    const auto index = [&](const DofId& d) {
      return static_cast<int64_t>(std::lower_bound(dofs.begin(), dofs.end(), d, fe_text::DofLess) -
                                  dofs.begin());
    };
    entries.reserve(node_lines.size());
    for (const NodeDofLine& e : node_lines) {
      fe_text::TextEntry t;
      t.row = index(e.row);
      t.col = index(e.col);
      t.re = e.value;
      t.line = e.line;
      entries.push_back(t);
    }
    m.rows = m.cols = static_cast<int64_t>(dofs.size());
    m.row_dofs = m.col_dofs = dofs;
  } else {
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
  // One triangle of a symmetric matrix unless some entry also appears transposed (then the file
  // holds a full, possibly unsymmetric, matrix and is taken as it is).
  m.symmetric = !fe_text::HasTransposePair(entries);
  std::function<std::string(int64_t, int64_t)> describe;
  if (!m.row_dofs.empty()) {
    describe = [&](int64_t r, int64_t c) {
      return "(row " + fe_text::DescribeDof(m.row_dofs[static_cast<size_t>(r)]) + ", column " +
             fe_text::DescribeDof(m.col_dofs[static_cast<size_t>(c)]) + ")";
    };
  }
  fe_text::AssembleEntries(path, entries, m.symmetric, m, describe);
  model.matrices.push_back(std::move(m));
  return model;
}

}  // namespace fricrom
