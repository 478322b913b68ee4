// Elements of Abaqus/CalculiX input decks (ReadInpNodesAndSets, *ELEMENT, TYPE=...): node counts
// per type, continuation lines (trailing comma; Abaqus's 15 nodes on the first line), *INCLUDE,
// types kept as given, the committed coarse meshes, and bad input named by file and line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace {

using fricrom::FeElement;
using fricrom::FeModel;
using fricrom::testing::ExpectError;
using fricrom::testing::ScratchDir;
using Ids = std::vector<int64_t>;

FeModel Read(const std::string& path) {
  FeModel model;
  fricrom::ReadInpNodesAndSets(path, model);
  return model;
}

// "*NODE" block with nodes 1..n on the x axis.
std::string Nodes(int n) {
  std::string s = "*NODE, NSET=NALL\n";
  for (int i = 1; i <= n; ++i) s += std::to_string(i) + ", " + std::to_string(i) + ".0, 0, 0\n";
  return s;
}

Ids Range(int64_t first, int64_t last) {
  Ids ids;
  for (int64_t i = first; i <= last; ++i) ids.push_back(i);
  return ids;
}

void ExpectElement(const FeElement& e, int64_t id, const std::string& type, const Ids& nodes) {
  EXPECT_EQ(e.id, id);
  EXPECT_EQ(e.type, type);
  EXPECT_EQ(e.nodes, nodes) << "element " << id;
}

TEST(InpElements, ReadsBlocksOfSeveralTypes) {
  ScratchDir dir;
  const std::string deck = Nodes(20) +
                           "** a comment\n"
                           "*ELEMENT, TYPE=C3D10, ELSET=BODY\n"
                           "1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10\n"
                           "2,4,3,2,1,10,9,8,7,6,5\n"
                           "*Element, type=c3d4\n"
                           "  7 , 1, 2, 3, 4\n"
                           "*ELEMENT, TYPE=S4\n"
                           "8, 5, 6, 7, 8\n"
                           "*NSET, NSET=FACE\n"
                           "1, 2, 3\n";
  const FeModel m = Read(dir.Write("deck.inp", deck));
  ASSERT_EQ(m.elements.size(), 4u);
  ExpectElement(m.elements[0], 1, "C3D10", Range(1, 10));
  ExpectElement(m.elements[1], 2, "C3D10", {4, 3, 2, 1, 10, 9, 8, 7, 6, 5});
  ExpectElement(m.elements[2], 7, "C3D4", {1, 2, 3, 4});
  ExpectElement(m.elements[3], 8, "S4", {5, 6, 7, 8});
  ASSERT_NE(m.FindNodeSet("FACE"), nullptr);  // blocks after the elements are still read
  EXPECT_EQ(m.FindNodeSet("FACE")->nodes, (Ids{1, 2, 3}));
  EXPECT_EQ(m.nodes.size(), 20u);
}

TEST(InpElements, ContinuationLines) {
  ScratchDir dir;
  const std::string deck = Nodes(20) +
                           "*ELEMENT, TYPE=C3D20R\n"
                           // CalculiX: a line ending in a comma continues.
                           "1, 1, 2, 3, 4, 5, 6, 7, 8,\n"
                           "9, 10, 11, 12, 13, 14, 15, 16,\n"
                           "17, 18, 19, 20\n"
                           // Abaqus: id and 15 nodes, the rest on the next line.
                           "2, 20, 19, 18, 17, 16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6\n"
                           "5, 4, 3, 2, 1\n"
                           "*ELEMENT, TYPE=C3D10\n"
                           "3, 1, 2, 3, 4, 5,\n"
                           "   6, 7, 8, 9, 10\n"
                           // A trailing comma on a complete element does not swallow the next.
                           "4, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,\n"
                           "5, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10\n"
                           // Unknown type: as given, continued by the comma only.
                           "*ELEMENT, TYPE=U7\n"
                           "6, 1, 2,\n"
                           "3\n"
                           "7, 4\n";
  const FeModel m = Read(dir.Write("deck.inp", deck));
  ASSERT_EQ(m.elements.size(), 7u);
  ExpectElement(m.elements[0], 1, "C3D20R", Range(1, 20));
  Ids down = Range(1, 20);
  std::reverse(down.begin(), down.end());
  ExpectElement(m.elements[1], 2, "C3D20R", down);
  ExpectElement(m.elements[2], 3, "C3D10", Range(1, 10));
  ExpectElement(m.elements[3], 4, "C3D10", Range(1, 10));
  ExpectElement(m.elements[4], 5, "C3D10", Range(1, 10));
  ExpectElement(m.elements[5], 6, "U7", {1, 2, 3});
  ExpectElement(m.elements[6], 7, "U7", {4});
}

