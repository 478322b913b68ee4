// Abaqus/CalculiX input deck reader (ReadInpNodesAndSets): *NODE coordinates and *NSET node sets
// of the CalculiX fixture tests/data/calculix/twobricks.inp (also through ReadCalculix and ReadFe),
// hand-written decks for every supported form (GENERATE, NSET= on *NODE, set names in *NSET data,
// repeated blocks, case, comments, CRLF, *INCLUDE, skipped keywords), and bad input.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace {

namespace fs = std::filesystem;
using fricrom::FeMatrix;
using fricrom::FeModel;
using fricrom::FeNode;
using fricrom::NodeSet;
using fricrom::testing::ExpectError;
using fricrom::testing::ScratchDir;
using Ids = std::vector<int64_t>;

const std::string kTwoBricks = std::string(FRICROM_SOURCE_DIR) + "/tests/data/calculix/twobricks";

FeModel ReadDeck(const std::string& path) {
  FeModel model;
  fricrom::ReadInpNodesAndSets(path, model);
  return model;
}

// Members of set `name` (looked up case-insensitively); fails the test when the set is absent.
Ids Members(const FeModel& model, const std::string& name) {
  const NodeSet* s = model.FindNodeSet(name);
  EXPECT_NE(s, nullptr) << "no node set " << name;
  return s ? s->nodes : Ids{};
}

std::vector<std::string> SetNames(const FeModel& model) {
  std::vector<std::string> names;
  for (const NodeSet& s : model.node_sets) names.push_back(s.name);
  return names;
}

void ExpectNodeAt(const FeModel& model, int64_t id, double x, double y, double z) {
  const FeNode* n = model.FindNode(id);
  ASSERT_NE(n, nullptr) << "no node " << id;
  EXPECT_EQ(n->xyz, Eigen::Vector3d(x, y, z)) << "node " << id;
  EXPECT_EQ(n->position_system, 0);
  EXPECT_EQ(n->displacement_system, 0);
}

// twobricks.inp: nodes 1..12 on x in {0,1,2}, y in {0,1}, z in {0,1} (x fastest), all in NALL;
// FIXED = the x = 0 face.
void ExpectTwoBricksMesh(const FeModel& model) {
  ASSERT_EQ(model.nodes.size(), 12u);
  int64_t id = 1;
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) {
        EXPECT_EQ(model.nodes[static_cast<size_t>(id - 1)].id, id);
        ExpectNodeAt(model, id++, x, y, z);
      }
    }
  }
  EXPECT_EQ(model.FindNode(13), nullptr);
  EXPECT_EQ(model.FindNode(0), nullptr);
  EXPECT_EQ(Members(model, "NALL"), (Ids{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}));
  EXPECT_EQ(Members(model, "FIXED"), (Ids{1, 4, 7, 10}));
  EXPECT_NE(model.FindNodeSet("fixed"), nullptr);
  EXPECT_NE(model.FindNodeSet("Nall"), nullptr);
  EXPECT_EQ(model.FindNodeSet("EALL"), nullptr);  // an element set, not a node set
}

// ---------------------------------------------------------------------------------------------
// The CalculiX fixture.

TEST(InpDeck, TwoBricksNodesAndSets) {
  const FeModel model = ReadDeck(kTwoBricks + ".inp");
  ExpectTwoBricksMesh(model);
  EXPECT_EQ(SetNames(model), (std::vector<std::string>{"NALL", "FIXED"}));
  EXPECT_TRUE(model.matrices.empty());
}

TEST(InpDeck, ReadCalculixAlsoReadsTheDeck) {
  const FeModel model = fricrom::ReadCalculix(kTwoBricks);
  EXPECT_EQ(model.format, "calculix");
  EXPECT_EQ(model.matrices.size(), 2u);
  ExpectTwoBricksMesh(model);
  EXPECT_NE(model.source.find("twobricks.inp"), std::string::npos) << model.source;
  // The clamped set is exactly the nodes missing from the .dof map.
  const FeMatrix* k = model.Find("STIFFNESS");
  ASSERT_NE(k, nullptr);
  for (const int64_t n : Members(model, "FIXED")) {
    for (const fricrom::DofId& d : k->row_dofs) EXPECT_NE(d.node, n);
  }
}

