// Nastran bulk data / punch (.pch) reader: DMIG matrices (small, large and free field), GRID,
// GRDSET, CORD2R/C/S (CORD1* recorded by id), SET1/ASET/ASET1 node sets and EXTRN cards. Every
// other card is skipped (with its continuations).
// Format notes and the rules chosen here: docs/formats-nastran-punch.md. This file splits the
// cards and reads their fields; nastran_punch_dmig.cpp assembles the DMIG matrices.
#include <algorithm>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <string_view>
#include <utility>

#include "fe_text.h"
#include "fricrom/fe_model.h"
#include "nastran_punch_dmig.h"

namespace fricrom {

namespace {

using fe_text::Fail;
using fe_text::Printable;
using fe_text::Trim;
using fe_text::Upper;
using punch::Dmig;
using punch::DmigEntry;

// One bulk data entry with its continuations. fields[k] is data field k: field 2 of the first
// logical (8-field) line is k = 0, field 9 is k = 7, field 2 of the first continuation is k = 8...
struct Card {
  std::string name;  // field 1, upper case, without the large-field '*'
  size_t line = 0;
  std::vector<std::string_view> fields;
  std::vector<size_t> lines;        // physical line of each field
  std::deque<std::string> storage;  // tab-expanded lines the fields point into

  std::string_view Field(size_t k) const { return k < fields.size() ? Trim(fields[k]) : ""; }
  bool Blank(size_t k) const { return Field(k).empty(); }
  size_t LineOf(size_t k) const {
    if (k < lines.size()) return lines[k];
    return lines.empty() ? line : lines.back();
  }
  // "field 4" on the first logical line, "continuation 2 field 3" after.
  static std::string FieldName(size_t k) {
    const std::string f = "field " + std::to_string(k % 8 + 2);
    return k < 8 ? f : "continuation " + std::to_string(k / 8) + " " + f;
  }
};

struct GridCard {
  FeNode node;
  bool cp_blank = false, cd_blank = false;
  size_t line = 0;
};

class PunchReader {
 public:
  PunchReader(std::string path, const FeReadOptions& options)
      : path_(std::move(path)), options_(options) {}

  FeModel Read() {
    const std::string text = fe_text::ReadCompleteTextFile(path_, "Nastran punch/bulk data file");
    Parse(text);
    if (dmigs_.empty() && grids_.empty() && extrn_.empty() && systems_.empty()) {
      FailAt(0,
             "no DMIG, EXTRN, GRID or CORD2R/C/S card found: not a Nastran punch/bulk data file "
             "fricrom can read");
    }
    return Build();
  }

 private:
  [[noreturn]] void FailAt(size_t line, const std::string& what) const { Fail(path_, line, what); }

  // ---- Card splitting --------------------------------------------------------------------------

  // "BEGIN BULK" (any case, any spacing); "BEGIN SUPER ..." is not.
  static bool IsBeginBulk(std::string_view line) {
    const std::string t = Upper(Trim(line));
    if (t.rfind("BEGIN", 0) != 0) return false;
    return Trim(std::string_view(t).substr(5)).substr(0, 4) == "BULK";
  }

  static bool HasBeginBulk(std::string_view text) {
    size_t pos = 0;
    std::string_view line;
    while (fe_text::NextLine(text, pos, line)) {
      if (IsBeginBulk(line)) return true;
    }
    return false;
  }

  void Parse(std::string_view text) {
    bool in_bulk = !HasBeginBulk(text);
    size_t pos = 0, number = 0;
    std::string_view raw;
    while (fe_text::NextLine(text, pos, raw)) {
      ++number;
      std::string_view line = raw;
      const size_t dollar = line.find('$');
      if (dollar != std::string_view::npos) line = line.substr(0, dollar);
      if (Trim(line).empty()) continue;
      const std::string head = Upper(Trim(line).substr(0, std::min<size_t>(Trim(line).size(), 7)));
      if (head.rfind("BEGIN", 0) == 0) {
        Flush();
        if (IsBeginBulk(line)) in_bulk = true;
        continue;
      }
      if (!in_bulk) continue;
      if (head == "ENDDATA") break;
      if (head.rfind("INCLUDE", 0) == 0) {
        FailAt(number,
               "INCLUDE statements are not supported: read the included file itself (or merge "
               "it into one file)");
      }
      AddLine(line, number);
    }
    Flush();
  }

