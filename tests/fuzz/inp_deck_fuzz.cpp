// libFuzzer target for ReadInpNodesAndSets (Abaqus/CalculiX .inp decks: *NODE, *NSET, *INCLUDE).
// Not built by CMake. Build and run by hand, e.g.:
//   clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
//     -Iinclude -isystem /usr/include/eigen3 tests/fuzz/inp_deck_fuzz.cpp src/io/*.cpp \
//     -o inp_deck_fuzz
//   ./inp_deck_fuzz -max_total_time=30 CORPUS_DIR tests/data/calculix
// Input: the deck d.inp, optionally followed by "@@\n" and a file a.inp, then "@@\n" and a file
// b.inp, all in one directory, so that "*INCLUDE, INPUT=a.inp" (or b.inp, or d.inp itself) finds
// them (a missing part means a missing file).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "fricrom/fe_model.h"
#include "fuzz_util.h"

using namespace fricrom_fuzz;

namespace {

// Invariants of an accepted deck: positive, unique node ids with finite coordinates in the
// basic system; non-empty, upper-case, unique set names; set members unique and all defined.
void CheckDeck(const fricrom::FeModel& model) {
  CheckModel(model);
  Check(model.matrices.empty(), "no matrices from a deck");
  std::unordered_set<int64_t> ids;
  for (const fricrom::FeNode& n : model.nodes) {
    Check(n.id > 0, "node id > 0");
    Check(ids.insert(n.id).second, "unique node ids");
    Check(n.xyz.allFinite(), "finite coordinates");
    Check(n.position_system == 0 && n.displacement_system == 0, "basic system");
    Check(model.FindNode(n.id) == &n, "FindNode");
  }
  std::unordered_set<std::string> names;
  for (const fricrom::NodeSet& s : model.node_sets) {
    Check(!s.name.empty(), "set name not empty");
    for (const char c : s.name) Check(!(c >= 'a' && c <= 'z'), "set name upper case");
    Check(names.insert(s.name).second, "unique set names");
    Check(model.FindNodeSet(s.name) == &s, "FindNodeSet");
    std::unordered_set<int64_t> members;
    for (const int64_t n : s.nodes) {
      Check(members.insert(n).second, "set members unique");
      // A sets-only deck (no *NODE) is checked by its user against a matrix DOF map instead.
      Check(ids.empty() || ids.count(n) == 1, "set members are defined nodes");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<std::string_view> parts = Parts(data, size);
  const char* names[3] = {"/d.inp", "/a.inp", "/b.inp"};
  for (size_t i = 0; i < 3; ++i) {
    const std::string path = TempDir() + names[i];
    std::error_code ec;
    std::filesystem::remove(path, ec);
    if (i < parts.size()) WriteFile(path, parts[i]);
  }
  try {
    fricrom::FeModel model;
    fricrom::ReadInpNodesAndSets(TempDir() + names[0], model);
    CheckDeck(model);
  } catch (const fricrom::FeReadError&) {
  }
  return 0;
}
