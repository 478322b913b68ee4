// FeModel::Find, ReadFe (reader dispatch) and the text helpers shared by the text readers
// (nastran_punch.cpp, abaqus_reader.cpp, calculix_reader.cpp, matrix_market.cpp), declared in the
// private header fe_text.h.
#include "fricrom/fe_model.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <new>
#include <numeric>
#include <string_view>
#include <system_error>

#include "fe_text.h"

namespace fricrom {

namespace fe_text {

std::string Printable(std::string_view s) {
  constexpr size_t kMax = 40;
  std::string out;
  for (size_t i = 0; i < s.size() && i < kMax; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      static const char* kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (s.size() > kMax) out += "...";
  return "'" + out + "'";
}

[[noreturn]] void Fail(const std::string& file, size_t line, const std::string& what) {
  std::string msg = file;
  if (line > 0) msg += ":" + std::to_string(line);
  msg += ": " + what;
  throw FeReadError(msg);
}

std::string ReadWholeFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    Fail(path, 0, "cannot open " + what + ": no such file");
  if (std::filesystem::is_directory(status))
    Fail(path, 0, "expected " + what + ", got a directory");
  // A device (/dev/zero, /dev/urandom) holds no file and never ends.
  if (std::filesystem::is_character_file(status) || std::filesystem::is_block_file(status))
    Fail(path, 0, "expected " + what + ", got a device");
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path, 0, "cannot open " + what);
  // One read of the whole (regular) file into a buffer of its size, then whatever is left (a file
  // that grew meanwhile, or one whose size the file system does not know, e.g. a pipe).
  std::string text;
  std::error_code size_ec;
  const std::uintmax_t size =
      std::filesystem::is_regular_file(status) ? std::filesystem::file_size(path, size_ec) : 0;
  if (!size_ec && size > 0 && size < static_cast<std::uintmax_t>(text.max_size())) {
    text.resize(static_cast<size_t>(size));
    in.read(text.data(), static_cast<std::streamsize>(size));
    text.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  }
  if (!in.bad() && !in.eof()) {
    char chunk[1 << 16];
    while (in.read(chunk, sizeof(chunk)) || in.gcount() > 0) {
      text.append(chunk, static_cast<size_t>(in.gcount()));
      if (in.eof()) break;
    }
  }
  if (in.bad()) Fail(path, 0, "error while reading " + what);
  return text;
}

std::string ReadCompleteTextFile(const std::string& path, const std::string& what) {
  std::string text = ReadWholeFile(path, what);
  if (text.empty()) Fail(path, 0, "empty " + what);
  if (text.back() != '\n') {
    size_t lines = 1;
    for (char c : text) lines += c == '\n';
    Fail(path, lines,
         "the last line has no line break: the " + what + " is truncated (" +
             std::to_string(text.size()) + " bytes; exporters end every line with a line break)");
  }
  return text;
}

// Next line of `text` from `pos` (without the line break and a trailing '\r'); false at the end.
bool NextLine(std::string_view text, size_t& pos, std::string_view& line) {
  if (pos >= text.size()) return false;
  const size_t end = text.find('\n', pos);
  const size_t stop = end == std::string_view::npos ? text.size() : end;
  line = text.substr(pos, stop - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos = end == std::string_view::npos ? text.size() : end + 1;
  return true;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string Upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

// Whole (trimmed) field as a base-10 integer; a leading '+' is allowed.
bool ParseInt(std::string_view s, int64_t& out) {
  s = Trim(s);
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return false;
  }
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// Whole (trimmed) field as a double. Accepts a leading '+', 'D'/'d' exponents, and with
// `nastran` the implicit exponent of Nastran fields ("1.5-3" = 1.5e-3, "2.+5" = 2e5). NaN, Inf
// and values overflowing a double are kNonFinite; underflow gives the nearest double.
RealStatus ParseReal(std::string_view s, double& out, bool nastran) {
  s = Trim(s);
  if (s.empty()) return RealStatus::kEmpty;
  if (s.front() == '+') {
    s.remove_prefix(1);
    if (s.empty() || s.front() == '+' || s.front() == '-') return RealStatus::kBad;
  }
  bool needs_copy = false;
  bool has_exponent = false;
  size_t implicit_at = std::string_view::npos;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == 'd' || c == 'D') needs_copy = true;
    if (c == 'd' || c == 'D' || c == 'e' || c == 'E') has_exponent = true;
    if ((c == '+' || c == '-') && i > 0 && implicit_at == std::string_view::npos) {
      const char p = s[i - 1];
      if ((p >= '0' && p <= '9') || p == '.') implicit_at = i;
    }
  }
  if (nastran && !has_exponent && implicit_at != std::string_view::npos) needs_copy = true;
  char small[64];
  std::string big;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (needs_copy) {
    char* buf = small;
    if (s.size() + 2 > sizeof(small)) {
      big.resize(s.size() + 2);
      buf = big.data();
    }
    size_t n = 0;
    for (size_t i = 0; i < s.size(); ++i) {
      if (nastran && !has_exponent && i == implicit_at) buf[n++] = 'e';
      const char c = s[i];
      buf[n++] = (c == 'd' || c == 'D') ? 'e' : c;
    }
    first = buf;
    last = buf + n;
  }
  const auto [ptr, ec] = std::from_chars(first, last, out, std::chars_format::general);
  if (ptr != last || ec == std::errc::invalid_argument) return RealStatus::kBad;
  if (ec == std::errc::result_out_of_range) {
    // from_chars reports both overflow and underflow; strtod tells them apart.
    const std::string copy(first, last);
    errno = 0;
    const double v = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(v)) return RealStatus::kNonFinite;
    out = v;
  } else if (ec != std::errc()) {
    return RealStatus::kBad;
  }
  if (!std::isfinite(out)) return RealStatus::kNonFinite;
  return RealStatus::kOk;
}