  void AddLine(std::string_view line, size_t number) {
    std::vector<std::string_view> data;  // the data fields of this physical line
    std::string_view first;
    const bool free_field = line.find(',') != std::string_view::npos;
    std::string_view text = line;
    std::string expanded;
    if (!free_field && line.find('\t') != std::string_view::npos) {
      for (char c : line) {
        if (c == '\t') {
          expanded.append(8 - expanded.size() % 8, ' ');
        } else {
          expanded += c;
        }
      }
    }
    if (free_field) {
      size_t start = 0;
      std::vector<std::string_view> tokens;
      while (true) {
        const size_t comma = text.find(',', start);
        tokens.push_back(text.substr(
            start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      first = Trim(tokens[0]);
      const bool large = !first.empty() && (first.front() == '*' || first.back() == '*');
      const size_t per_line = large ? 4 : 8;
      // Data fields, then optionally field 10 (continuation tag, ignored).
      if (tokens.size() > per_line + 2) {
        FailAt(number, "free-field line has " + std::to_string(tokens.size()) +
                           " fields; expected at most " + std::to_string(per_line + 2) + " (" +
                           (large ? "large" : "small") +
                           " field: name, data fields and a continuation tag)");
      }
      for (size_t k = 1; k < tokens.size() && k <= per_line; ++k) data.push_back(tokens[k]);
      data.resize(per_line);
    } else {
      // Tab-expanded lines must outlive the card: keep them in the card's storage (the card is
      // flushed below first when this line starts a new card).
      if (!expanded.empty()) text = expanded;
      first = Trim(text.substr(0, std::min<size_t>(text.size(), 8)));
    }
    const bool continuation = first.empty() || first.front() == '+' || first.front() == '*';
    const bool large = continuation ? (!first.empty() && first.front() == '*')
                                    : (!first.empty() && first.back() == '*');
    if (!continuation) {
      Flush();
      std::string_view name = first;
      if (!name.empty() && name.back() == '*') name.remove_suffix(1);
      card_.name = Upper(Trim(name));
      card_.line = number;
      have_card_ = true;
    } else if (!have_card_) {
      FailAt(number, "continuation line " + Printable(Trim(line)) +
                         " without a card to continue (expected a card name in columns 1-8)");
    }
    if (!free_field) {
      if (!expanded.empty()) {
        card_.storage.push_back(std::move(expanded));
        text = card_.storage.back();
      }
      const size_t width = large ? 16 : 8, count = large ? 4 : 8;
      for (size_t k = 0; k < count; ++k) {
        const size_t at = 8 + k * width;
        data.push_back(at < text.size() && at < 72 ? text.substr(at, std::min(width, 72 - at))
                                                   : std::string_view());
      }
    }
    // Logical layout: a small-field line fills fields 2-9 of a new logical line; a large-field
    // line fills fields 2-5 or 6-9 (the second line of a large-field pair).
    std::vector<std::string_view>& f = card_.fields;
    if (!large || f.size() % 8 == 0) {
      while (f.size() % 8 != 0) f.emplace_back();
    }
    for (std::string_view d : data) f.push_back(d);
    card_.lines.resize(f.size(), number);
  }

  void Flush() {
    if (have_card_) Process(card_);
    card_ = Card();
    have_card_ = false;
  }

  // ---- Field helpers ---------------------------------------------------------------------------

  int64_t Int(const Card& c, size_t k, const std::string& what) const {
    int64_t v = 0;
    if (!fe_text::ParseInt(c.Field(k), v)) {
      FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected " + what +
                              " (an integer), got " +
                              (c.Blank(k) ? std::string("a blank field") : Printable(c.Field(k))));
    }
    return v;
  }
  int64_t IntOr(const Card& c, size_t k, int64_t fallback, const std::string& what) const {
    return c.Blank(k) ? fallback : Int(c, k, what);
  }
  double Real(const Card& c, size_t k, const std::string& what) const {
    double v = 0;
    switch (fe_text::ParseReal(c.Field(k), v, true)) {
      case fe_text::RealStatus::kOk:
        return v;
      case fe_text::RealStatus::kNonFinite:
        FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected " + what +
                                " as a finite real number, got " + Printable(c.Field(k)) +
                                " (NaN, Inf or beyond the double range)");
      case fe_text::RealStatus::kEmpty:
        FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected " + what +
                                " (a real number), got a blank field");
      case fe_text::RealStatus::kBad:
        break;
    }
    FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected " + what +
                            " (a real number such as 1.5, 1.5E-3, 1.5D-3 or 1.5-3), got " +
                            Printable(c.Field(k)));
  }
  double RealOr(const Card& c, size_t k, double fallback, const std::string& what) const {
    return c.Blank(k) ? fallback : Real(c, k, what);
  }
  int Component(const Card& c, size_t k, const std::string& what) const {
    const int64_t v = IntOr(c, k, 0, what);
    if (v < 0 || v > 6) {
      FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected " + what +
                              " 1..6 for a grid or 0 (blank) for a scalar point, got " +
                              std::to_string(v));
    }
    return static_cast<int>(v);
  }