TEST(InpDeck, ReadFeOnTheDeckReadsTheMatricesBesideIt) {
  const FeModel from_inp = fricrom::ReadFe(kTwoBricks + ".inp");
  const FeModel from_sti = fricrom::ReadFe(kTwoBricks + ".sti");
  EXPECT_EQ(from_inp.format, "calculix");
  ASSERT_EQ(from_inp.matrices.size(), 2u);
  ASSERT_EQ(from_sti.matrices.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const FeMatrix& a = from_inp.matrices[i];
    const FeMatrix& b = from_sti.matrices[i];
    EXPECT_EQ(a.name, b.name);
    ASSERT_EQ(a.rows, b.rows);
    ASSERT_EQ(a.cols, b.cols);
    EXPECT_EQ(a.row_dofs, b.row_dofs);
    EXPECT_EQ(a.col_dofs, b.col_dofs);
    EXPECT_EQ(a.real.nonZeros(), b.real.nonZeros());
    EXPECT_EQ((Eigen::MatrixXd(a.real) - Eigen::MatrixXd(b.real)).cwiseAbs().maxCoeff(), 0.0)
        << a.name;
  }
  ExpectTwoBricksMesh(from_inp);
  ExpectTwoBricksMesh(from_sti);  // the deck beside the .sti is read too
}

// ---------------------------------------------------------------------------------------------
// Hand-written decks.

const char* const kTenNodes =
    "*NODE\n"
    "1, 0, 0, 0\n2, 1, 0, 0\n3, 2, 0, 0\n4, 3, 0, 0\n5, 4, 0, 0\n"
    "6, 5, 0, 0\n7, 6, 0, 0\n8, 7, 0, 0\n9, 8, 0, 0\n10, 9, 0, 0\n";

TEST(InpDeck, NsetGenerate) {
  ScratchDir dir;
  const FeModel model =
      ReadDeck(dir.Write("g.inp", std::string(kTenNodes) + "*NSET, NSET=ODD, GENERATE\n"
                                                           "1, 9, 2\n"
                                                           "*NSET, NSET=RANGE, GENERATE\n"
                                                           " 4, 6\n"
                                                           "*NSET, NSET=STRIDE, GENERATE\n"
                                                           "1, 8, 3\n"
                                                           "10, 10, 5\n"
                                                           "*NSET, NSET=PLAIN\n"
                                                           "1, 9, 2\n"));
  EXPECT_EQ(Members(model, "ODD"), (Ids{1, 3, 5, 7, 9}));
  EXPECT_EQ(Members(model, "RANGE"), (Ids{4, 5, 6}));       // increment 1 by default
  EXPECT_EQ(Members(model, "STRIDE"), (Ids{1, 4, 7, 10}));  // last not on the stride
  EXPECT_EQ(Members(model, "PLAIN"), (Ids{1, 9, 2}));       // without GENERATE: a list
  EXPECT_EQ(model.nodes.size(), 10u);
}

TEST(InpDeck, NsetOnNodeKeyword) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("n.inp",
                                           "*NODE, NSET=A\n"
                                           "1, 0, 0, 0\n"
                                           "2, 1, 0, 0\n"
                                           "*NODE\n"  // no set: must not extend A
                                           "3, 2, 0, 0\n"
                                           "*NODE, NSET=B\n"
                                           "4, 3, 0, 0\n"
                                           "*NODE, NSET=A\n"  // A again: appended
                                           "5, 4, 0, 0\n"));
  EXPECT_EQ(model.nodes.size(), 5u);
  EXPECT_EQ(Members(model, "A"), (Ids{1, 2, 5}));
  EXPECT_EQ(Members(model, "B"), (Ids{4}));
  EXPECT_EQ(SetNames(model), (std::vector<std::string>{"A", "B"}));
}

