// Nodes, node sets and elements of an Abaqus/CalculiX input deck (.inp). Only *NODE, *NSET,
// *ELEMENT and *INCLUDE are interpreted; every other keyword block is skipped, so a full analysis
// deck can be given.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "fe_text.h"
#include "fricrom/fe_model.h"

namespace fricrom {

namespace {

using fe_text::Fail;

constexpr int kMaxIncludeDepth = 16;
// Bounds on what *NSET, GENERATE may produce (one line / the whole deck): a 40-byte line must not
// be able to ask for gigabytes.
constexpr int64_t kMaxGenerateLine = 10'000'000;
constexpr int64_t kMaxSetEntries = 10'000'000;

struct Keyword {
  std::string name;                           // upper case, without '*'
  std::map<std::string, std::string> params;  // upper-case keys; values as written
};

// "*NSET, NSET=Left, GENERATE" -> {NSET, {NSET: Left, GENERATE: ""}}.
Keyword ParseKeyword(std::string_view line) {
  Keyword k;
  std::string_view rest = line.substr(1);
  size_t comma = rest.find(',');
  k.name = fe_text::Upper(fe_text::Trim(rest.substr(0, comma)));
  while (comma != std::string_view::npos) {
    rest = rest.substr(comma + 1);
    comma = rest.find(',');
    const std::string_view item = fe_text::Trim(rest.substr(0, comma));
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    const std::string key = fe_text::Upper(fe_text::Trim(item.substr(0, eq)));
    const std::string value = eq == std::string_view::npos
                                  ? std::string()
                                  : std::string(fe_text::Trim(item.substr(eq + 1)));
    k.params[key] = value;
  }
  return k;
}

struct DeckState {
  FeModel* model = nullptr;
  std::unordered_map<int64_t, size_t> node_index;     // id -> model->nodes index
  std::unordered_map<std::string, size_t> set_index;  // upper name -> model->node_sets index
  std::vector<std::unordered_set<int64_t>> set_members;
  // First place each set member was named, for the "undefined node" error at the end.
  std::vector<std::pair<std::string, size_t>> member_origin;  // parallel to set_index entries
  int64_t set_entries = 0;
  // The keyword block in force: *INCLUDE splices a file in place, so data lines of an included
  // file continue the block of the including one (and vice versa).
  enum class Block { kNone, kNode, kNset, kNsetGenerate, kElement, kSkip } block = Block::kNone;
  size_t current_set = 0;
  bool node_has_set = false;
  // *ELEMENT: type, node count it takes (0 = unknown: as given), the element being read (its data
  // may continue over lines), and where each element was defined, for the errors at the end.
  std::string element_type;
  size_t element_nodes = 0;
  bool element_open = false;
  size_t element_first_line_nodes = 0;
  std::unordered_map<int64_t, size_t> element_index;
  std::vector<std::string> files;
  std::vector<std::pair<size_t, size_t>> element_origin;  // (files index, line) per element
};

// Nodes an element type takes; 0 for types this reader does not know (kept as given).
size_t NodesPerElement(const std::string& type) {
  static const std::unordered_map<std::string, size_t> kCounts = {
      {"C3D4", 4},    {"C3D10", 10}, {"C3D8", 8},   {"C3D8R", 8}, {"C3D8I", 8}, {"C3D20", 20},
      {"C3D20R", 20}, {"C3D6", 6},   {"C3D15", 15}, {"S3", 3},    {"S4", 4},    {"S4R", 4}};
  const auto it = kCounts.find(type);
  return it == kCounts.end() ? 0 : it->second;
}

void StartElementBlock(DeckState& st, const Keyword& k, const std::string& path, size_t line) {
  const auto type = k.params.find("TYPE");
  if (type == k.params.end() || type->second.empty()) {
    Fail(path, line, "*ELEMENT without TYPE=<element type>");
  }
  st.element_type = fe_text::Upper(type->second);
  st.element_nodes = NodesPerElement(st.element_type);
  st.block = DeckState::Block::kElement;
}

// One data line under *ELEMENT: "id, n1, n2, ..." or the continuation of the element before
// (that line ended in a comma, or, Abaqus style, held 15 nodes of a type taking more).
void ElementLine(DeckState& st, std::string_view t, const std::vector<std::string_view>& tokens,
                 const std::string& path, size_t line) {
  std::vector<FeElement>& elements = st.model->elements;
  size_t first = 0;
  if (!st.element_open) {
    if (tokens.empty()) Fail(path, line, "expected 'element id, node ids' under *ELEMENT");
    FeElement e;
    e.id = fe_text::RequireInt(tokens[0], path, line, "an element id");
    if (e.id <= 0) Fail(path, line, "expected an element id > 0, got " + std::to_string(e.id));
    if (!st.element_index.emplace(e.id, elements.size()).second) {
      Fail(path, line, "element " + std::to_string(e.id) + " defined twice");
    }
    e.type = st.element_type;
    elements.push_back(std::move(e));
    if (st.files.empty() || st.files.back() != path) st.files.push_back(path);
    st.element_origin.emplace_back(st.files.size() - 1, line);
    st.element_open = true;
    first = 1;
  }
  FeElement& e = elements.back();
  for (size_t i = first; i < tokens.size(); ++i) {
    const int64_t n = fe_text::RequireInt(tokens[i], path, line, "a node id of an element");
    if (n <= 0) Fail(path, line, "expected a node id > 0, got " + std::to_string(n));
    e.nodes.push_back(n);
  }
  if (first == 1) st.element_first_line_nodes = e.nodes.size();
  const size_t want = st.element_nodes;
  const bool comma = t.back() == ',';
  const auto count_error = [&] {
    Fail(path, line,
         "element " + std::to_string(e.id) + " of type " + e.type + " has " +
             std::to_string(e.nodes.size()) + " node ids, expected " + std::to_string(want));
  };
  if (want == 0) {
    st.element_open = comma;
  } else if (e.nodes.size() > want) {
    count_error();
  } else if (e.nodes.size() == want) {
    st.element_open = false;
  } else if (!comma && !(first == 1 && e.nodes.size() == 15)) {
    count_error();
  }
}

size_t SetFor(DeckState& st, const std::string& name, const std::string& file, size_t line) {
  const std::string upper = fe_text::Upper(name);
  if (upper.empty()) Fail(file, line, "expected a set name after NSET=");
  auto it = st.set_index.find(upper);
  if (it != st.set_index.end()) return it->second;
  st.model->node_sets.push_back(NodeSet{upper, {}});
  st.set_members.emplace_back();
  st.member_origin.emplace_back(file, line);
  return st.set_index[upper] = st.model->node_sets.size() - 1;
}

void AddToSet(DeckState& st, size_t set, int64_t node, const std::string& file, size_t line) {
  if (st.set_members[set].insert(node).second) {
    st.model->node_sets[set].nodes.push_back(node);
    if (++st.set_entries > kMaxSetEntries) {
      Fail(file, line,
           "node sets hold more than " + std::to_string(kMaxSetEntries) +
               " entries in total (limit of this reader)");
    }
  }
}

void ReadDeck(const std::string& path, DeckState& st, int depth);

// *INCLUDE, INPUT=<file>: the file is read in place, relative to the including one; its errors
// name the line that included it.
void IncludeDeck(const Keyword& k, const std::string& path, size_t number, DeckState& st,
                 int depth) {
  const auto it = k.params.find("INPUT");
  if (it == k.params.end() || it->second.empty()) {
    Fail(path, number, "*INCLUDE without INPUT=<file>");
  }
  std::filesystem::path inc(it->second);
  if (inc.is_relative()) inc = std::filesystem::path(path).parent_path() / inc;
  try {
    ReadDeck(inc.string(), st, depth + 1);
  } catch (const FeReadError& e) {
    throw FeReadError(std::string(e.what()) + " (included from " + path + ":" +
                      std::to_string(number) + ")");
  }
}

void StartNodeBlock(DeckState& st, const Keyword& k, const std::string& path, size_t number) {
  const auto sys = k.params.find("SYSTEM");
  if (sys != k.params.end() && fe_text::Upper(sys->second) != "R") {
    Fail(path, number,
         "*NODE, SYSTEM=" + sys->second +
             " is not supported: expected rectangular coordinates (SYSTEM=R or none)");
  }
  if (k.params.count("INPUT")) {
    Fail(path, number, "*NODE, INPUT=<file> is not supported: use *INCLUDE, INPUT=<file>");
  }
  st.block = DeckState::Block::kNode;
  const auto nset = k.params.find("NSET");
  st.node_has_set = nset != k.params.end();
  if (st.node_has_set) st.current_set = SetFor(st, nset->second, path, number);
}

void StartNsetBlock(DeckState& st, const Keyword& k, const std::string& path, size_t number) {
  const auto nset = k.params.find("NSET");
  if (nset == k.params.end()) Fail(path, number, "*NSET without NSET=<name>");
  if (k.params.count("ELSET")) {
    Fail(path, number,
         "*NSET, ELSET=... (nodes of an element set) is not supported: list the nodes");
  }
  st.current_set = SetFor(st, nset->second, path, number);
  st.block = k.params.count("GENERATE") ? DeckState::Block::kNsetGenerate : DeckState::Block::kNset;
}

// A keyword line `t`: it ends the block in force and may start one of the blocks read here.
void KeywordLine(std::string_view t, const std::string& path, size_t number, DeckState& st,
                 int depth) {
  if (st.element_open) {
    Fail(path, number,
         "element " + std::to_string(st.model->elements.back().id) +
             " is not complete: its last data line ended in a comma, then a keyword came");
  }
  const Keyword k = ParseKeyword(t);
  if (k.name != "INCLUDE") st.block = DeckState::Block::kSkip;
  if (k.name == "INCLUDE") {
    IncludeDeck(k, path, number, st, depth);
  } else if (k.name == "NODE") {
    StartNodeBlock(st, k, path, number);
  } else if (k.name == "NSET") {
    StartNsetBlock(st, k, path, number);
  } else if (k.name == "ELEMENT") {
    StartElementBlock(st, k, path, number);
  }
}

// One data line under *NODE: "id, x[, y[, z]]".
void NodeLine(DeckState& st, std::string_view t, const std::vector<std::string_view>& tokens,
              const std::string& path, size_t number) {
  if (tokens.size() < 2 || tokens.size() > 4) {
    Fail(path, number, "expected 'node id, x[, y[, z]]' under *NODE, got " + fe_text::Printable(t));
  }
  FeNode node;
  node.id = fe_text::RequireInt(tokens[0], path, number, "a node id");
  if (node.id <= 0) Fail(path, number, "expected a node id > 0, got " + std::to_string(node.id));
  for (size_t c = 1; c < tokens.size(); ++c) {
    node.xyz[static_cast<int>(c - 1)] =
        fe_text::RequireReal(tokens[c], false, path, number, "a node coordinate [m]");
  }
  if (!st.node_index.emplace(node.id, st.model->nodes.size()).second) {
    Fail(path, number, "node " + std::to_string(node.id) + " defined twice");
  }
  st.model->nodes.push_back(node);
  if (st.node_has_set) AddToSet(st, st.current_set, node.id, path, number);
}

// One data line under *NSET, GENERATE: "first, last[, increment]".
void NsetGenerateLine(DeckState& st, std::string_view t,
                      const std::vector<std::string_view>& tokens, const std::string& path,
                      size_t number) {
  if (tokens.size() < 2 || tokens.size() > 3) {
    Fail(path, number,
         "expected 'first, last[, increment]' under *NSET, GENERATE, got " + fe_text::Printable(t));
  }
  const int64_t first = fe_text::RequireInt(tokens[0], path, number, "the first node id");
  const int64_t last = fe_text::RequireInt(tokens[1], path, number, "the last node id");
  const int64_t step =
      tokens.size() == 3 ? fe_text::RequireInt(tokens[2], path, number, "the increment") : 1;
  if (first <= 0 || last < first || step <= 0) {
    Fail(path, number,
         "expected 0 < first <= last and increment > 0 under *NSET, GENERATE, got " +
             fe_text::Printable(t));
  }
  const int64_t count = (last - first) / step + 1;  // no overflow: 0 < first <= last
  if (count > kMaxGenerateLine) {
    Fail(path, number,
         "*NSET, GENERATE range of " + std::to_string(count) + " nodes exceeds the limit of " +
             std::to_string(kMaxGenerateLine) + " per line");
  }
  for (int64_t k = 0; k < count; ++k) AddToSet(st, st.current_set, first + k * step, path, number);
}

// One data line under *NSET: node ids or names of sets defined before.
void NsetLine(DeckState& st, const std::vector<std::string_view>& tokens, const std::string& path,
              size_t number) {
  for (const std::string_view tok : tokens) {
    int64_t id = 0;
    if (fe_text::ParseInt(tok, id)) {
      if (id <= 0) Fail(path, number, "expected a node id > 0, got " + std::to_string(id));
      AddToSet(st, st.current_set, id, path, number);
      continue;
    }
    const auto it = st.set_index.find(fe_text::Upper(tok));
    if (it == st.set_index.end()) {
      Fail(path, number,
           "expected a node id or the name of a node set defined above, got " +
               fe_text::Printable(tok));
    }
    const std::vector<int64_t> members = st.model->node_sets[it->second].nodes;
    for (const int64_t n : members) AddToSet(st, st.current_set, n, path, number);
  }
}

void ReadDeck(const std::string& path, DeckState& st, int depth) {
  if (depth > kMaxIncludeDepth) {
    Fail(path, 0,
         "*INCLUDE nested deeper than " + std::to_string(kMaxIncludeDepth) +
             " levels (a file including itself?)");
  }
  const std::string text = fe_text::ReadWholeFile(path, "Abaqus/CalculiX input deck (.inp)");
  using Block = DeckState::Block;
  size_t pos = 0, number = 0;
  std::string_view line;
  std::vector<std::string_view> tokens;
  while (fe_text::NextLine(text, pos, line)) {
    ++number;
    const std::string_view t = fe_text::Trim(line);
    if (t.empty() || t.rfind("**", 0) == 0) continue;
    if (t.front() == '*') {
      KeywordLine(t, path, number, st, depth);
      continue;
    }
    if (st.block == Block::kNone || st.block == Block::kSkip) continue;
    fe_text::SplitTokens(t, tokens);
    if (st.block == Block::kElement) {
      ElementLine(st, t, tokens, path, number);
    } else if (st.block == Block::kNode) {
      NodeLine(st, t, tokens, path, number);
    } else if (st.block == Block::kNsetGenerate) {
      NsetGenerateLine(st, t, tokens, path, number);
    } else {
      NsetLine(st, tokens, path, number);
    }
  }
}

}  // namespace

void ReadInpNodesAndSets(const std::string& path, FeModel& model) {
  DeckState st;
  st.model = &model;
  for (size_t i = 0; i < model.nodes.size(); ++i) st.node_index.emplace(model.nodes[i].id, i);
  for (size_t i = 0; i < model.node_sets.size(); ++i) {
    st.set_index.emplace(fe_text::Upper(model.node_sets[i].name), i);
    st.set_members.emplace_back(model.node_sets[i].nodes.begin(), model.node_sets[i].nodes.end());
    st.member_origin.emplace_back(path, 0);
  }
  for (size_t i = 0; i < model.elements.size(); ++i) {
    st.element_index.emplace(model.elements[i].id, i);
  }
  const size_t first_new_element = model.elements.size();
  ReadDeck(path, st, 0);
  if (st.element_open) {
    const auto& [file, line] = st.element_origin.back();
    Fail(st.files[file], line,
         "element " + std::to_string(model.elements.back().id) +
             " is not complete: its last data line ends in a comma at the end of the deck");
  }
  // Every set member must be a defined node: a set naming an unknown node would silently drop
  // boundary DOFs later. A sets-only deck (no *NODE at all, e.g. `reduce --sets` beside matrices
  // whose DOF maps carry the nodes) is checked by its user against the matrix DOF map instead.
  const bool defines_nodes = !st.node_index.empty();
  for (size_t s = 0; defines_nodes && s < model.node_sets.size(); ++s) {
    for (const int64_t n : model.node_sets[s].nodes) {
      if (!st.node_index.count(n)) {
        Fail(st.member_origin[s].first, st.member_origin[s].second,
             "node set " + model.node_sets[s].name + " lists node " + std::to_string(n) +
                 ", which no *NODE block defines");
      }
    }
  }
  // Elements likewise (they may come before their nodes in the deck, so checked here).
  for (size_t i = first_new_element; defines_nodes && i < model.elements.size(); ++i) {
    for (const int64_t n : model.elements[i].nodes) {
      if (!st.node_index.count(n)) {
        const auto& [file, line] = st.element_origin[i - first_new_element];
        Fail(st.files[file], line,
             "element " + std::to_string(model.elements[i].id) + " lists node " +
                 std::to_string(n) + ", which no *NODE block defines");
      }
    }
  }
}

}  // namespace fricrom
