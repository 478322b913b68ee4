// Tests of the Nastran OUTPUT4 reader against real Nastran-written files (tests/data/op4, see
// PROVENANCE.md there): every file reads, the same matrices in every layout, spot values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/op4_test_util.h"

namespace fricrom {
namespace {

using namespace op4_test;

// ---- every fixture reads ----------------------------------------------------------------

const std::vector<std::string> kRcFiles = {
    "double_dense_le.op4",          "double_bigmat_be.op4",        "double_nonbigmat_le_i64.op4",
    "double_dense_ascii.op4",       "double_bigmat_ascii_i64.op4", "double_nonbigmat_ascii.op4",
    "double_nonbigmat_ascii_d.op4", "single_nonbigmat_ascii.op4"};

TEST(Op4Reader, EveryFixtureReads) {
  std::vector<std::string> all = kRcFiles;
  all.push_back("rd.op4");
  all.push_back("cdbin.op4");
  all.push_back("inboard.op4");
  for (const std::string& f : all) {
    SCOPED_TRACE(f);
    const FeModel model = ReadOp4(Fixture(f));
    EXPECT_EQ(model.format, "op4");
    EXPECT_EQ(model.source, Fixture(f));
    EXPECT_FALSE(model.matrices.empty());
    EXPECT_TRUE(model.nodes.empty());
    for (const FeMatrix& m : model.matrices) {
      EXPECT_EQ(m.real.rows(), m.rows);
      EXPECT_EQ(m.real.cols(), m.cols);
      if (m.is_complex) {
        EXPECT_EQ(m.imag.rows(), m.rows);
        EXPECT_EQ(m.imag.cols(), m.cols);
      } else {
        EXPECT_EQ(m.imag.size(), 0);
      }
      EXPECT_TRUE(m.row_dofs.empty());
      EXPECT_TRUE(m.col_dofs.empty());
      EXPECT_TRUE(Re(m).allFinite());
      EXPECT_TRUE(Im(m).allFinite());
    }
  }
}

TEST(Op4Reader, NamesShapesTypesInFileOrder) {
  for (const std::string& f : kRcFiles) {
    SCOPED_TRACE(f);
    const FeModel model = ReadOp4(Fixture(f));
    ASSERT_EQ(model.matrices.size(), 3u);
    const bool single = f.rfind("single", 0) == 0;
    const std::string suffix = single ? "S" : "";
    EXPECT_EQ(model.matrices[0].name, "RMAT" + suffix);  // trailing blanks trimmed
    EXPECT_EQ(model.matrices[1].name, "CMAT" + suffix);
    EXPECT_EQ(model.matrices[2].name, "RCMAT" + suffix);
    EXPECT_FALSE(model.matrices[0].is_complex);
    EXPECT_TRUE(model.matrices[1].is_complex);
    EXPECT_TRUE(model.matrices[2].is_complex);
    for (const FeMatrix& m : model.matrices) {
      EXPECT_EQ(m.rows, 25);
      EXPECT_EQ(m.cols, 31);
      EXPECT_FALSE(m.symmetric);  // form 2
    }
  }
  // Precision follows the type code: 2/4 are double, 1/3 single. The `_i64` ASCII file was
  // written by an 8-byte-word Nastran, which labels its (double) data as types 1 and 3; ASCII
  // cannot tell, so it reports 32 (documented).
  EXPECT_EQ(ReadOp4(Fixture("double_dense_le.op4")).matrices[0].source_precision_bits, 64);
  EXPECT_EQ(ReadOp4(Fixture("double_dense_ascii.op4")).matrices[1].source_precision_bits, 64);
  EXPECT_EQ(ReadOp4(Fixture("single_nonbigmat_ascii.op4")).matrices[0].source_precision_bits, 32);
  EXPECT_EQ(ReadOp4(Fixture("single_nonbigmat_ascii.op4")).matrices[2].source_precision_bits, 32);
  EXPECT_EQ(ReadOp4(Fixture("double_bigmat_ascii_i64.op4")).matrices[0].source_precision_bits, 32);
}

// ---- the same three matrices in every layout --------------------------------------------

struct Rc {
  Eigen::MatrixXd r, cr, ci, rcr, rci;
};
Rc LoadRc(const std::string& f) {
  const FeModel model = ReadOp4(Fixture(f));
  const FeMatrix& r = model.matrices.at(0);
  const FeMatrix& c = model.matrices.at(1);
  const FeMatrix& rc = model.matrices.at(2);
  return {Re(r), Re(c), Im(c), Re(rc), Im(rc)};
}

// Same zero pattern; |a - b| <= rel * |b| elementwise.
void ExpectClose(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double rel, const char* what) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      EXPECT_EQ(a(i, j) == 0.0, b(i, j) == 0.0) << what << " (" << i << "," << j << ")";
      EXPECT_LE(std::abs(a(i, j) - b(i, j)), rel * std::abs(b(i, j)))
          << what << " (" << i << "," << j << "): " << a(i, j) << " vs " << b(i, j);
    }
  }
}

