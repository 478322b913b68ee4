// Assembly of the DMIG matrices read by the Nastran punch reader (nastran_punch.cpp): value
// checks, DOF sets and the EXTRN order. Format notes: docs/formats-nastran-punch.md.
#include "nastran_punch_dmig.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fe_text.h"

namespace fricrom::punch {

namespace {

using fe_text::Fail;

using Values = std::vector<std::pair<double, double>>;  // (re, im) per entry of a Dmig

// Position of x in the sorted EXTRN set, or end() when x is not in it.
ExtrnSorted::const_iterator FindExtrn(const ExtrnSorted& extrn_sorted, const DofId& x) {
  return std::lower_bound(
      extrn_sorted.begin(), extrn_sorted.end(), x,
      [](const auto& a, const DofId& b) { return fe_text::DofLess(a.first, b); });
}

// The value of each entry as the file stores it: type checks against TIN and IFO,
// single-precision rounding (TIN 1 and 3), polar form converted.
Values DmigValues(const std::string& path, const Dmig& d, bool is_complex, bool single) {
  Values values(d.entries.size());
  for (size_t i = 0; i < d.entries.size(); ++i) {
    const DmigEntry& e = d.entries[i];
    if (!is_complex && e.b_given) {
      Fail(path, e.line,
           "DMIG " + d.name + ": imaginary part given for " + fe_text::DescribeDof(e.row) +
               " but TIN " + std::to_string(d.tin) +
               " declares a real matrix (expected the field after Ai blank)");
    }
    double re = e.a, im = e.b;
    if (is_complex && d.polar == 1) {
      const double phase = e.b * std::numbers::pi / 180.0;
      re = e.a * std::cos(phase);
      im = e.a * std::sin(phase);
    }
    if (single) {
      // volatile: GCC 12 -O2/-O3 (SLP vectorizer) drops this double->float->double rounding
      // of the (re, im) pair otherwise; clang and -O1 keep it.
      const volatile float fre = static_cast<float>(re), fim = static_cast<float>(im);
      re = fre;
      im = fim;
      if (!std::isfinite(re) || !std::isfinite(im)) {
        Fail(path, e.line,
             "DMIG " + d.name + ": value beyond the single-precision range (TIN " +
                 std::to_string(d.tin) + ")");
      }
    }
    if (d.ifo == 9) {
      if (e.col.component != 0) {
        Fail(path, e.line,
             "DMIG " + d.name +
                 ": IFO 9 column card needs CJ 0 or blank (GJ is the "
                 "column number), got " +
                 std::to_string(e.col.component));
      }
      if (e.col.node > d.ncol) {
        Fail(path, e.line,
             "DMIG " + d.name + ": column " + std::to_string(e.col.node) +
                 " out of range (expected 1..NCOL = " + std::to_string(d.ncol) + ")");
      }
    }
    values[i] = {re, im};
  }
  return values;
}

// One id cannot be both a scalar point (component 0) and a grid (components 1-6).
void CheckScalarOrGrid(const std::string& path, const Dmig& d) {
  std::vector<std::pair<DofId, size_t>> all;
  for (const DmigEntry& e : d.entries) {
    all.emplace_back(e.row, e.line);
    if (d.ifo != 9) all.emplace_back(e.col, e.line);
  }
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return fe_text::DofLess(a.first, b.first) || (a.first == b.first && a.second < b.second);
  });
  for (size_t i = 1; i < all.size(); ++i) {
    const DofId &p = all[i - 1].first, &q = all[i].first;
    if (p.node == q.node && p.component == 0 && q.component != 0) {
      Fail(path, std::max(all[i].second, all[i - 1].second),
           "DMIG " + d.name + ": id " + std::to_string(q.node) +
               " used both as a scalar point (component 0, line " +
               std::to_string(all[i - 1].second) + ") and as a grid (component " +
               std::to_string(q.component) + ", line " + std::to_string(all[i].second) + ")");
    }
  }
}

