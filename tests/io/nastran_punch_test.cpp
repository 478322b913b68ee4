// Nastran punch / bulk data reader (ReadNastranPunch): the real DMIG punch sample checked against
// an independent column-based reading of its text, the EXTSEOUT punch (EXTRN order, GRID, CORD2R)
// with the superelement matrices of its OUTPUT4 file, hand-made decks for every field format,
// and one test per kind of bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace {

namespace fs = std::filesystem;
using fricrom::DofId;
using fricrom::FeMatrix;
using fricrom::FeModel;
using fricrom::FeReadError;
using fricrom::testing::ExpectError;

const std::string kFixtures = std::string(FRICROM_SOURCE_DIR) + "/tests/data/";

using TempDir = fricrom::testing::ScratchDir;

int64_t IndexOf(const std::vector<DofId>& dofs, int64_t node, int component) {
  for (size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i].node == node && dofs[i].component == component) return static_cast<int64_t>(i);
  }
  return -1;
}

double At(const FeMatrix& m, int64_t r, int64_t c) {
  return m.real.coeff(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
}

// Value at (row DOF, column DOF); the column may be a plain column number (IFO 9).
double At(const FeMatrix& m, DofId row, DofId col) {
  const int64_t r = IndexOf(m.row_dofs, row.node, row.component);
  const int64_t c =
      m.col_dofs.empty() ? col.node - 1 : IndexOf(m.col_dofs, col.node, col.component);
  EXPECT_GE(r, 0) << m.name << " has no row " << row.node << "." << row.component;
  EXPECT_GE(c, 0) << m.name << " has no column " << col.node << "." << col.component;
  return (r < 0 || c < 0) ? std::nan("") : At(m, r, c);
}

// ---- The real DMIG punch (pyNastran sample): IFO 6 and 9, large field, D exponents ------------

// Independent reading of the sample by fixed columns: header cards `DMIG    NAME  0 IFO ...`,
// large-field column cards `DMIG*   NAME  GJ  CJ` and their `*  GI  CI  VALUE` lines.
struct TextEntry {
  std::string name;
  DofId row, col;
  double value;
};
std::vector<TextEntry> ReadDmigByColumns(const std::string& path, std::map<std::string, int>& ifo) {
  std::ifstream in(path);
  std::string line, name;
  DofId col;
  std::vector<TextEntry> out;
  const auto field16 = [&](size_t i) { return line.substr(8 + 16 * i, 16); };
  while (std::getline(in, line)) {
    line.resize(std::max<size_t>(line.size(), 72), ' ');
    if (line.rfind("DMIG    ", 0) == 0) {
      std::istringstream s(line.substr(8));
      std::string n;
      int zero, form;
      s >> n >> zero >> form;
      ifo[n] = form;
      name.clear();
    } else if (line.rfind("DMIG*", 0) == 0) {
      std::istringstream s(field16(0));
      s >> name;
      col = DofId{std::stoll(field16(1)), std::stoi(field16(2))};
    } else if (line[0] == '*' && !name.empty()) {
      std::string v = field16(2);
      for (char& c : v) {
        if (c == 'D') c = 'E';
      }
      out.push_back({name, DofId{std::stoll(field16(0)), std::stoi(field16(1))}, col,
                     std::strtod(v.c_str(), nullptr)});
    } else {
      name.clear();
    }
  }
  return out;
}

TEST(NastranPunch, DmigSampleMatchesItsTextEntryByEntry) {
  const std::string path = kFixtures + "dmig/dmig.pch";
  const FeModel model = fricrom::ReadNastranPunch(path);
  EXPECT_EQ(model.format, "dmig");
  std::map<std::string, int> ifo;
  const std::vector<TextEntry> text = ReadDmigByColumns(path, ifo);
  ASSERT_EQ(text.size(), 29u + 15u + 6u + 15u + 4u + 15u);  // KAAX MAAX BAAX VAX RVA MUG1T lines
  std::map<std::string, int64_t> expected_nnz;
  for (const TextEntry& e : text) {
    const FeMatrix* m = model.Find(e.name);
    ASSERT_NE(m, nullptr) << e.name;
    EXPECT_EQ(At(*m, e.row, e.col), e.value) << e.name << " " << e.row.node << " " << e.col.node;
    const bool sym = ifo[e.name] == 6;
    if (sym) {
      EXPECT_EQ(At(*m, e.col, e.row), e.value) << e.name << " (transpose)";
    }
    expected_nnz[e.name] += (sym && !(e.row == e.col)) ? 2 : 1;
  }
  ASSERT_EQ(model.matrices.size(), 6u);
  for (const FeMatrix& m : model.matrices) {
    EXPECT_EQ(m.real.nonZeros(), expected_nnz[m.name]) << m.name;
    EXPECT_EQ(m.symmetric, ifo[m.name] == 6) << m.name;
    EXPECT_FALSE(m.is_complex);
    EXPECT_EQ(m.source_precision_bits, 64);
    EXPECT_EQ(static_cast<int64_t>(m.row_dofs.size()), m.rows);
  }
}

TEST(NastranPunch, DmigSampleShapesDofOrderAndKnownTerms) {
  const FeModel model = fricrom::ReadNastranPunch(kFixtures + "dmig/dmig.pch");
  const FeMatrix* k = model.Find("kaax");  // case-insensitive
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(model.Find("KaaX"), k);
  EXPECT_EQ(model.Find("KAAXX"), nullptr);
  EXPECT_EQ(k->rows, 15);
  EXPECT_EQ(k->cols, 15);
  EXPECT_TRUE(k->symmetric);
  // DOF order: sorted (id, component), the 15 grids in the file.
  const std::vector<int64_t> grids = {101, 102, 105, 106, 107, 108, 109, 201,
                                      301, 302, 305, 306, 307, 308, 309};
  ASSERT_EQ(k->row_dofs.size(), grids.size());
  for (size_t i = 0; i < grids.size(); ++i) {
    EXPECT_EQ(k->row_dofs[i], (DofId{grids[i], 1}));
  }
  EXPECT_EQ(k->col_dofs, k->row_dofs);
  // Terms read off the file text (1.556000000D+02 etc.), both triangles after expansion.
  EXPECT_EQ(At(*k, {101, 1}, {101, 1}), 155.6);
  EXPECT_EQ(At(*k, {101, 1}, {102, 1}), -155.6);
  EXPECT_EQ(At(*k, {102, 1}, {101, 1}), -155.6);
  EXPECT_EQ(At(*k, {105, 1}, {108, 1}), -2728.2);
  EXPECT_EQ(At(*k, {201, 1}, {308, 1}), -186.9);
  EXPECT_EQ(At(*k, {101, 1}, {309, 1}), 0.0);
  // Symmetric and, as a stiffness of a free chain, with zero row sums.
  const Eigen::MatrixXd kd(k->real);
  EXPECT_EQ((kd - kd.transpose()).norm(), 0.0);
  EXPECT_LT((kd * Eigen::VectorXd::Ones(15)).norm(), 1e-9 * kd.norm());

  const FeMatrix* mass = model.Find("MAAX");
  ASSERT_NE(mass, nullptr);
  EXPECT_EQ(At(*mass, {101, 1}, {101, 1}), 1.324200034);
  EXPECT_EQ(mass->real.nonZeros(), 15);

  const FeMatrix* b = model.Find("BAAX");
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->rows, 4);  // only the DOFs that appear: 101 102 301 302
  EXPECT_EQ(b->row_dofs[2], (DofId{301, 1}));

  const FeMatrix* vax = model.Find("VAX");  // IFO 9, NCOL 1
  ASSERT_NE(vax, nullptr);
  EXPECT_EQ(vax->rows, 15);
  EXPECT_EQ(vax->cols, 1);
  EXPECT_FALSE(vax->symmetric);
  EXPECT_TRUE(vax->col_dofs.empty());       // IFO 9 columns are plain numbers
  const FeMatrix* rva = model.Find("RVA");  // IFO 9, NCOL 2
  ASSERT_NE(rva, nullptr);
  EXPECT_EQ(rva->rows, 4);
  EXPECT_EQ(rva->cols, 2);
  EXPECT_EQ(At(*rva, {301, 1}, {1, 0}), -3.162277660);
  EXPECT_EQ(At(*rva, {102, 1}, {2, 0}), 3.162277660);
  const FeMatrix* mug = model.Find("MUG1T");  // NCOL 90, columns 1, 7, ..., 85 given
  ASSERT_NE(mug, nullptr);
  EXPECT_EQ(mug->cols, 90);
  EXPECT_EQ(At(*mug, {309, 1}, {85, 0}), 1.0);
  EXPECT_EQ(At(*mug, {309, 1}, {86, 0}), 0.0);
}