TEST(InpDeck, SetNamesInsideNsetData) {
  ScratchDir dir;
  const FeModel model =
      ReadDeck(dir.Write("s.inp", std::string(kTenNodes) + "*NSET, NSET=LEFT\n"
                                                           "1, 2\n"
                                                           "*NSET, NSET=RIGHT, GENERATE\n"
                                                           "8, 10\n"
                                                           "*NSET, NSET=BOTH\n"
                                                           "left, 5, Right\n"
                                                           "2, LEFT\n"  // repeats dropped
                                                           "*NSET, NSET=NESTED\n"
                                                           "BOTH, 3\n"));
  EXPECT_EQ(Members(model, "BOTH"), (Ids{1, 2, 5, 8, 9, 10}));
  EXPECT_EQ(Members(model, "NESTED"), (Ids{1, 2, 5, 8, 9, 10, 3}));
  EXPECT_EQ(Members(model, "LEFT"), (Ids{1, 2}));  // unchanged by being referenced
}

TEST(InpDeck, RepeatedNsetBlocksAppendWithoutRepeats) {
  ScratchDir dir;
  const FeModel model =
      ReadDeck(dir.Write("r.inp", std::string(kTenNodes) + "*NSET, NSET=A\n"
                                                           "5, 3, 5\n"
                                                           "*NSET, NSET=B\n"
                                                           "7\n"
                                                           "*NSET, NSET=a\n"
                                                           "3, 1\n"
                                                           "*NSET, NSET=A, GENERATE\n"
                                                           "1, 4\n"
                                                           "*NSET, NSET=A\n"
                                                           "A, 6\n"));  // itself: no change
  EXPECT_EQ(Members(model, "A"), (Ids{5, 3, 1, 2, 4, 6}));  // deck order, first occurrence
  EXPECT_EQ(SetNames(model), (std::vector<std::string>{"A", "B"}));
}

TEST(InpDeck, CaseInsensitiveKeywordsAndSetNames) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("c.inp",
                                           "*node, nset=Left\n"
                                           "1, 0, 0, 0\n"
                                           "2, 1, 0, 0\n"
                                           "*Nset, Nset=mixedCase, Generate\n"
                                           "1, 2\n"
                                           "*NsEt,NSET = Both \n"
                                           "LEFT, MixedCASE\n"
                                           "*Node, System=r\n"
                                           "3, 2, 0, 0\n"));
  EXPECT_EQ(SetNames(model), (std::vector<std::string>{"LEFT", "MIXEDCASE", "BOTH"}));
  EXPECT_EQ(Members(model, "left"), (Ids{1, 2}));
  EXPECT_EQ(Members(model, "MixedCase"), (Ids{1, 2}));
  EXPECT_EQ(Members(model, "both"), (Ids{1, 2}));
  EXPECT_EQ(model.FindNodeSet("nope"), nullptr);
  ExpectNodeAt(model, 3, 2, 0, 0);
}

TEST(InpDeck, CommentsBlankLinesCrlfAndTabs) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("k.inp",
                                           "** header comment\r\n"
                                           "\r\n"
                                           "*NODE, NSET=N\r\n"
                                           "1, 0.5, 0., 0.\r\n"
                                           "** a comment inside the block, *NODE, 99, 1, 2, 3\r\n"
                                           "   \r\n"
                                           "\t2,\t1.5 ,\t2.5,3.5\r\n"
                                           "  3 4.0 5.0 6.0\r\n"  // blank-separated
                                           "\r\n"
                                           "   ** indented comment\r\n"
                                           "*NSET, NSET=S\r\n"
                                           "3, 1,\r\n"  // trailing comma
                                           "**\r\n"
                                           "2\r\n"));  // no line break at the end
  ASSERT_EQ(model.nodes.size(), 3u);
  ExpectNodeAt(model, 1, 0.5, 0, 0);
  ExpectNodeAt(model, 2, 1.5, 2.5, 3.5);
  ExpectNodeAt(model, 3, 4, 5, 6);
  EXPECT_EQ(model.FindNode(99), nullptr);
  EXPECT_EQ(Members(model, "N"), (Ids{1, 2, 3}));
  EXPECT_EQ(Members(model, "S"), (Ids{3, 1, 2}));
}