void ExpectRcClose(const Rc& a, const Rc& b, double rel) {
  ExpectClose(a.r, b.r, rel, "rmat");
  ExpectClose(a.cr, b.cr, rel, "cmat real");
  ExpectClose(a.ci, b.ci, rel, "cmat imag");
  ExpectClose(a.rcr, b.rcr, rel, "rcmat real");
  ExpectClose(a.rci, b.rci, rel, "rcmat imag");
}

TEST(Op4Reader, CrossLayoutIdentity) {
  const Rc ref = LoadRc("double_dense_le.op4");
  EXPECT_EQ((ref.r.array() != 0).count(), 32);
  // Binary double layouts carry the same bits.
  for (const char* f : {"double_bigmat_be.op4", "double_nonbigmat_le_i64.op4"}) {
    SCOPED_TRACE(f);
    ExpectRcClose(LoadRc(f), ref, 0.0);
  }
  // ASCII double layouts: equal to the printed digits (E21.14: 15 significant, E16.9: 10).
  ExpectRcClose(LoadRc("double_nonbigmat_ascii.op4"), ref, 6e-15);
  ExpectRcClose(LoadRc("double_dense_ascii.op4"), ref, 6e-10);
  ExpectRcClose(LoadRc("double_bigmat_ascii_i64.op4"), ref, 6e-10);
  // Same printed digits in different layouts, and D instead of E exponents: exactly equal.
  ExpectRcClose(LoadRc("double_bigmat_ascii_i64.op4"), LoadRc("double_dense_ascii.op4"), 0.0);
  ExpectRcClose(LoadRc("double_nonbigmat_ascii_d.op4"), LoadRc("double_nonbigmat_ascii.op4"), 0.0);

  // Single precision: the double values rounded to float, exactly.
  Rc single_ref = ref;
  for (Eigen::MatrixXd* m :
       {&single_ref.r, &single_ref.cr, &single_ref.ci, &single_ref.rcr, &single_ref.rci}) {
    *m = m->unaryExpr([](double v) { return static_cast<double>(static_cast<float>(v)); });
  }
  ExpectRcClose(LoadRc("single_nonbigmat_ascii.op4"), single_ref, 0.0);

  // Known structure of the set: cmat is purely imaginary, rcmat = rmat + cmat.
  EXPECT_EQ(ref.cr.norm(), 0.0);
  EXPECT_EQ(ref.rcr, ref.r);
  EXPECT_EQ(ref.rci, ref.ci);
}

// ---- spot values read by an independent route -------------------------------------------

TEST(Op4Reader, SpotValuesFromHandParsedAsciiColumn) {
  // RMAT's first stored column of the dense ASCII file, parsed here by hand: header line, then
  // "icol irow nwords", then values in 16-character fields.
  std::ifstream in(Fixture("double_dense_ascii.op4"));
  std::string header;
  std::string colhdr;
  std::getline(in, header);
  std::getline(in, colhdr);
  const int icol = std::stoi(colhdr.substr(0, 8));
  const int irow = std::stoi(colhdr.substr(8, 8));
  const int n = std::stoi(colhdr.substr(16, 8));
  ASSERT_EQ(icol, 2);
  ASSERT_EQ(irow, 7);
  ASSERT_EQ(n, 17);
  std::vector<double> vals;
  std::string line;
  while (static_cast<int>(vals.size()) < n && std::getline(in, line)) {
    for (size_t p = 0; p + 16 <= line.size(); p += 16)
      vals.push_back(std::strtod(line.substr(p, 16).c_str(), nullptr));
  }
  ASSERT_EQ(static_cast<int>(vals.size()), n);
  const Eigen::MatrixXd r = Re(ReadOp4(Fixture("double_dense_ascii.op4")).matrices[0]);
  for (int k = 0; k < n; ++k) EXPECT_EQ(r(irow - 1 + k, icol - 1), vals[static_cast<size_t>(k)]);
  EXPECT_EQ(r(6, 1), -4.062035008e+02);
  EXPECT_EQ(r.col(0).norm(), 0.0);  // column 1 is not stored: all zero

  // The same entry straight from the bytes of the little-endian binary file: first column
  // record at byte 32, its three integers, then the first double.
  const std::string b = ReadBytes(Fixture("double_dense_le.op4"));
  ASSERT_EQ(GetI32(b, 36), 2);  // column
  ASSERT_EQ(GetI32(b, 40), 7);  // first row
  const Eigen::MatrixXd rb = Re(ReadOp4(Fixture("double_dense_le.op4")).matrices[0]);
  EXPECT_EQ(rb(6, 1), GetF64(b, 48));
  EXPECT_NEAR(rb(6, 1), -406.2035008, 1e-7);
}