  // ---- Cards -----------------------------------------------------------------------------------

  void Process(const Card& c) {
    if (c.name == "DMIG") {
      ProcessDmig(c);
    } else if (c.name == "GRID") {
      ProcessGrid(c);
    } else if (c.name == "GRDSET") {
      grdset_cp_ = IntOr(c, 1, 0, "CP (coordinate system id)");
      grdset_cd_ = IntOr(c, 5, 0, "CD (coordinate system id)");
      constexpr int64_t kMaxId = std::numeric_limits<int>::max();
      if (grdset_cp_ < 0 || grdset_cp_ > kMaxId || grdset_cd_ < -1 || grdset_cd_ > kMaxId) {
        FailAt(c.line, "GRDSET: expected CP >= 0 and CD >= -1 (coordinate system ids)");
      }
    } else if (c.name == "CORD2R" || c.name == "CORD2C" || c.name == "CORD2S") {
      ProcessCord2(c, c.name[5]);
    } else if (c.name == "CORD1R" || c.name == "CORD1C" || c.name == "CORD1S") {
      ProcessCord1(c);
    } else if (c.name == "SET1") {
      ProcessSet1(c);
    } else if (c.name == "ASET" || c.name == "ASET1") {
      ProcessAset(c);
    } else if (c.name == "EXTRN") {
      ProcessExtrn(c);
    }
  }

  Dmig& FindDmig(const std::string& name, size_t line) {
    auto it = dmig_index_.find(name);
    if (it == dmig_index_.end()) {
      it = dmig_index_.emplace(name, dmigs_.size()).first;
      dmigs_.emplace_back();
      dmigs_.back().name = name;
      dmigs_.back().first_line = line;
    }
    return dmigs_[it->second];
  }