TEST(InpDeck, NodesWithFewerCoordinatesAndExponents) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("2d.inp",
                                           "*NODE\n"
                                           "1, 1.5, 2.5\n"
                                           "2, -3.0\n"
                                           "3, 1.5e-3, -2.E+1, +4\n"
                                           "100000000000, 1, 2, 3\n"));  // 64-bit id
  ExpectNodeAt(model, 1, 1.5, 2.5, 0);
  ExpectNodeAt(model, 2, -3, 0, 0);
  ExpectNodeAt(model, 3, 1.5e-3, -20, 4);
  ExpectNodeAt(model, 100000000000, 1, 2, 3);
}

TEST(InpDeck, IncludeRelativeToTheIncludingFile) {
  ScratchDir dir;
  fs::create_directories(dir.path() / "mesh");
  // A same-named file beside the top deck must not be taken for mesh/sets.inp.
  dir.Write("sets.inp", "*NSET, NSET=WRONG\n1\n");
  dir.Write("mesh/nodes.inp",
            "*NODE, NSET=NALL\n"
            "1, 0, 0, 0\n"
            "2, 1, 0, 0\n"
            "*INCLUDE, INPUT=sets.inp\n"
            "*NODE, NSET=NALL\n"  // the included file continues after its own *INCLUDE
            "3, 2, 0, 0\n");
  dir.Write("mesh/sets.inp", "*NSET, NSET=FIXED\n1\n");
  const std::string top = dir.Write("job.inp",
                                    "*HEADING\n"
                                    "job\n"
                                    "*Include, Input=mesh/nodes.inp\n"
                                    "*NSET, NSET=ALL2\n"  // the top deck continues after it
                                    "NALL, FIXED\n");
  const FeModel model = ReadDeck(top);
  EXPECT_EQ(model.nodes.size(), 3u);
  ExpectNodeAt(model, 3, 2, 0, 0);
  EXPECT_EQ(Members(model, "NALL"), (Ids{1, 2, 3}));
  EXPECT_EQ(Members(model, "FIXED"), (Ids{1}));
  EXPECT_EQ(Members(model, "ALL2"), (Ids{1, 2, 3}));
  EXPECT_EQ(model.FindNodeSet("WRONG"), nullptr);
  // The same file included by absolute path.
  const std::string abs_top =
      dir.Write("abs.inp", "*INCLUDE, INPUT=" + (dir.path() / "mesh/nodes.inp").string() + "\n");
  EXPECT_EQ(ReadDeck(abs_top).nodes.size(), 3u);
}

TEST(InpDeck, OtherKeywordBlocksAreSkipped) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("full.inp",
                                           "*HEADING\n"
                                           "Model: bracket, 2 parts\n"
                                           "*NODE, NSET=NALL\n"
                                           "1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n"
                                           "5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, 1\n"
                                           "*ELEMENT, TYPE=C3D8, ELSET=EALL\n"
                                           "1, 1, 2, 3, 4, 5, 6, 7, 8\n"
                                           "*ELSET, ELSET=E2\n"
                                           "1, 2\n"
                                           "*MATERIAL, NAME=STEEL\n"
                                           "*ELASTIC\n"
                                           "210000., 0.3\n"
                                           "*DENSITY\n"
                                           "7.8E-9\n"
                                           "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
                                           "*BOUNDARY\n"
                                           "NALL, 1, 3\n"
                                           "*STEP\n"
                                           "*STATIC\n"
                                           "*CLOAD\n"
                                           "7, 3, -1.0\n"
                                           "*NODE PRINT, NSET=NALL\n"
                                           "U\n"
                                           "*NODE FILE, NSET=OUT\n"
                                           "U, RF\n"
                                           "*END STEP\n"));
  EXPECT_EQ(model.nodes.size(), 8u);
  ExpectNodeAt(model, 7, 1, 1, 1);
  EXPECT_EQ(SetNames(model), (std::vector<std::string>{"NALL"}));
  EXPECT_EQ(Members(model, "NALL").size(), 8u);
}