TEST(Op4Reader, TwoMatricesOfOneNameReadButCannotBeSelectedByIt) {
  // The fuzz regression seed: an ASCII OP4 holding R2 (5 x 6), R2 (10 x 19) and R3.
  const std::string path =
      std::string(FRICROM_SOURCE_DIR) + "/tests/fuzz/regressions/op4/two_matrices_named_R2.op4";
  const FeModel all = ReadOp4(path);
  ASSERT_EQ(all.matrices.size(), 3u);
  EXPECT_EQ(all.matrices[0].name, "R2");
  EXPECT_EQ(all.matrices[1].name, "R2");
  FeReadOptions only;
  only.only_matrix = "R2";
  try {
    ReadOp4(path, only);
    FAIL() << "expected FeReadError";
  } catch (const FeReadError& e) {
    EXPECT_NE(std::string(e.what()).find("ambiguous"), std::string::npos) << e.what();
  }
  only.only_matrix = "R3";
  EXPECT_EQ(ReadOp4(path, only).matrices.size(), 1u);
}

TEST(Op4Reader, RealDoubleAsciiSeveralMatrices) {
  const FeModel model = ReadOp4(Fixture("rd.op4"));
  ASSERT_EQ(model.matrices.size(), 3u);
  const FeMatrix& r1 = model.matrices[0];
  const FeMatrix& r2 = model.matrices[1];
  const FeMatrix& r3 = model.matrices[2];
  EXPECT_EQ(r1.name, "R1");
  EXPECT_EQ(r2.name, "R2");
  EXPECT_EQ(r3.name, "R3");
  EXPECT_EQ(r1.rows, 5);
  EXPECT_EQ(r1.cols, 6);
  EXPECT_EQ(r2.rows, 10);
  EXPECT_EQ(r2.cols, 19);
  EXPECT_EQ(r3.rows, 1);
  EXPECT_EQ(r3.cols, 1);
  EXPECT_FALSE(r1.is_complex);
  EXPECT_EQ(r1.source_precision_bits, 64);
  // Values as printed in the file (E24.17 round-trips doubles).
  const Eigen::MatrixXd m1 = Re(r1);
  EXPECT_EQ(m1(0, 0), 1.23314083328218890E+00);
  EXPECT_EQ(m1(4, 0), 6.60163437000680140E-01);
  EXPECT_EQ(m1.col(1).norm(), 0.0);
  EXPECT_EQ(m1(0, 2), -1.44736988258324260E+00);
  EXPECT_EQ(m1(2, 3), -1.98510352161182870E-01);  // column 4 starts at row 3
  EXPECT_EQ(m1(0, 3), 0.0);
  EXPECT_EQ(m1(4, 5), -7.92238234758003420E-02);
  EXPECT_EQ(r2.real.nonZeros(), 0);  // all-zero matrix: only the end record
  EXPECT_TRUE(r3.symmetric);         // form 6
  EXPECT_EQ(Re(r3)(0, 0), 3.0);
  EXPECT_FALSE(r1.symmetric);
}

TEST(Op4Reader, ComplexBinary64BitWords) {
  // cdbin.op4: big endian, 8-byte integers and 16-byte names, types 3 with 8-byte reals.
  const FeModel model = ReadOp4(Fixture("cdbin.op4"));
  ASSERT_EQ(model.matrices.size(), 5u);
  const char* names[] = {"C1", "C2", "C3", "C4", "C5"};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(model.matrices[i].name, names[i]);
    EXPECT_TRUE(model.matrices[i].is_complex);
    EXPECT_EQ(model.matrices[i].source_precision_bits, 64);
  }
  // Built on the same real 5x6 matrix as rd.op4's R1 (which prints round-trip digits).
  const Eigen::MatrixXd r1 = Re(ReadOp4(Fixture("rd.op4")).matrices[0]);
  const FeMatrix& c1 = model.matrices[0];
  const FeMatrix& c4 = model.matrices[3];
  const FeMatrix& c5 = model.matrices[4];
  EXPECT_EQ(Re(c1), r1);
  EXPECT_NE(Im(c1).norm(), 0.0);
  EXPECT_EQ(Re(c4).norm(), 0.0);  // i * R1
  EXPECT_EQ(Im(c4), r1);
  EXPECT_EQ(Re(c5), r1);  // R1 + 0i
  EXPECT_EQ(Im(c5).norm(), 0.0);
  EXPECT_EQ(model.matrices[1].rows, 10);
  EXPECT_EQ(model.matrices[1].cols, 19);
  EXPECT_EQ(model.matrices[1].real.nonZeros() + model.matrices[1].imag.nonZeros(), 0);
  const FeMatrix& c3 = model.matrices[2];
  EXPECT_TRUE(c3.symmetric);
  EXPECT_EQ(Re(c3)(0, 0), 3.0);
  EXPECT_EQ(Im(c3)(0, 0), 7.0);
  // Raw bytes: C1(1,1) imaginary part is the second big-endian double of the record at 56.
  const std::string b = ReadBytes(Fixture("cdbin.op4"));
  uint64_t u = 0;
  for (size_t i = 0; i < 8; ++i) u = (u << 8) | static_cast<uint8_t>(b[56 + 4 + 24 + 8 + i]);
  double v;
  std::memcpy(&v, &u, 8);
  EXPECT_EQ(Im(c1)(0, 0), v);
}