  void ProcessDmig(const Card& c) {
    const std::string name = Upper(c.Field(0));
    if (name.empty()) FailAt(c.line, "DMIG field 2: expected the matrix name, got a blank field");
    const int64_t f3 = Int(c, 1, "0 (header card) or the column grid/point GJ (column card)");
    Dmig& d = FindDmig(name, c.line);
    if (f3 == 0) {
      if (d.has_header) {
        FailAt(c.line, "second header card for DMIG " + name + " (the first is on line " +
                           std::to_string(d.header_line) + ")");
      }
      d.has_header = true;
      d.header_line = c.line;
      d.ifo = Int(c, 2, "IFO (form of matrix: 1, 2, 6 or 9)");
      if (d.ifo != 1 && d.ifo != 2 && d.ifo != 6 && d.ifo != 9) {
        FailAt(c.LineOf(2), "DMIG " + name + " header field 4: unknown IFO " +
                                std::to_string(d.ifo) +
                                " (expected 1 square, 2 rectangular, 6 symmetric or 9 "
                                "rectangular with NCOL)");
      }
      d.tin = Int(c, 3, "TIN (input type 1..4)");
      if (d.tin < 1 || d.tin > 4) {
        FailAt(c.LineOf(3), "DMIG " + name + " header field 5: unknown TIN " +
                                std::to_string(d.tin) +
                                " (expected 1 real single, 2 real double, 3 complex single or 4 "
                                "complex double)");
      }
      d.tout = IntOr(c, 4, 0, "TOUT (output type 0..4)");
      if (d.tout < 0 || d.tout > 4) {
        FailAt(c.LineOf(4), "DMIG " + name + " header field 6: unknown TOUT " +
                                std::to_string(d.tout) + " (expected 0..4 or blank)");
      }
      d.polar = IntOr(c, 5, 0, "POLAR (0 or 1)");
      if (d.polar != 0 && d.polar != 1) {
        FailAt(c.LineOf(5), "DMIG " + name + " header field 7: expected POLAR 0, 1 or blank, got " +
                                std::to_string(d.polar));
      }
      d.ncol = IntOr(c, 7, 0, "NCOL (number of columns)");
      if (d.ifo == 9 && (d.ncol < 1 || d.ncol > fe_text::kMaxDimension)) {
        FailAt(c.LineOf(7),
               "DMIG " + name + " header field 9: IFO 9 needs NCOL in 1.." +
                   std::to_string(fe_text::kMaxDimension) + ", got " +
                   (c.Blank(7) ? std::string("a blank field") : std::to_string(d.ncol)));
      }
      for (size_t k = 8; k < c.fields.size(); ++k) {
        if (!c.Blank(k)) {
          FailAt(c.LineOf(k), "DMIG " + name + " header card: unexpected " + Card::FieldName(k) +
                                  " " + Printable(c.Field(k)) +
                                  " (a header card has no continuation)");
        }
      }
      return;
    }
    if (f3 < 0) {
      FailAt(c.LineOf(1), "DMIG " + name + " field 3: expected GJ > 0 (or 0 on the header), got " +
                              std::to_string(f3));
    }
    DofId col{f3, Component(c, 2, "column component CJ")};
    const size_t before = d.entries.size();
    for (size_t q = 4; q < c.fields.size(); q += 4) {
      if (c.Blank(q) && c.Blank(q + 1) && c.Blank(q + 2) && c.Blank(q + 3)) continue;
      if (c.Blank(q)) {
        FailAt(c.LineOf(q), "DMIG " + name + " " + Card::FieldName(q) +
                                ": expected the row grid/point Gi, got a blank field (its "
                                "component or value is given)");
      }
      DmigEntry e;
      e.col = col;
      e.row.node = Int(c, q, "row grid/point Gi");
      if (e.row.node <= 0) {
        FailAt(c.LineOf(q), "DMIG " + name + " " + Card::FieldName(q) +
                                ": expected a row grid/point id > 0, got " +
                                std::to_string(e.row.node));
      }
      e.row.component = Component(c, q + 1, "row component Ci");
      if (c.Blank(q + 2)) {
        FailAt(c.LineOf(q + 2), "DMIG " + name + " " + Card::FieldName(q + 2) +
                                    ": expected the value Ai of row " +
                                    fe_text::DescribeDof(e.row) + ", got a blank field");
      }
      e.a = Real(c, q + 2, "the value Ai");
      e.b_given = !c.Blank(q + 3);
      if (e.b_given) e.b = Real(c, q + 3, "the value Bi");
      e.line = c.LineOf(q);
      d.entries.push_back(e);
    }
    // Exporters never write a column without terms: a column card with none is a card cut off
    // before its continuation (a truncated file).
    if (d.entries.size() == before) {
      FailAt(c.LineOf(1), "DMIG " + name + " column " + fe_text::DescribeDof(col) +
                              " has no terms (expected Gi Ci Ai on the card or its "
                              "continuation): truncated card or file");
    }
  }