TEST(InpDeck, SetsMayListNodesDefinedFurtherDown) {
  ScratchDir dir;
  const FeModel model = ReadDeck(dir.Write("fwd.inp",
                                           "*NSET, NSET=TIP\n"
                                           "2\n"
                                           "*NODE\n"
                                           "1, 0, 0, 0\n"
                                           "2, 1, 0, 0\n"));
  EXPECT_EQ(Members(model, "TIP"), (Ids{2}));
}

TEST(InpDeck, AppendsToTheGivenModel) {
  ScratchDir dir;
  FeModel model;
  model.nodes.push_back(FeNode{100, Eigen::Vector3d(1, 2, 3), 0, 0});
  model.node_sets.push_back(NodeSet{"PRE", {100}});
  fricrom::ReadInpNodesAndSets(dir.Write("more.inp",
                                         "*NODE\n"
                                         "1, 0, 0, 0\n"
                                         "*NSET, NSET=ALL\n"
                                         "pre, 1\n"
                                         "*NSET, NSET=Pre\n"
                                         "1\n"),
                               model);
  ASSERT_EQ(model.nodes.size(), 2u);
  ExpectNodeAt(model, 100, 1, 2, 3);
  EXPECT_EQ(Members(model, "ALL"), (Ids{100, 1}));
  EXPECT_EQ(Members(model, "PRE"), (Ids{100, 1}));
  EXPECT_EQ(model.node_sets.size(), 2u);

  FeModel again = model;
  ExpectError(
      [&] { fricrom::ReadInpNodesAndSets(dir.Write("dup.inp", "*NODE\n100, 0, 0, 0\n"), again); },
      dir.Path("dup.inp"), 2, "node 100 defined twice");
}

TEST(InpDeck, EmptyDeckAndEmptySet) {
  ScratchDir dir;
  EXPECT_TRUE(ReadDeck(dir.Write("empty.inp", "")).nodes.empty());
  const FeModel model = ReadDeck(dir.Write("e.inp", "*NSET, NSET=NONE\n*NODE\n1, 0, 0, 0\n"));
  ASSERT_NE(model.FindNodeSet("NONE"), nullptr);
  EXPECT_TRUE(model.FindNodeSet("NONE")->nodes.empty());
}

// ---------------------------------------------------------------------------------------------
// Bad input: FeReadError naming the file and (where there is one) the line.

void ExpectDeckError(const std::string& text, int line, const std::string& what) {
  ScratchDir dir;
  const std::string path = dir.Write("bad.inp", text);
  ExpectError([&] { ReadDeck(path); }, path, line, what);
}

TEST(InpDeckErrors, NodeDefinedTwice) {
  ExpectDeckError("*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*NODE, NSET=X\n1, 5, 5, 5\n", 5,
                  "node 1 defined twice");
  // Across files: the line of the included file.
  ScratchDir dir;
  const std::string inc = dir.Write("inc.inp", "** nodes again\n*NODE\n3, 0, 0, 0\n");
  const std::string top = dir.Write("top.inp", "*NODE\n3, 0, 0, 0\n*INCLUDE, INPUT=inc.inp\n");
  ExpectError([&] { ReadDeck(top); }, inc, 3, "node 3 defined twice");
}

TEST(InpDeckErrors, NsetWithoutName) {
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*NSET\n1\n", 3, "*NSET without NSET=");
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*NSET, GENERATE\n1, 1\n", 3, "*NSET without NSET=");
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*NSET, NSET=\n1\n", 3, "expected a set name");
  ExpectDeckError("*NODE, NSET= \n1, 0, 0, 0\n", 1, "expected a set name");
}

TEST(InpDeckErrors, IncludeWithoutInput) {
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*INCLUDE\n", 3, "*INCLUDE without INPUT=");
  ExpectDeckError("*INCLUDE, INPUT=\n", 1, "*INCLUDE without INPUT=");
  ExpectDeckError("*INCLUDE, FILE=a.inp\n", 1, "*INCLUDE without INPUT=");
}