TEST(Op4Reader, ExtseoutSuperelementKnownFacts) {
  // inboard.op4: NX Nastran EXTSEOUT(MATOP4=...) of a Craig-Bampton superelement. KXX and MXX
  // are 32 x 32 (24 boundary DOFs, then 8 modal DOFs), symmetric form, bigmat sparse.
  const FeModel model = ReadOp4(Fixture("inboard.op4"));
  ASSERT_GE(model.matrices.size(), 2u);
  const FeMatrix& k = model.matrices[0];
  const FeMatrix& m = model.matrices[1];
  EXPECT_EQ(k.name, "KXX");
  EXPECT_EQ(m.name, "MXX");
  for (const FeMatrix* a : {&k, &m}) {
    EXPECT_EQ(a->rows, 32);
    EXPECT_EQ(a->cols, 32);
    EXPECT_TRUE(a->symmetric);
    EXPECT_FALSE(a->is_complex);
    EXPECT_EQ(a->source_precision_bits, 64);
  }
  const Eigen::MatrixXd kd = Re(k);
  const Eigen::MatrixXd md = Re(m);
  // Stored in full: both triangles, equal.
  EXPECT_LE((kd - kd.transpose()).cwiseAbs().maxCoeff(), 1e-9 * kd.cwiseAbs().maxCoeff());
  EXPECT_LE((md - md.transpose()).cwiseAbs().maxCoeff(), 1e-9 * md.cwiseAbs().maxCoeff());
  // Modal block: MXX identity, KXX diagonal, no boundary-modal stiffness coupling.
  const Eigen::MatrixXd mq = md.bottomRightCorner(8, 8);
  const Eigen::MatrixXd kq = kd.bottomRightCorner(8, 8);
  EXPECT_LE((mq - Eigen::MatrixXd::Identity(8, 8)).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LE((kq - Eigen::MatrixXd(kq.diagonal().asDiagonal())).cwiseAbs().maxCoeff(),
            1e-6 * kq.diagonal().maxCoeff());
  EXPECT_LE(kd.topRightCorner(24, 8).cwiseAbs().maxCoeff(), 1e-6 * kq.diagonal().maxCoeff());
  const double f1 = std::sqrt(kq(0, 0)) / (2.0 * std::numbers::pi);
  EXPECT_NEAR(f1, 6.13, 0.01);
}

TEST(Op4Reader, EightByteRecordMarkers) {
  TempDir tmp;
  for (const auto& [f, big] : std::vector<std::pair<std::string, bool>>{
           {"double_dense_le.op4", false}, {"cdbin.op4", true}, {"double_bigmat_be.op4", true}}) {
    SCOPED_TRACE(f);
    const FeModel a = ReadOp4(Fixture(f));
    const FeModel b = ReadOp4(tmp.Write("wide_" + f, WidenMarkers(ReadBytes(Fixture(f)), big)));
    ASSERT_EQ(a.matrices.size(), b.matrices.size());
    ExpectPrefixOf(b, a);
  }
}

TEST(Op4Reader, AsciiVariants) {
  TempDir tmp;
  // CRLF line ends, Fortran three-digit exponents without the letter, lower-case d.
  const std::string text =
      "       3       3       2       2TINY    1P,3E16.9\r\n"
      "       1       1       3\r\n"
      " 1.000000000+100-2.500000000d-01 3.000000000E+00\r\n"
      "       2       0       3\r\n"
      "  196610\r\n"
      "-1.000000000-100\r\n"
      "       4       1       1\r\n"
      " 1.000000000E+00\r\n";
  const FeModel m = ReadOp4(tmp.Write("tiny.op4", text));
  ASSERT_EQ(m.matrices.size(), 1u);
  const Eigen::MatrixXd r = Re(m.matrices[0]);
  EXPECT_EQ(r(0, 0), 1e100);
  EXPECT_EQ(r(1, 0), -0.25);
  EXPECT_EQ(r(2, 0), 3.0);
  EXPECT_EQ(r(1, 1), -1e-100);
  EXPECT_EQ(m.matrices[0].real.nonZeros(), 4);
}

}  // namespace
}  // namespace fricrom