// Number parse with the error message every reader uses.
double RequireReal(std::string_view field, bool nastran, const std::string& file, size_t line,
                   const std::string& what) {
  double v = 0;
  switch (ParseReal(field, v, nastran)) {
    case RealStatus::kOk:
      return v;
    case RealStatus::kEmpty:
      Fail(file, line, "expected " + what + " (a real number), got an empty field");
    case RealStatus::kNonFinite:
      Fail(file, line,
           "expected " + what + " as a finite real number, got " + Printable(field) +
               " (NaN, Inf or beyond the double range)");
    case RealStatus::kBad:
      break;
  }
  Fail(file, line, "expected " + what + " (a real number), got " + Printable(field));
}

int64_t RequireInt(std::string_view field, const std::string& file, size_t line,
                   const std::string& what) {
  int64_t v = 0;
  if (!ParseInt(field, v)) {
    Fail(file, line,
         "expected " + what + " (an integer), got " +
             (Trim(field).empty() ? std::string("an empty field") : Printable(field)));
  }
  return v;
}

// Splits `line` into the tokens separated by blanks, tabs and/or commas (no empty tokens).
void SplitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  const size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t' || line[i] == ',')) ++i;
    if (i >= n) break;
    const size_t start = i;
    while (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != ',') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
}

bool DofLess(const DofId& a, const DofId& b) {
  return a.node != b.node ? a.node < b.node : a.component < b.component;
}

std::string DescribeDof(const DofId& d) {
  return "node " + std::to_string(d.node) + " component " + std::to_string(d.component);
}

// True when some off-diagonal entry (i, j) also appears as (j, i).
bool HasTransposePair(const std::vector<TextEntry>& entries) {
  // Common case first: every off-diagonal entry in the same strict triangle (O(n), no sort).
  bool lower = false, upper = false;
  for (const TextEntry& e : entries) {
    lower = lower || e.row > e.col;
    upper = upper || e.row < e.col;
  }
  if (!lower || !upper) return false;
  std::vector<std::pair<int64_t, int64_t>> keys;
  keys.reserve(entries.size());
  for (const TextEntry& e : entries) {
    if (e.row != e.col) keys.emplace_back(e.row, e.col);
  }
  std::sort(keys.begin(), keys.end());
  for (const auto& [r, c] : keys) {
    if (std::binary_search(keys.begin(), keys.end(), std::make_pair(c, r))) return true;
  }
  return false;
}

// Highest accepted component number in DOF maps (Abaqus numbers degrees of freedom up to 30;
// Nastran uses 1..6 and 0 for scalar points).