TEST(InpDeckErrors, IncludedFileMissing) {
  ScratchDir dir;
  const std::string top = dir.Write("top.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=sub/none.inp\n");
  ExpectError([&] { ReadDeck(top); }, dir.Path("sub/none.inp"), 0, "no such file");
  ExpectError([&] { ReadDeck(dir.Path("absent.inp")); }, dir.Path("absent.inp"), 0, "no such file");
  fs::create_directories(dir.path() / "folder");
  ExpectError([&] { ReadDeck(dir.Path("folder")); }, dir.Path("folder"), 0, "got a directory");
}

TEST(InpDeckErrors, IncludeRecursion) {
  ScratchDir dir;
  // Nothing but the *INCLUDE, so that only the depth limit can stop the reading.
  const std::string loop = dir.Write("loop.inp", "*INCLUDE, INPUT=loop.inp\n");
  ExpectError([&] { ReadDeck(loop); }, loop, 0, "nested deeper");
  // a -> b -> a
  dir.Write("a.inp", "*INCLUDE, INPUT=b.inp\n");
  dir.Write("b.inp", "** b\n*INCLUDE, INPUT=a.inp\n");
  ExpectError([&] { ReadDeck(dir.Path("a.inp")); }, dir.path().string(), 0, "nested deeper");
  // With a node before the *INCLUDE, the second reading of the file stops at the repeated node.
  const std::string self = dir.Write("self.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=self.inp\n");
  ExpectError([&] { ReadDeck(self); }, self, 2, "node 1 defined twice");
}

TEST(InpDeckErrors, BadNodeLine) {
  ExpectDeckError("*NODE\n1, 0., 0., 0.\n2, 0., abc, 0.\n", 3, "a node coordinate");
  ExpectDeckError("*NODE\n1, 0., nan, 0.\n", 2, "finite real number");
  ExpectDeckError("*NODE\n1, 0., 1e999, 0.\n", 2, "finite real number");
  ExpectDeckError("*NODE\n1, 0., 0., 0., 0.\n", 2, "expected 'node id, x[, y[, z]]'");
  ExpectDeckError("** only an id\n*NODE\n7\n", 3, "expected 'node id, x[, y[, z]]'");
  ExpectDeckError("*NODE\n1.5, 0., 0., 0.\n", 2, "a node id");
  ExpectDeckError("*NODE\nA, 0., 0., 0.\n", 2, "a node id");
}

TEST(InpDeckErrors, NodeIdNotPositive) {
  ExpectDeckError("*NODE\n0, 0., 0., 0.\n", 2, "node id > 0");
  ExpectDeckError("*NODE\n1, 0., 0., 0.\n-5, 0., 0., 0.\n", 3, "node id > 0");
  ExpectDeckError("*NODE\n1, 0., 0., 0.\n*NSET, NSET=S\n1, -1\n", 4, "node id > 0");
  ExpectDeckError("*NODE\n1, 0., 0., 0.\n*NSET, NSET=S\n1, 0\n", 4, "node id > 0");
}

TEST(InpDeckErrors, BadGenerate) {
  const std::string nodes = kTenNodes;
  const int l = 13;  // the GENERATE data line (kTenNodes is 11 lines)
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n9, 1\n", l, "0 < first <= last");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n1, 9, 0\n", l, "increment > 0");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n1, 9, -2\n", l, "increment > 0");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n0, 9\n", l, "0 < first");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n5\n", l, "'first, last[, increment]'");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n1, 2, 1, 1\n", l, "'first, last[, increment]'");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n1, X\n", l, "the last node id");
  ExpectDeckError(nodes + "*NSET, NSET=G, GENERATE\n1, 1000000000000\n", l, "exceeds the limit");
}

// `last` near INT64_MAX once made `n += step` overflow (UB; a near-endless loop in practice).
TEST(InpDeckErrors, GenerateNearInt64MaxDoesNotOverflow) {
  // One generated id (no overflow in the loop), which no *NODE defines.
  ExpectDeckError(
      "*NODE\n1, 0, 0, 0\n*NSET, NSET=G, GENERATE\n9223372036854775806, 9223372036854775807, 10\n",
      0, "lists node 9223372036854775806");
}