// ---- EXTSEOUT (NX Nastran 9, superelement 102) -----------------------------------------------

std::vector<DofId> InboardExtrnOrder() {
  std::vector<DofId> dofs;
  for (int64_t g : {3, 11, 19, 27}) {
    for (int c = 1; c <= 6; ++c) dofs.push_back({g, c});
  }
  for (int64_t s = 2995001; s <= 2995008; ++s) dofs.push_back({s, 0});
  return dofs;
}

TEST(NastranPunch, ExtseoutPunchGivesExtrnOrderGridsAndSystems) {
  const FeModel model = fricrom::ReadNastranPunch(kFixtures + "extseout/inboard.pch");
  // The punch carries no DMIG (MATOP4 sent the matrices to inboard.op4): only the EXTRN order.
  EXPECT_TRUE(model.matrices.empty());
  EXPECT_EQ(model.external_dofs.size(), 32u);
  EXPECT_EQ(model.external_dofs, InboardExtrnOrder());

  // GRID cards appear twice (BEGIN SUPER section and main bulk section), read once.
  ASSERT_EQ(model.nodes.size(), 4u);
  const std::vector<std::tuple<int64_t, double, double, double, int>> grids = {
      {3, 600, 0, 300, 0}, {11, 600, 300, 300, 10}, {19, 600, 300, 0, 0}, {27, 600, 0, 0, 0}};
  for (size_t i = 0; i < grids.size(); ++i) {
    const auto& [id, x, y, z, cd] = grids[i];
    EXPECT_EQ(model.nodes[i].id, id);
    EXPECT_EQ(model.nodes[i].xyz, Eigen::Vector3d(x, y, z));
    EXPECT_EQ(model.nodes[i].position_system, 0);
    EXPECT_EQ(model.nodes[i].displacement_system, cd);
  }
  // CORD2R 10: origin 0, z axis along basic x (B = (1,0,0)), x-z plane through C = (0,1,0).
  ASSERT_EQ(model.systems.size(), 1u);
  EXPECT_EQ(model.systems[0].id, 10);
  EXPECT_EQ(model.systems[0].reference, 0);
  EXPECT_EQ(model.systems[0].a, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(model.systems[0].b, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(model.systems[0].c, Eigen::Vector3d(0, 1, 0));
}

// The superelement matrices themselves are in inboard.op4 (read by ReadOp4); the punch's EXTRN
// order names their rows. Craig-Bampton structure: identity modal mass, diagonal modal
// stiffness, no boundary-modal stiffness coupling.
TEST(NastranPunch, ExtseoutMatricesFollowTheExtrnOrder) {
  const FeModel punch = fricrom::ReadNastranPunch(kFixtures + "extseout/inboard.pch");
  const FeModel op4 = fricrom::ReadOp4(kFixtures + "extseout/inboard.op4");
  const std::vector<DofId>& order = punch.external_dofs;
  const FeMatrix* k = op4.Find("KXX");
  const FeMatrix* m = op4.Find("MXX");
  ASSERT_NE(k, nullptr);
  ASSERT_NE(m, nullptr);
  ASSERT_EQ(k->rows, static_cast<int64_t>(order.size()));
  ASSERT_EQ(m->rows, static_cast<int64_t>(order.size()));
  const Eigen::MatrixXd kd(k->real), md(m->real);
  const int nb = 24, nq = 8;
  ASSERT_EQ(order[nb], (DofId{2995001, 0}));
  const Eigen::MatrixXd mqq = md.block(nb, nb, nq, nq), kqq = kd.block(nb, nb, nq, nq);
  EXPECT_LT((mqq - Eigen::MatrixXd::Identity(nq, nq)).cwiseAbs().maxCoeff(), 1e-6);
  const Eigen::MatrixXd off = kqq - Eigen::MatrixXd(kqq.diagonal().asDiagonal());
  EXPECT_LT(off.cwiseAbs().maxCoeff(), 1e-6 * kqq.diagonal().maxCoeff());
  EXPECT_LT(kd.block(0, nb, nb, nq).cwiseAbs().maxCoeff(), 1e-6 * kqq.diagonal().maxCoeff());
  EXPECT_NEAR(std::sqrt(kqq(0, 0)) / (2 * std::numbers::pi), 6.13, 0.01);
  for (int i = 1; i < nq; ++i) EXPECT_GE(kqq(i, i), kqq(i - 1, i - 1));
}

// ---- Hand-made decks ------------------------------------------------------------------------

TEST(NastranPunch, SmallLargeAndFreeFieldDeck) {
  const FeModel model = fricrom::ReadFe(kFixtures + "dmig/mixed_fields.bdf");
  EXPECT_EQ(model.format, "dmig");
  ASSERT_EQ(model.matrices.size(), 4u);  // KSQ PRECT ZSYM KLG (not the one after ENDDATA)

  const FeMatrix& ksq = *model.Find("KSQ");  // IFO 1, TIN 1, implicit exponents
  EXPECT_FALSE(ksq.symmetric);
  EXPECT_EQ(ksq.source_precision_bits, 32);
  ASSERT_EQ(ksq.row_dofs, (std::vector<DofId>{{10, 1}, {20, 3}}));
  EXPECT_EQ(ksq.col_dofs, ksq.row_dofs);
  EXPECT_EQ(At(ksq, 0, 0), 1500.0);                                        // 1.5+3
  EXPECT_EQ(At(ksq, 1, 0), -0.25);                                         // -2.5-1
  EXPECT_EQ(At(ksq, 0, 1), 0.0);                                           // square, not symmetric
  EXPECT_EQ(At(ksq, 1, 1), static_cast<double>(static_cast<float>(0.1)));  // 1.-1, single

  const FeMatrix& p = *model.Find("PRECT");  // IFO 2, free field, SPOINT column
  EXPECT_EQ(p.rows, 2);
  EXPECT_EQ(p.cols, 1);
  EXPECT_EQ(p.col_dofs, (std::vector<DofId>{{30, 0}}));
  EXPECT_EQ(At(p, 0, 0), 125.0);
  EXPECT_EQ(At(p, 1, 0), -0.75);

  const FeMatrix& z = *model.Find("ZSYM");  // IFO 6, TIN 4, polar
  EXPECT_TRUE(z.is_complex);
  EXPECT_TRUE(z.symmetric);
  ASSERT_EQ(z.imag.rows(), 2);
  EXPECT_NEAR(At(z, 0, 0), 0.0, 1e-15);
  EXPECT_NEAR(z.imag.coeff(0, 0), 2.0, 1e-15);
  EXPECT_NEAR(At(z, 0, 1), -1.0, 1e-15);
  EXPECT_NEAR(At(z, 1, 0), -1.0, 1e-15);
  EXPECT_NEAR(z.imag.coeff(1, 0), 0.0, 1e-15);
  EXPECT_EQ(At(z, 1, 1), 3.0);

  const FeMatrix& klg = *model.Find("KLG");  // large field, '*' continuations
  EXPECT_EQ(At(klg, 0, 0), 1.0);
  EXPECT_EQ(At(klg, 0, 1), -2.0);
  EXPECT_EQ(At(klg, 1, 0), -2.0);

  ASSERT_EQ(model.nodes.size(), 2u);
  EXPECT_EQ(model.nodes[1].id, 20);
  EXPECT_EQ(model.nodes[1].xyz, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(model.nodes[1].position_system, 5);
  EXPECT_EQ(model.nodes[1].displacement_system, 7);
  ASSERT_EQ(model.systems.size(), 1u);
  EXPECT_EQ(model.systems[0].c, Eigen::Vector3d(1, 0, 0));
}

TEST(NastranPunch, ExtrnOrderIsTheOrderOfSuperelementMatrices) {
  const FeModel model = fricrom::ReadNastranPunch(kFixtures + "dmig/extrn_kaax.pch");
  const FeMatrix& k = *model.Find("KAAX");
  const std::vector<DofId> order = {{20, 1}, {20, 2}, {20, 3}, {10, 1}, {900, 0}};
  EXPECT_EQ(k.row_dofs, order);  // EXTRN order, including DOF 20.2 that has no term
  EXPECT_EQ(k.col_dofs, order);
  EXPECT_EQ(At(k, 3, 3), 10.0);
  EXPECT_EQ(At(k, 0, 3), -1.0);
  EXPECT_EQ(At(k, 3, 0), -1.0);
  EXPECT_EQ(At(k, 4, 4), 4.0);
  EXPECT_EQ(At(k, 2, 4), 0.5);
  EXPECT_EQ(k.real.col(1).nonZeros(), 0);
  EXPECT_EQ(model.external_dofs, order);
}

TEST(NastranPunch, ReadFeDispatch) {
  TempDir dir;
  EXPECT_EQ(fricrom::ReadFe(kFixtures + "dmig/dmig.pch").matrices.size(), 6u);
  // A .dat deck without DMIG is not a matrix file.
  ExpectError([&] { fricrom::ReadFe(kFixtures + "extseout/inboard.dat"); }, "inboard.dat", 0,
              "no DMIG");
  const std::string bdf = dir.Write("k.bdf", "DMIG,K,0,6,2\nDMIG,K,1,1,,1,1,2.\n");
  EXPECT_EQ(fricrom::ReadFe(bdf).Find("K")->real.coeff(0, 0), 2.0);
}

// ---- Bad input: one test each ---------------------------------------------------------------

TEST(NastranPunchErrors, UnknownIfo) {
  TempDir dir;
  const std::string p =
      dir.Write("ifo.pch", "$ comment\nDMIG    K              0       5       2\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "unknown IFO 5");
}

TEST(NastranPunchErrors, UnknownTin) {
  TempDir dir;
  const std::string p = dir.Write("tin.pch", "DMIG    K              0       6       7\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 1, "unknown TIN 7");
}

TEST(NastranPunchErrors, ContinuationWithoutParentCard) {
  TempDir dir;
  const std::string p = dir.Write("cont.pch",
                                  "$ header lost\n"
                                  "*                    101               1 1.556000000D+02\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "without a card to continue");
}

TEST(NastranPunchErrors, MalformedLargeFieldContinuation) {
  // The value is shifted into the component's 16-column field.
  TempDir dir;
  const std::string p = dir.Write("shift.pch",
                                  "DMIG    K              0       6       2\n"
                                  "DMIG*   K                             101               1\n"
                                  "*                    101 1.556000000D+02\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 3, "expected row component Ci");
}

TEST(NastranPunchErrors, SymmetricMatrixWithBothTriangles) {
  TempDir dir;
  const std::string p = dir.Write("both.pch",
                                  "DMIG,K,0,6,2\n"
                                  "DMIG,K,1,1,,1,1,2.,\n"
                                  ",2,1,-1.\n"
                                  "DMIG,K,2,1,,2,1,2.,\n"
                                  ",1,1,-1.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 5, "in both triangles");
}

TEST(NastranPunchErrors, DuplicateTermIsAnError) {
  // Nastran: a GJ,CJ column may be given twice, a matrix term may not.
  TempDir dir;
  const std::string p = dir.Write("dup.pch",
                                  "DMIG,K,0,1,2\n"
                                  "DMIG,K,1,1,,1,1,2.\n"
                                  "DMIG,K,1,1,,2,1,3.\n"
                                  "DMIG,K,1,1,,1,1,4.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 4, "given twice (also on line 2)");
}

TEST(NastranPunchErrors, TruncatedEntry) {
  TempDir dir;
  const std::string p = dir.Write("trunc.pch",
                                  "DMIG    K              0       6       2\n"
                                  "DMIG    K             10       1              10       1\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "expected the value Ai");
}

TEST(NastranPunchErrors, NanValue) {
  TempDir dir;
  const std::string p = dir.Write("nan.pch", "DMIG,K,0,6,2\nDMIG,K,1,1,,1,1,NaN\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "finite real number");
  const std::string q = dir.Write("inf.pch", "DMIG,K,0,6,2\nDMIG,K,1,1,,1,1,1.+999\n");
  ExpectError([&] { fricrom::ReadNastranPunch(q); }, q, 2, "finite real number");
}

TEST(NastranPunchErrors, ColumnOutOfRange) {
  TempDir dir;
  const std::string p = dir.Write("ncol.pch", "DMIG,P,0,9,2,,,,2\nDMIG,P,3,,,1,1,1.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "out of range (expected 1..NCOL = 2)");
}

TEST(NastranPunchErrors, ColumnsWithoutHeader) {
  TempDir dir;
  const std::string p = dir.Write("nohead.pch", "DMIG,K,1,1,,1,1,1.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 1, "no header card");
}

TEST(NastranPunchErrors, ImaginaryPartOnRealMatrix) {
  TempDir dir;
  const std::string p = dir.Write("imag.pch", "DMIG,K,0,6,2\nDMIG,K,1,1,,1,1,1.,2.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "declares a real matrix");
}

TEST(NastranPunchErrors, IdUsedAsGridAndScalarPoint) {
  TempDir dir;
  const std::string p = dir.Write("mix.pch", "DMIG,K,0,6,2\nDMIG,K,5,0,,5,0,1.\n,5,1,1.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 3, "both as a scalar point");
}

TEST(NastranPunchErrors, ConflictingGridCards) {
  TempDir dir;
  const std::string p = dir.Write("grid.pch", "GRID,1,,0.,0.,0.\nGRID,1,,1.,0.,0.\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "GRID 1 defined twice");
}

TEST(NastranPunchErrors, BadExtrnComponents) {
  TempDir dir;
  const std::string p = dir.Write("extrn.pch", "EXTRN,3,1237\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 1, "expected components like 123456");
}

TEST(NastranPunchErrors, IncludeIsRefused) {
  TempDir dir;
  const std::string p = dir.Write("inc.bdf", "BEGIN BULK\nINCLUDE 'k.dmig'\nENDDATA\n");
  ExpectError([&] { fricrom::ReadNastranPunch(p); }, p, 2, "INCLUDE");
}

TEST(NastranPunchErrors, MissingFile) {
  ExpectError([] { fricrom::ReadNastranPunch("/nonexistent/k.pch"); }, "/nonexistent/k.pch", 0,
              "no such file");
}

}  // namespace

namespace {

// Node sets from Nastran bulk data: ASET grids (not its scalar points) of the EXTSEOUT punch, and
// SET1 with single ids and a THRU range that keeps the deck's grids inside it.
TEST(NastranPunch, SetCardsBecomeNodeSets) {
  const FeModel se = fricrom::ReadNastranPunch(kFixtures + "extseout/inboard.pch");
  const fricrom::NodeSet* aset = se.FindNodeSet("ASET");
  ASSERT_NE(aset, nullptr);
  EXPECT_EQ(aset->nodes, (std::vector<int64_t>{3, 11, 19, 27}));
  TempDir dir;
  const std::string deck = dir.Path("sets.bdf");
  std::ofstream(deck) << "BEGIN BULK\n"
                         "GRID,5,,0.,0.,0.\nGRID,7,,1.,0.,0.\nGRID,9,,2.,0.,0.\n"
                         "GRID,400,,3.,0.,0.\n"
                         "SET1,12,9,5\nSET1,13,6,THRU,100000000\n"
                         "CORD2C,3,0,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\nENDDATA\n";
  FeModel mesh;
  fricrom::ReadMeshDeck(deck, mesh);
  ASSERT_EQ(mesh.nodes.size(), 4u);
  ASSERT_NE(mesh.FindNodeSet("SET1_12"), nullptr);
  EXPECT_EQ(mesh.FindNodeSet("SET1_12")->nodes, (std::vector<int64_t>{9, 5}));
  EXPECT_EQ(mesh.FindNodeSet("SET1_13")->nodes, (std::vector<int64_t>{7, 9, 400}));
  ASSERT_EQ(mesh.systems.size(), 1u);
  EXPECT_EQ(mesh.systems[0].type, 'C');
  // A Nastran deck with nothing a mesh needs is an error, not an empty mesh.
  const std::string empty = dir.Path("empty.pch");
  std::ofstream(empty) << "CORD2R,3,0,0.,0.,0.,0.,0.,1.\n,1.,0.,0.\n";
  FeModel none;
  ExpectError([&] { fricrom::ReadMeshDeck(empty, none); }, {"empty.pch", "no GRID, SET1 or ASET"});
}

}  // namespace