  void ProcessGrid(const Card& c) {
    GridCard g;
    g.line = c.line;
    g.node.id = Int(c, 0, "the grid id");
    if (g.node.id <= 0) {
      FailAt(c.LineOf(0), "GRID field 2: expected a grid id > 0, got " + std::to_string(g.node.id));
    }
    g.cp_blank = c.Blank(1);
    const int64_t cp = IntOr(c, 1, 0, "CP (coordinate system id)");
    for (int i = 0; i < 3; ++i) g.node.xyz[i] = RealOr(c, 2 + i, 0.0, "a coordinate");
    g.cd_blank = c.Blank(5);
    const int64_t cd = IntOr(c, 5, 0, "CD (coordinate system id)");
    constexpr int64_t kMaxId = std::numeric_limits<int>::max();
    if (cp < 0 || cp > kMaxId || cd < -1 || cd > kMaxId) {
      FailAt(c.line, "GRID " + std::to_string(g.node.id) +
                         ": expected CP >= 0 and CD >= -1 (coordinate system ids), got " +
                         std::to_string(cp) + " and " + std::to_string(cd));
    }
    g.node.position_system = static_cast<int>(cp);
    g.node.displacement_system = static_cast<int>(cd);
    grids_.push_back(g);
  }

  void ProcessCord2(const Card& c, char type) {
    CoordinateSystem s;
    s.type = type;
    const int64_t id = Int(c, 0, "the coordinate system id CID");
    const int64_t ref = IntOr(c, 1, 0, "the reference system RID");
    constexpr int64_t kMaxId = std::numeric_limits<int>::max();
    if (id <= 0 || id > kMaxId || ref < 0 || ref > kMaxId) {
      FailAt(c.line, c.name + ": expected CID > 0 and RID >= 0, got " + std::to_string(id) +
                         " and " + std::to_string(ref));
    }
    s.id = static_cast<int>(id);
    s.reference = static_cast<int>(ref);
    for (int i = 0; i < 3; ++i) {
      s.a[i] = RealOr(c, 2 + i, 0.0, "a coordinate of point A");
      s.b[i] = RealOr(c, 5 + i, 0.0, "a coordinate of point B");
      s.c[i] = RealOr(c, 8 + i, 0.0, "a coordinate of point C");
    }
    const Eigen::Vector3d z = s.b - s.a, xz = s.c - s.a;
    // (Points given in a curvilinear reference are checked once resolved: BasicFrame.)
    if (s.reference == 0 &&
        (!(z.norm() > 0) || !(z.cross(xz).norm() > 1e-12 * z.norm() * xz.norm()))) {
      FailAt(c.line, c.name + " " + std::to_string(s.id) +
                         ": degenerate system (expected B != A and C off the line A-B)");
    }
    AddSystem(s, c);
  }

  // CORD1R/C/S: up to two systems per card, each by three grid ids. Recorded so that a grid
  // using one is refused by name (BasicFrame) instead of reported as undefined.
  void ProcessCord1(const Card& c) {
    for (size_t k = 0; k < 8 && k < c.fields.size(); k += 4) {
      if (k > 0 && c.Blank(k)) break;
      const int64_t id = Int(c, k, "the coordinate system id CID");
      if (id <= 0 || id > std::numeric_limits<int>::max()) {
        FailAt(c.LineOf(k), c.name + ": expected CID > 0, got " + std::to_string(id));
      }
      CoordinateSystem s;
      s.id = static_cast<int>(id);
      s.type = c.name[5];
      s.by_grids = true;
      for (int i = 0; i < 3; ++i) s.a[i] = static_cast<double>(IntOr(c, k + 1 + i, 0, "a grid id"));
      AddSystem(s, c);
    }
  }

