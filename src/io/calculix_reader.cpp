// CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE` output: prefix.sti (stiffness) and prefix.mas
// (mass), coordinate triplets `row col value` (1-based, upper triangle of a symmetric matrix), and
// prefix.dof, one `node.direction` line per row. Format notes: docs/formats-abaqus-calculix-mtx.md.
#include <filesystem>
#include <functional>
#include <future>
#include <string_view>

#include "fe_text.h"
#include "fricrom/fe_model.h"

namespace fricrom {

namespace {

using fe_text::Fail;

std::vector<DofId> ReadDofFile(const std::string& path) {
  const std::string text = fe_text::ReadCompleteTextFile(path, "CalculiX .dof file");
  std::vector<DofId> dofs;
  std::vector<size_t> lines;
  size_t pos = 0, number = 0;
  std::string_view line;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = fe_text::Trim(line);
    if (t.empty()) continue;
    const size_t dot = t.find('.');
    int64_t node = 0, dir = -1;
    if (dot == std::string_view::npos || !fe_text::ParseInt(t.substr(0, dot), node) ||
        !fe_text::ParseInt(t.substr(dot + 1), dir) || t.substr(dot + 1).front() == '-' ||
        t.substr(dot + 1).front() == '+') {
      Fail(path, number, "expected 'node.direction' (e.g. 12.3), got " + fe_text::Printable(t));
    }
    if (node <= 0) Fail(path, number, "expected a node number > 0, got " + std::to_string(node));
    if (dir > 6) {
      Fail(path, number, "expected a direction 0..6, got " + std::to_string(dir));
    }
    dofs.push_back(DofId{node, static_cast<int>(dir)});
    lines.push_back(number);
  }
  if (dofs.empty()) Fail(path, 0, "empty .dof file: expected one 'node.direction' line per row");
  fe_text::CheckUniqueDofs(path, dofs, lines);
  return dofs;
}

FeMatrix ReadTriplets(const std::string& path, const std::string& name,
                      const std::vector<DofId>& dofs, const FeReadOptions& options) {
  const std::string text = fe_text::ReadCompleteTextFile(path, "CalculiX matrix file");
  FeMatrix m;
  m.name = name;
  m.rows = m.cols = static_cast<int64_t>(dofs.size());
  m.symmetric = true;
  m.row_dofs = m.col_dofs = dofs;
  std::vector<fe_text::TextEntry> entries;
  std::vector<std::string_view> tokens;
  size_t pos = 0, number = 0;
  std::string_view line;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    fe_text::SplitTokens(line, tokens);
    if (tokens.empty()) continue;
    if (tokens.size() != 3) {
      Fail(path, number,
           "expected 'row column value', got " + std::to_string(tokens.size()) + " fields" +
               (tokens.size() < 3 ? " (truncated line?)" : ""));
    }
    fe_text::TextEntry e;
    e.row = fe_text::RequireInt(tokens[0], path, number, "a row number") - 1;
    e.col = fe_text::RequireInt(tokens[1], path, number, "a column number") - 1;
    e.re = fe_text::RequireReal(tokens[2], false, path, number, "the matrix value");
    e.line = number;
    entries.push_back(e);
  }
  if (entries.empty()) Fail(path, 0, "no matrix entries (empty file)");
  const auto describe = [&](int64_t r, int64_t c) {
    return "(row " + std::to_string(r + 1) + " = " + fe_text::DescribeDof(dofs[r]) + ", column " +
           std::to_string(c + 1) + " = " + fe_text::DescribeDof(dofs[c]) + ")";
  };
  for (const auto& e : entries) {
    if (e.row < 0 || e.col < 0 || e.row >= m.rows || e.col >= m.cols) {
      Fail(path, e.line,
           "entry index out of range: row " + std::to_string(e.row + 1) + ", column " +
               std::to_string(e.col + 1) + " (the .dof file lists " + std::to_string(m.rows) +
               " DOFs)");
    }
  }
  // CalculiX writes the diagonal term of every DOF (its last line is the last diagonal): a missing
  // one means the file was cut, even exactly at a line end.
  std::vector<bool> diagonal(dofs.size(), false);
  for (const auto& e : entries) {
    if (e.row == e.col) diagonal[static_cast<size_t>(e.row)] = true;
  }
  for (size_t k = 0; k < diagonal.size(); ++k) {
    if (!diagonal[k]) {
      Fail(path, number,
           "no diagonal term for DOF " + std::to_string(k + 1) + " (" +
               fe_text::DescribeDof(dofs[k]) + ") of the " + std::to_string(dofs.size()) +
               " in the .dof file; CalculiX writes every diagonal term: the file is truncated");
    }
  }
  // CalculiX writes the upper triangle column by column, each column closed by its diagonal, so
  // its last line is the last DOF's diagonal: with this, a cut at any line end is caught, whatever
  // the order of the lines before it.
  const int64_t n = static_cast<int64_t>(dofs.size());
  if (entries.back().row != n - 1 || entries.back().col != n - 1) {
    Fail(path, entries.back().line,
         "the last entry is (" + std::to_string(entries.back().row + 1) + ", " +
             std::to_string(entries.back().col + 1) + "), expected the diagonal (" +
             std::to_string(n) + ", " + std::to_string(n) +
             ") of the last DOF: CalculiX ends every matrix with it (the file is truncated)");
  }
  fe_text::AssembleEntries(path, entries, true, m, describe, options);
  return m;
}

}  // namespace

FeModel ReadCalculix(const std::string& prefix, const FeReadOptions& options) {
  const std::string dof_path = prefix + ".dof", sti = prefix + ".sti", mas = prefix + ".mas";
  const bool has_sti = std::filesystem::exists(sti), has_mas = std::filesystem::exists(mas);
  if (!has_sti && !has_mas) {
    Fail(prefix, 0,
         "no CalculiX matrix files: expected " + sti + " and/or " + mas +
             " (written by *FREQUENCY, SOLVER=MATRIXSTORAGE)");
  }
  if (!std::filesystem::exists(dof_path)) {
    Fail(dof_path, 0,
         "missing .dof file: expected one 'node.direction' line per matrix row, written by "
         "CalculiX next to " +
             (has_sti ? sti : mas));
  }
  const std::vector<DofId> dofs = ReadDofFile(dof_path);
  FeModel model;
  model.format = "calculix";
  model.source = dof_path;
  // Text parsing dominates for large models: the mass file is read on a second thread. Errors are
  // reported in a fixed order (stiffness first); the future's destructor joins the thread.
  std::future<FeMatrix> mass_future;
  if (has_mas) {
    mass_future =
        std::async(std::launch::async, [&] { return ReadTriplets(mas, "MASS", dofs, options); });
  }
  if (has_sti) {
    model.matrices.push_back(ReadTriplets(sti, "STIFFNESS", dofs, options));
    model.source += ", " + sti;
  }
  if (has_mas) {
    model.matrices.push_back(mass_future.get());
    model.source += ", " + mas;
  }
  // The deck that produced the matrices carries the node coordinates and node sets.
  const std::string deck = prefix + ".inp";
  if (std::filesystem::exists(deck)) {
    ReadInpNodesAndSets(deck, model);
    model.source += ", " + deck;
  }
  fe_text::KeepOnly(prefix, options, model);
  return model;
}

}  // namespace fricrom