std::vector<DofId> SortedUnique(std::vector<DofId> v) {
  std::sort(v.begin(), v.end(), fe_text::DofLess);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Sorted row and column DOF sets. A square or symmetric form (IFO 1, 6) has one set for both; IFO
// 9 numbers its columns and has no column set.
void CollectDofSets(const Dmig& d, std::vector<DofId>& rows, std::vector<DofId>& cols) {
  for (const DmigEntry& e : d.entries) {
    rows.push_back(e.row);
    if (d.ifo != 9) (d.ifo == 2 ? cols : rows).push_back(e.col);
  }
  rows = SortedUnique(std::move(rows));
  cols = SortedUnique(std::move(cols));
  if (d.ifo == 1 || d.ifo == 6) cols = rows;
}

bool InExtrn(const ExtrnSorted& extrn_sorted, const std::vector<DofId>& set) {
  if (extrn_sorted.empty() || set.empty()) return false;
  for (const DofId& x : set) {
    const auto it = FindExtrn(extrn_sorted, x);
    if (it == extrn_sorted.end() || !(it->first == x)) return false;
  }
  return true;
}

// Index of DOF x in its (sorted) set, or its EXTRN position when the set takes the EXTRN order.
inline int64_t IndexOf(const ExtrnSorted& extrn_sorted, const std::vector<DofId>& set, bool extrn,
                       const DofId& x) {
  if (extrn) return static_cast<int64_t>(FindExtrn(extrn_sorted, x)->second);
  return static_cast<int64_t>(std::lower_bound(set.begin(), set.end(), x, fe_text::DofLess) -
                              set.begin());
}

// The entries of d with 0-based matrix indices.
std::vector<fe_text::TextEntry> IndexedEntries(const Dmig& d, const Values& values,
                                               const std::vector<DofId>& rows, bool rows_extrn,
                                               const std::vector<DofId>& cols, bool cols_extrn,
                                               const ExtrnSorted& extrn_sorted) {
  std::vector<fe_text::TextEntry> entries(d.entries.size());
  for (size_t i = 0; i < d.entries.size(); ++i) {
    const DmigEntry& e = d.entries[i];
    fe_text::TextEntry& t = entries[i];
    t.row = IndexOf(extrn_sorted, rows, rows_extrn, e.row);
    t.col = d.ifo == 9 ? e.col.node - 1 : IndexOf(extrn_sorted, cols, cols_extrn, e.col);
    t.re = values[i].first;
    t.im = values[i].second;
    t.line = e.line;
  }
  return entries;
}

}  // namespace

ExtrnSorted SortExtrn(const std::string& path, const std::vector<DofId>& extrn,
                      const std::vector<size_t>& lines) {
  ExtrnSorted sorted;
  for (size_t i = 0; i < extrn.size(); ++i) sorted.emplace_back(extrn[i], i);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return fe_text::DofLess(a.first, b.first); });
  for (size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].first == sorted[i - 1].first) {
      const size_t later = std::max(sorted[i].second, sorted[i - 1].second);
      Fail(path, lines[later], "EXTRN lists " + fe_text::DescribeDof(sorted[i].first) + " twice");
    }
  }
  return sorted;
}

FeMatrix BuildDmig(const std::string& path, const Dmig& d, const std::vector<DofId>& extrn,
                   const ExtrnSorted& extrn_sorted, const FeReadOptions& options) {
  if (!d.has_header) {
    Fail(path, d.first_line,
         "DMIG " + d.name + " has column cards but no header card (expected 'DMIG " + d.name +
             " 0 IFO TIN TOUT POLAR NCOL')");
  }
  FeMatrix m;
  m.name = d.name;
  m.symmetric = d.ifo == 6;
  m.is_complex = d.tin >= 3;
  m.source_precision_bits = (d.tin == 1 || d.tin == 3) ? 32 : 64;
  const Values values = DmigValues(path, d, m.is_complex, m.source_precision_bits == 32);
  CheckScalarOrGrid(path, d);

  std::vector<DofId> rows, cols;
  CollectDofSets(d, rows, cols);
  const bool rows_extrn = InExtrn(extrn_sorted, rows);
  const bool cols_extrn = d.ifo != 9 && InExtrn(extrn_sorted, cols);
  const std::vector<fe_text::TextEntry> entries =
      IndexedEntries(d, values, rows, rows_extrn, cols, cols_extrn, extrn_sorted);
  if (rows_extrn) rows = extrn;
  if (cols_extrn) cols = extrn;
  if ((d.ifo == 1 || d.ifo == 6) && rows_extrn != cols_extrn) {
    // cannot happen (same set), kept for clarity
    Fail(path, d.header_line, "DMIG " + d.name + ": inconsistent DOF sets");
  }
  m.rows = static_cast<int64_t>(rows.size());
  m.cols = d.ifo == 9 ? d.ncol : static_cast<int64_t>(cols.size());
  m.row_dofs = rows;
  if (d.ifo != 9) m.col_dofs = cols;
  const auto describe = [&](int64_t r, int64_t c) {
    const std::string col = d.ifo == 9 ? "column " + std::to_string(c + 1)
                                       : "column " + fe_text::DescribeDof(m.col_dofs[c]);
    return "(row " + fe_text::DescribeDof(m.row_dofs[r]) + ", " + col + ") of DMIG " + d.name;
  };
  fe_text::AssembleEntries(path, entries, m.symmetric, m, describe, options);
  return m;
}

void BuildNodeSets(const std::vector<SetCard>& sets, FeModel* model) {
  for (const SetCard& set : sets) {
    NodeSet* ns = nullptr;
    for (NodeSet& n : model->node_sets) {
      if (n.name == set.name) ns = &n;
    }
    if (!ns) {
      model->node_sets.push_back({set.name, {}});
      ns = &model->node_sets.back();
    }
    const auto add = [&](int64_t id) {
      if (std::find(ns->nodes.begin(), ns->nodes.end(), id) == ns->nodes.end()) {
        ns->nodes.push_back(id);
      }
    };
    for (const auto& [lo, hi] : set.ranges) {
      if (lo == hi) {
        add(lo);
        continue;
      }
      for (const FeNode& n : model->nodes) {
        if (n.id >= lo && n.id <= hi) add(n.id);
      }
    }
  }
}

}  // namespace fricrom::punch