  void AddSystem(const CoordinateSystem& s, const Card& c) {
    for (const auto& [other, line] : systems_) {
      if (other.id != s.id) continue;
      if (other.reference == s.reference && other.type == s.type && other.by_grids == s.by_grids &&
          other.a == s.a && other.b == s.b && other.c == s.c) {
        return;  // the same card repeated (punch files repeat it per section)
      }
      FailAt(c.line, c.name + " " + std::to_string(s.id) +
                         " defined twice with different data (first on line " +
                         std::to_string(line) + ")");
    }
    systems_.emplace_back(s, c.line);
  }

  // Grid ids of a set card from field `first` on: single ids and "A THRU B" ranges (a range
  // keeps the grids of the file inside it, so a wide range allocates nothing).
  void ReadIdList(const Card& c, size_t first, size_t step, punch::SetCard* set) {
    for (size_t k = first; k < c.fields.size(); k += step) {
      if (c.Blank(k)) continue;
      if (Upper(c.Field(k)) == "THRU") {
        if (set->ranges.empty() || k + 1 >= c.fields.size() || c.Blank(k + 1)) {
          FailAt(c.LineOf(k),
                 c.name + " " + Card::FieldName(k) + ": THRU needs an id before and after it");
        }
        const int64_t to = Int(c, k + 1, "the last id of a THRU range");
        if (to < set->ranges.back().first) {
          FailAt(c.LineOf(k + 1), c.name + ": THRU range ends at " + std::to_string(to) +
                                      ", before its start " +
                                      std::to_string(set->ranges.back().first));
        }
        set->ranges.back().second = to;
        ++k;
        continue;
      }
      const int64_t id = Int(c, k, "a grid id");
      if (id <= 0) {
        FailAt(c.LineOf(k), c.name + " " + Card::FieldName(k) + ": expected a grid id > 0, got " +
                                std::to_string(id));
      }
      set->ranges.emplace_back(id, id);
    }
  }

  // SET1 SID G1 G2 ... (THRU): node set "SET1_<SID>".
  void ProcessSet1(const Card& c) {
    const int64_t sid = Int(c, 0, "the set id SID");
    punch::SetCard set;
    set.name = "SET1_" + std::to_string(sid);
    set.line = c.line;
    ReadIdList(c, 1, 1, &set);
    for (const punch::SetCard& o : sets_) {
      if (o.name == set.name && o.ranges != set.ranges) {
        FailAt(c.line, "SET1 " + std::to_string(sid) + " defined twice with different grids " +
                           "(first on line " + std::to_string(o.line) + ")");
      }
    }
    sets_.push_back(std::move(set));
  }

  // ASET ID1 C1 ID2 C2 ... and ASET1 C G1 G2 ... (THRU): the grids (not the scalar points,
  // component 0) join node set "ASET", a superelement's boundary.
  void ProcessAset(const Card& c) {
    punch::SetCard set;
    set.name = "ASET";
    set.line = c.line;
    if (c.name == "ASET1") {
      const int64_t comp = IntOr(c, 0, 0, "the components C");
      if (comp != 0) ReadIdList(c, 1, 1, &set);
    } else {
      for (size_t k = 0; k < c.fields.size(); k += 2) {
        if (c.Blank(k)) continue;
        const int64_t id = Int(c, k, "a grid id");
        if (IntOr(c, k + 1, 0, "the components C") != 0) set.ranges.emplace_back(id, id);
      }
    }
    sets_.push_back(std::move(set));
  }