// Fails when a DOF appears twice in a map; `lines` gives the line of each DOF (may be empty).
void CheckUniqueDofs(const std::string& file, const std::vector<DofId>& dofs,
                     const std::vector<size_t>& lines) {
  std::vector<size_t> order(dofs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return DofLess(dofs[a], dofs[b]); });
  for (size_t k = 1; k < order.size(); ++k) {
    if (dofs[order[k]] == dofs[order[k - 1]]) {
      const size_t a = std::min(order[k], order[k - 1]), b = std::max(order[k], order[k - 1]);
      const size_t line_b = lines.empty() ? 0 : lines[b];
      const std::string other =
          lines.empty() ? "entry " + std::to_string(a + 1) : "line " + std::to_string(lines[a]);
      Fail(file, line_b, "DOF " + DescribeDof(dofs[b]) + " listed twice (also on " + other + ")");
    }
  }
}

// DOF-map sidecar: a header line `node,component`, then one `node,component` line per row.
std::vector<DofId> ReadDofCsv(const std::string& path) {
  const std::string text = ReadCompleteTextFile(path, "DOF map (node,component CSV)");
  std::vector<DofId> dofs;
  std::vector<size_t> lines;
  size_t pos = 0, number = 0;
  bool header = false;
  std::string_view line;
  while (NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = Trim(line);
    if (t.empty()) continue;
    const size_t comma = t.find(',');
    if (!header) {
      if (comma == std::string_view::npos || Upper(Trim(t.substr(0, comma))) != "NODE" ||
          Upper(Trim(t.substr(comma + 1))) != "COMPONENT") {
        Fail(path, number, "expected the header line 'node,component', got " + Printable(t));
      }
      header = true;
      continue;
    }
    if (comma == std::string_view::npos) {
      Fail(path, number, "expected 'node,component', got " + Printable(t));
    }
    DofId d;
    d.node = RequireInt(t.substr(0, comma), path, number, "a node id");
    const int64_t c = RequireInt(t.substr(comma + 1), path, number, "a component");
    if (c < 0 || c > kMaxComponent) {
      Fail(path, number,
           "expected a component 0.." + std::to_string(kMaxComponent) + ", got " +
               std::to_string(c));
    }
    d.component = static_cast<int>(c);
    dofs.push_back(d);
    lines.push_back(number);
  }
  if (!header) Fail(path, number, "empty DOF map: expected the header line 'node,component'");
  CheckUniqueDofs(path, dofs, lines);
  return dofs;
}

// Default DOF-map sidecar of a matrix file: same name, extension replaced by ".dof.csv".
std::string DefaultDofSidecar(const std::string& path) {
  std::filesystem::path p(path);
  p.replace_extension(".dof.csv");
  return p.string();
}

}  // namespace fe_text

const FeMatrix* FeModel::Find(const std::string& name) const {
  const std::string wanted = fe_text::Upper(name);
  for (const FeMatrix& m : matrices) {
    if (fe_text::Upper(m.name) == wanted) return &m;
  }
  return nullptr;
}

const NodeSet* FeModel::FindNodeSet(const std::string& name) const {
  const std::string wanted = fe_text::Upper(name);
  for (const NodeSet& s : node_sets) {
    if (fe_text::Upper(s.name) == wanted) return &s;
  }
  return nullptr;
}

const FeNode* FeModel::FindNode(int64_t id) const {
  for (const FeNode& n : nodes) {
    if (n.id == id) return &n;
  }
  return nullptr;
}

namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// First bytes of a file (up to n), empty when it cannot be read.
std::string Head(const std::string& path, size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(s.data(), static_cast<std::streamsize>(n));
  s.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return s;
}

bool StartsWithMatrixMarket(const std::string& path) {
  const std::string head = Head(path, 14);
  return fe_text::Upper(head) == "%%MATRIXMARKET";
}

// True when the Nastran bulk text has a DMIG or EXTRN card (a card name in columns 1-8, small,
// large or free field).
bool HasNastranMatrixCards(const std::string& path) {
  const std::string text = fe_text::ReadWholeFile(path, "Nastran bulk data");
  size_t pos = 0;
  std::string_view line;
  while (fe_text::NextLine(text, pos, line)) {
    const std::string name = fe_text::Upper(line.substr(0, std::min<size_t>(line.size(), 5)));
    if (name.rfind("DMIG", 0) == 0) {
      const char next = name.size() > 4 ? name[4] : ' ';
      if (next == ' ' || next == '*' || next == ',' || next == '\t') return true;
    }
    if (name == "EXTRN") return true;
  }
  return false;
}

}  // namespace