TEST(InpDeck, IncludedDataLinesContinueTheIncludingBlock) {
  // *INCLUDE splices the file in place (Abaqus semantics): data-only files continue the block.
  ScratchDir dir;
  dir.Write("data.inp", "1, 0, 0, 0\n2, 1, 0, 0\n");
  const std::string top = dir.Write(
      "top.inp", "*NODE, NSET=N\n*INCLUDE, INPUT=data.inp\n3, 2, 0, 0\n*NSET, NSET=S\n1\n");
  fricrom::FeModel model;
  fricrom::ReadInpNodesAndSets(top, model);
  ASSERT_EQ(model.nodes.size(), 3u);
  ASSERT_NE(model.FindNodeSet("N"), nullptr);
  EXPECT_EQ(model.FindNodeSet("N")->nodes, (std::vector<int64_t>{1, 2, 3}));
}

TEST(InpDeckErrors, ErrorsInIncludedFilesNameTheIncludingLine) {
  ScratchDir dir;
  const std::string top = dir.Write("top.inp", "** header\n*INCLUDE, INPUT=missing.inp\n");
  ExpectError(
      [&] {
        fricrom::FeModel model;
        fricrom::ReadInpNodesAndSets(top, model);
      },
      "missing.inp", 0, "(included from " + top + ":2)");
}

TEST(InpDeckErrors, HugeGenerateRangesAreRefusedBeforeAllocating) {
  ExpectDeckError("*NSET, NSET=A, GENERATE\n1, 100000000\n", 2, "exceeds the limit of 10000000");
}

TEST(InpDeckErrors, NodesOfAnElementSetAndNodeInputAreRefused) {
  // Named, not std::string(kTenNodes) + "...": there GCC 12 warns falsely (-Warray-bounds).
  const std::string nodes = kTenNodes;
  ExpectDeckError(nodes + "*NSET, NSET=X, ELSET=E\n", 12, "ELSET");
  ExpectDeckError("*NODE, INPUT=nodes.txt\n", 1, "*INCLUDE");
}

TEST(InpDeckErrors, UndefinedSetReference) {
  const std::string nodes = kTenNodes;
  ExpectDeckError(nodes + "*NSET, NSET=A\n1, 2\n*NSET, NSET=B\nA, MISSING\n", 15,
                  "node set defined above, got 'MISSING'");
  // Defined only further down: still an error (sets must be defined before use).
  ExpectDeckError(nodes + "*NSET, NSET=B\nLATER\n*NSET, NSET=LATER\n1\n", 13,
                  "node set defined above");
  // An element set is not a node set.
  ExpectDeckError(nodes + "*ELSET, ELSET=E\n1\n*NSET, NSET=B\nE\n", 15, "node set defined above");
}

TEST(InpDeckErrors, SetListsUndefinedNode) {
  // Reported at the first line that names the set.
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*NSET, NSET=Tip\n1, 7\n", 3,
                  "node set TIP lists node 7, which no *NODE block defines");
  ExpectDeckError("*NODE\n1, 0, 0, 0\n2, 0, 0, 0\n*NSET, NSET=G, GENERATE\n1, 3\n", 4,
                  "node set G lists node 3");
  ExpectDeckError("*NSET, NSET=S\n1\n*NODE\n2, 0, 0, 0\n", 1, "node set S lists node 1");
}

TEST(InpDeckErrors, CylindricalSystemUnsupported) {
  ExpectDeckError("*NODE\n1, 0, 0, 0\n*NODE, SYSTEM=C\n2, 1, 90, 0\n", 3,
                  "SYSTEM=C is not supported");
  ExpectDeckError("*node, system=s\n2, 1, 90, 0\n", 1, "SYSTEM=s is not supported");
}

TEST(InpDeckErrors, ReadCalculixReportsDeckErrors) {
  ScratchDir dir;
  dir.Write("k.dof", "1.1\n");
  dir.Write("k.sti", "1 1 2.0\n");
  const std::string deck = dir.Write("k.inp", "*NODE\n1, 0, 0, 0\n1, 0, 0, 0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, deck, 3, "defined twice");
  ExpectError([&] { fricrom::ReadFe(deck); }, deck, 3, "defined twice");
}

}  // namespace