  void ProcessExtrn(const Card& c) {
    for (size_t k = 0; k < c.fields.size(); k += 2) {
      if (c.Blank(k) && c.Blank(k + 1)) continue;
      if (c.Blank(k)) {
        FailAt(c.LineOf(k), "EXTRN " + Card::FieldName(k) +
                                ": expected a grid/point id, got a blank field (its component "
                                "is given)");
      }
      const int64_t id = Int(c, k, "a grid/point id");
      if (id <= 0) {
        FailAt(c.LineOf(k),
               "EXTRN " + Card::FieldName(k) + ": expected an id > 0, got " + std::to_string(id));
      }
      const std::string_view comps = c.Blank(k + 1) ? std::string_view("0") : c.Field(k + 1);
      bool seen[7] = {};
      bool ok = !comps.empty() && comps.size() <= 6;
      for (char ch : comps) {
        if (ch < '0' || ch > '6' || seen[ch - '0']) ok = false;
        if (ok) seen[ch - '0'] = true;
      }
      if (ok && seen[0] && comps.size() != 1) ok = false;
      if (!ok) {
        FailAt(c.LineOf(k + 1), "EXTRN " + Card::FieldName(k + 1) +
                                    ": expected components like 123456 (digits 1-6, each once) or "
                                    "0 for a scalar point, got " +
                                    Printable(comps));
      }
      for (int comp = 0; comp <= 6; ++comp) {
        if (seen[comp]) {
          extrn_.push_back(DofId{id, comp});
          extrn_lines_.push_back(c.LineOf(k));
        }
      }
    }
  }

  // ---- Model -----------------------------------------------------------------------------------

  FeModel Build() {
    FeModel model;
    model.source = path_;
    model.format = "dmig";

    // EXTRN: unique DOFs; sorted copy with original positions for look-ups.
    const punch::ExtrnSorted extrn_sorted = punch::SortExtrn(path_, extrn_, extrn_lines_);
    for (const Dmig& d : dmigs_) {
      model.matrices.push_back(punch::BuildDmig(path_, d, extrn_, extrn_sorted, options_));
    }

    model.external_dofs = extrn_;  // DOF order of the external superelement

    for (GridCard& g : grids_) {
      if (g.cp_blank) g.node.position_system = static_cast<int>(grdset_cp_);
      if (g.cd_blank) g.node.displacement_system = static_cast<int>(grdset_cd_);
    }
    std::stable_sort(grids_.begin(), grids_.end(),
                     [](const GridCard& a, const GridCard& b) { return a.node.id < b.node.id; });
    for (size_t i = 0; i < grids_.size(); ++i) {
      if (i > 0 && grids_[i].node.id == grids_[i - 1].node.id) {
        const FeNode &a = grids_[i - 1].node, &b = grids_[i].node;
        if (a.xyz == b.xyz && a.position_system == b.position_system &&
            a.displacement_system == b.displacement_system) {
          continue;  // the same card repeated (punch files repeat it per section)
        }
        FailAt(std::max(grids_[i].line, grids_[i - 1].line),
               "GRID " + std::to_string(b.id) +
                   " defined twice with different data (other card on line " +
                   std::to_string(std::min(grids_[i].line, grids_[i - 1].line)) + ")");
      }
      model.nodes.push_back(grids_[i].node);
    }
    std::stable_sort(systems_.begin(), systems_.end(),
                     [](const auto& a, const auto& b) { return a.first.id < b.first.id; });
    for (const auto& s : systems_) model.systems.push_back(s.first);
    punch::BuildNodeSets(sets_, &model);
    return model;
  }

  std::string path_;
  const FeReadOptions& options_;
  Card card_;
  bool have_card_ = false;
  std::vector<Dmig> dmigs_;
  std::map<std::string, size_t> dmig_index_;
  std::vector<GridCard> grids_;
  int64_t grdset_cp_ = 0, grdset_cd_ = 0;
  std::vector<std::pair<CoordinateSystem, size_t>> systems_;
  std::vector<punch::SetCard> sets_;
  std::vector<DofId> extrn_;
  std::vector<size_t> extrn_lines_;
};

}  // namespace

FeModel ReadNastranPunch(const std::string& path, const FeReadOptions& options) {
  FeModel model = PunchReader(path, options).Read();
  fe_text::KeepOnly(path, options, model);
  return model;
}

}  // namespace fricrom