void ReadMeshDeck(const std::string& path, FeModel& model) {
  const std::string ext = LowerExtension(path);
  const bool nastran = ext == ".pch" || ext == ".bdf" || ext == ".dat" || ext == ".nas" ||
                       ext == ".blk" || ext == ".asm" || ext == ".bulk";
  const size_t nodes = model.nodes.size(), sets = model.node_sets.size();
  if (!nastran) {
    ReadInpNodesAndSets(path, model);
  } else {
    // Grids, systems and sets only: the deck's matrices (DMIG) are not a mesh's business.
    FeModel deck = ReadNastranPunch(path);
    for (const FeNode& n : deck.nodes) {
      if (!model.FindNode(n.id)) model.nodes.push_back(n);
    }
    model.systems.insert(model.systems.end(), deck.systems.begin(), deck.systems.end());
    for (NodeSet& s : deck.node_sets) {
      if (!model.FindNodeSet(s.name)) model.node_sets.push_back(std::move(s));
    }
  }
  if (model.nodes.size() == nodes && model.node_sets.size() == sets) {
    fe_text::Fail(path, 0,
                  nastran ? "no GRID, SET1 or ASET card: a mesh from Nastran bulk data needs "
                            "the grids (GRID, CORD2R/C/S) or node sets (SET1, ASET, ASET1)"
                          : "no *NODE or *NSET: expected an Abaqus/CalculiX input deck with "
                            "nodes or node sets (a Nastran deck is read by its extension: .pch, "
                            ".bdf, .dat, .nas, .blk, .asm, .bulk)");
  }
}

FeModel ReadDofMap(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".pch" || ext == ".bdf" || ext == ".dat" || ext == ".nas" || ext == ".blk" ||
      ext == ".asm" || ext == ".bulk") {
    FeModel deck = ReadNastranPunch(path);
    if (deck.external_dofs.empty()) {
      fe_text::Fail(path, 0,
                    "no EXTRN card: a DOF map from Nastran bulk data is the EXTRN order of an "
                    "external superelement (EXTSEOUT punch or .asm)");
    }
    deck.matrices.clear();
    return deck;
  }
  if (ext != ".csv") {
    fe_text::Fail(path, 0,
                  "expected a DOF map: a CSV file (header node,component, one row per matrix "
                  "row) or a Nastran punch with an EXTRN card (.pch, .asm, .bdf, .dat)");
  }
  FeModel map;
  map.source = path;
  map.format = "dof-csv";
  map.external_dofs = fe_text::ReadDofCsv(path);
  return map;
}

FeModel ReadFe(const std::string& path, const FeReadOptions& options) {
  const std::string ext = LowerExtension(path);
  if (ext == ".op4") return ReadOp4(path, options);
  if (ext == ".pch") return ReadNastranPunch(path, options);
  if (ext == ".bdf" || ext == ".dat" || ext == ".nas" || ext == ".blk") {
    if (!HasNastranMatrixCards(path)) {
      fe_text::Fail(path, 0,
                    "no DMIG or EXTRN card: expected Nastran bulk data with DMIG matrices (only "
                    "DMIG, EXTRN, GRID and CORD2R cards are read from Nastran decks)");
    }
    return ReadNastranPunch(path, options);
  }
  if (ext == ".sti" || ext == ".mas" || ext == ".dof" || ext == ".inp") {
    std::filesystem::path prefix(path);
    prefix.replace_extension();
    return ReadCalculix(prefix.string(), options);
  }
  if (ext == ".mtx" || ext == ".mm") {
    if (!std::filesystem::exists(path))
      fe_text::Fail(path, 0, "cannot open matrix file: no such file");
    if (StartsWithMatrixMarket(path)) {
      const std::string sidecar = fe_text::DefaultDofSidecar(path);
      return ReadMatrixMarket(path, std::filesystem::exists(sidecar) ? sidecar : "", options);
    }
    return ReadAbaqusMatrix(path, options);
  }
  if (std::filesystem::exists(path) && StartsWithMatrixMarket(path)) {
    return ReadMatrixMarket(path, "", options);
  }
  fe_text::Fail(path, 0,
                "unknown FE matrix format (expected .op4, .pch/.bdf/.dat with DMIG, .mtx (Matrix "
                "Market or Abaqus), or .sti/.mas/.dof/.inp (CalculiX))");
}

}  // namespace fricrom