TEST(InpElements, IncludedMeshAndElementsBeforeNodes) {
  ScratchDir dir;
  dir.Write("mesh.inp", "*ELEMENT, TYPE=C3D4, ELSET=E\n3, 4, 3, 2, 1\n" + Nodes(4));
  const FeModel m = Read(dir.Write("deck.inp", "*INCLUDE, INPUT=mesh.inp\n*STEP\n*END STEP\n"));
  ASSERT_EQ(m.elements.size(), 1u);
  ExpectElement(m.elements[0], 3, "C3D4", {4, 3, 2, 1});
}

TEST(InpElements, CoarseMeshesHoldTheirC3D10Elements) {
  const std::string dir = std::string(FRICROM_SOURCE_DIR) + "/meshes/";
  for (const auto& [file, nodes, elements] :
       {std::tuple{"blade_sector/coarse/blade_sector_mesh.inp", 1416u, 665u},
        std::tuple{"damper/coarse/damper_mesh.inp", 330u, 145u}}) {
    const FeModel m = Read(dir + file);
    EXPECT_EQ(m.nodes.size(), nodes) << file;
    ASSERT_EQ(m.elements.size(), elements) << file;
    for (const FeElement& e : m.elements) {
      EXPECT_EQ(e.type, "C3D10");
      EXPECT_EQ(e.nodes.size(), 10u);
    }
    EXPECT_EQ(m.elements.front().id, 1);
    EXPECT_EQ(m.elements.back().id, static_cast<int64_t>(elements));
  }
  // The damper's first element, as in the file.
  const FeModel d = Read(dir + "damper/coarse/damper_mesh.inp");
  ExpectElement(d.elements[0], 1, "C3D10", {50, 229, 103, 145, 244, 245, 246, 154, 248, 247});
}

TEST(InpElements, BadInputNamesFileAndLine) {
  ScratchDir dir;
  const std::string nodes = Nodes(10);  // lines 1..11
  const auto error = [&](const std::string& name, const std::string& tail, int line,
                         const std::string& what) {
    const std::string path = dir.Write(name, nodes + tail);
    ExpectError([&] { Read(path); }, path, line, what);
  };
  error("short.inp", "*ELEMENT, TYPE=C3D10\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9\n", 13,
        "element 1 of type C3D10 has 9 node ids, expected 10");
  error("long.inp", "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4, 5\n", 13,
        "element 1 of type C3D4 has 5 node ids, expected 4");
  error("long2.inp", "*ELEMENT, TYPE=C3D10\n1, 1, 2, 3, 4, 5,\n6, 7, 8, 9, 10, 1\n", 14,
        "has 11 node ids, expected 10");
  error("realid.inp", "*ELEMENT, TYPE=C3D4\n1.5, 1, 2, 3, 4\n", 13,
        "expected an element id (an integer), got '1.5'");
  error("realnode.inp", "*ELEMENT, TYPE=C3D4\n1, 1, 2, x3, 4\n", 13,
        "expected a node id of an element (an integer), got 'x3'");
  error("zero.inp", "*ELEMENT, TYPE=C3D4\n1, 1, 0, 3, 4\n", 13, "expected a node id > 0");
  error("twice.inp", "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=S3\n1, 1, 2, 3\n", 15,
        "element 1 defined twice");
  error("notype.inp", "*ELEMENT, ELSET=E\n1, 1, 2, 3, 4\n", 12, "*ELEMENT without TYPE=");
  error("undefined.inp", "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n2, 1, 2, 3, 44\n", 14,
        "element 2 lists node 44, which no *NODE block defines");
  error("dangling.inp", "*ELEMENT, TYPE=U2\n1, 1, 2,\n*STEP\n", 14, "element 1 is not complete");
  error("dangling_eof.inp", "*ELEMENT, TYPE=U2\n1, 1, 2,\n", 13, "element 1 is not complete");
}

}  // namespace
