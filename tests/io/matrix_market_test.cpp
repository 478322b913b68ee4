// Matrix Market reader and writer: write -> read round trips that must be bit-identical (real,
// symmetric, complex, with the DOF-map sidecar), a hand-written fixture, atomic writes, and one
// test per kind of bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
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

const std::string kMtxData = std::string(FRICROM_SOURCE_DIR) + "/tests/data/mtx/";

using TempDir = fricrom::testing::ScratchDir;

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Same pattern and the same bits in every stored value.
void ExpectBitIdentical(const Eigen::SparseMatrix<double>& a,
                        const Eigen::SparseMatrix<double>& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  Eigen::SparseMatrix<double> x = a, y = b;
  x.makeCompressed();
  y.makeCompressed();
  ASSERT_EQ(x.nonZeros(), y.nonZeros());
  for (Eigen::Index j = 0; j < x.outerSize(); ++j) {
    Eigen::SparseMatrix<double>::InnerIterator p(x, j), q(y, j);
    for (; p && q; ++p, ++q) {
      ASSERT_EQ(p.row(), q.row()) << "column " << j;
      const double u = p.value(), v = q.value();
      EXPECT_EQ(std::memcmp(&u, &v, sizeof u), 0)
          << u << " vs " << v << " at " << p.row() << "," << j;
    }
    EXPECT_FALSE(p || q);
  }
}

// Awkward doubles: extremes, subnormals, signed zero, values needing all 17 digits.
std::vector<double> AwkwardValues() {
  return {0.1,
          -1.0 / 3.0,
          3.141592653589793,
          1e308,
          -std::numeric_limits<double>::max(),
          std::numeric_limits<double>::min(),
          std::numeric_limits<double>::denorm_min(),
          -4.9406564584124654e-320,
          -0.0,
          123456789012345678.0,
          2.2250738585072009e-308,
          1.0000000000000002};
}

FeMatrix RandomMatrix(int64_t rows, int64_t cols, bool symmetric, bool complex, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  std::uniform_int_distribution<int64_t> ri(0, rows - 1), ci(0, cols - 1);
  const std::vector<double> awkward = AwkwardValues();
  std::vector<Eigen::Triplet<double, int>> re, im;
  std::vector<std::pair<int64_t, int64_t>> seen;
  for (int k = 0; k < 3 * static_cast<int>(rows); ++k) {
    int64_t r = ri(rng), c = ci(rng);
    if (symmetric && r < c) std::swap(r, c);
    if (std::find(seen.begin(), seen.end(), std::make_pair(r, c)) != seen.end()) continue;
    seen.emplace_back(r, c);
    const double v =
        k < static_cast<int>(awkward.size()) ? awkward[static_cast<size_t>(k)] : u(rng);
    const double w = u(rng) * 1e-7;
    re.emplace_back(static_cast<int>(r), static_cast<int>(c), v);
    if (complex) im.emplace_back(static_cast<int>(r), static_cast<int>(c), w);
    if (symmetric && r != c) {
      re.emplace_back(static_cast<int>(c), static_cast<int>(r), v);
      if (complex) im.emplace_back(static_cast<int>(c), static_cast<int>(r), w);
    }
  }
  FeMatrix m;
  m.name = "KAAX";
  m.rows = rows;
  m.cols = cols;
  m.symmetric = symmetric;
  m.is_complex = complex;
  m.real.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  m.real.setFromTriplets(re.begin(), re.end());
  if (complex) {
    m.imag.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    m.imag.setFromTriplets(im.begin(), im.end());
  }
  return m;
}

std::vector<DofId> Dofs(int64_t n, int64_t first_node) {
  std::vector<DofId> d;
  for (int64_t i = 0; i < n; ++i) d.push_back({first_node + i / 6, static_cast<int>(i % 6 + 1)});
  return d;
}

TEST(MatrixMarket, RoundTripGeneralIsBitIdentical) {
  TempDir dir;
  const FeMatrix m = RandomMatrix(40, 25, false, false, 1);
  const std::string p = dir.Path("g.mtx");
  fricrom::WriteMatrixMarket(m, p);
  const FeModel back = fricrom::ReadMatrixMarket(p);
  EXPECT_EQ(back.format, "matrix-market");
  const FeMatrix& r = back.matrices.at(0);
  EXPECT_EQ(r.name, "KAAX");
  EXPECT_FALSE(r.symmetric);
  EXPECT_FALSE(r.is_complex);
  ExpectBitIdentical(m.real, r.real);
  EXPECT_FALSE(fs::exists(dir.Path("g.dof.csv")));  // no DOF map, no sidecar
  EXPECT_NE(Slurp(p).find("%%MatrixMarket matrix coordinate real general"), std::string::npos);
}

TEST(MatrixMarket, RoundTripSymmetricWithDofSidecar) {
  TempDir dir;
  FeMatrix m = RandomMatrix(30, 30, true, false, 2);
  m.row_dofs = m.col_dofs = Dofs(30, 101);
  const std::string p = dir.Path("k.mtx");
  fricrom::WriteMatrixMarket(m, p);  // sidecar at the default k.dof.csv
  const std::string text = Slurp(p);
  EXPECT_NE(text.find("coordinate real symmetric"), std::string::npos);
  const std::string csv = Slurp(dir.Path("k.dof.csv"));
  EXPECT_EQ(csv.substr(0, 25), "node,component\n101,1\n101,");
  const FeMatrix r = fricrom::ReadMatrixMarket(p, dir.Path("k.dof.csv")).matrices.at(0);
  EXPECT_TRUE(r.symmetric);
  ExpectBitIdentical(m.real, r.real);
  EXPECT_EQ(r.row_dofs, m.row_dofs);
  EXPECT_EQ(r.col_dofs, m.col_dofs);
  // ReadFe picks the default sidecar up by itself.
  EXPECT_EQ(fricrom::ReadFe(p).matrices.at(0).row_dofs, m.row_dofs);
}

TEST(MatrixMarket, RoundTripComplexAndRectangularDofMaps) {
  TempDir dir;
  FeMatrix m = RandomMatrix(12, 7, false, true, 3);
  m.row_dofs = Dofs(12, 1);
  m.col_dofs = {{900, 0}, {901, 0}, {902, 0}, {903, 0}, {904, 0}, {905, 0}, {906, 0}};
  const std::string p = dir.Path("z.mtx"), csv = dir.Path("z_map.csv");
  fricrom::WriteMatrixMarket(m, p, csv);
  const FeMatrix r = fricrom::ReadMatrixMarket(p, csv).matrices.at(0);
  EXPECT_TRUE(r.is_complex);
  ExpectBitIdentical(m.real, r.real);
  ExpectBitIdentical(m.imag, r.imag);
  EXPECT_EQ(r.row_dofs, m.row_dofs);
  EXPECT_EQ(r.col_dofs, m.col_dofs);
}

TEST(MatrixMarket, FlaggedSymmetricButNotSymmetricIsWrittenGeneral) {
  TempDir dir;
  FeMatrix m = RandomMatrix(5, 5, false, false, 4);
  m.symmetric = true;  // the flag alone must not make the writer drop a triangle
  const std::string p = dir.Path("n.mtx");
  fricrom::WriteMatrixMarket(m, p);
  ExpectBitIdentical(m.real, fricrom::ReadMatrixMarket(p).matrices.at(0).real);
}

TEST(MatrixMarket, AtomicWriteReplacesAndLeavesNoTemporary) {
  TempDir dir;
  const std::string p = dir.Write("a.mtx", "old content\n");
  const FeMatrix m = RandomMatrix(4, 4, false, false, 5);
  fricrom::WriteMatrixMarket(m, p);
  ExpectBitIdentical(m.real, fricrom::ReadMatrixMarket(p).matrices.at(0).real);
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    ++files;
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
  }
  EXPECT_EQ(files, 1);
  // An unwritable target: exception, target untouched, no temporary left.
  EXPECT_THROW(fricrom::WriteMatrixMarket(m, dir.Path("missing-dir/a.mtx")), std::runtime_error);
}

TEST(MatrixMarket, HandWrittenFixture) {
  const FeModel model =
      fricrom::ReadMatrixMarket(kMtxData + "spring3.mtx", kMtxData + "spring3.dof.csv");
  const FeMatrix& k = model.matrices.at(0);
  EXPECT_EQ(k.name, "spring3");
  EXPECT_TRUE(k.symmetric);
  const Eigen::MatrixXd kd(k.real);
  Eigen::MatrixXd expected(3, 3);
  expected << 2, -1, 0, -1, 2, -1, 0, -1, 1;
  EXPECT_EQ(kd, expected * 1000.0);
  EXPECT_EQ(k.row_dofs, (std::vector<DofId>{{1, 1}, {2, 1}, {3, 1}}));
  // integer field, general
  const FeMatrix i = fricrom::ReadMatrixMarket(kMtxData + "incidence.mtx").matrices.at(0);
  EXPECT_EQ(i.rows, 2);
  EXPECT_EQ(i.cols, 3);
  EXPECT_EQ(i.real.coeff(1, 2), -1.0);
}

// ---- Bad input ------------------------------------------------------------------------------

const char* kBanner = "%%MatrixMarket matrix coordinate real general\n";

TEST(MatrixMarketErrors, PatternIsRefused) {
  TempDir dir;
  const std::string p =
      dir.Write("p.mtx", "%%MatrixMarket matrix coordinate pattern general\n2 2 1\n1 1\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 1, "'pattern' matrix has no values");
}

TEST(MatrixMarketErrors, TruncatedFile) {
  TempDir dir;
  const std::string p = dir.Write("t.mtx", std::string(kBanner) + "3 3 3\n1 1 1.0\n2 2 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 4, "truncated file");
  const std::string q = dir.Write("t2.mtx", std::string(kBanner) + "% only comments\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(q); }, q, 2, "truncated file");
}

TEST(MatrixMarketErrors, NanAndInf) {
  TempDir dir;
  const std::string p = dir.Write("n.mtx", std::string(kBanner) + "2 2 2\n1 1 1.0\n2 2 NaN\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 4, "finite real number");
  const std::string q = dir.Write("i.mtx", std::string(kBanner) + "2 2 1\n1 1 -1e999\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(q); }, q, 3, "finite real number");
}

TEST(MatrixMarketErrors, IndexOutOfRange) {
  TempDir dir;
  const std::string p = dir.Write("r.mtx", std::string(kBanner) + "2 2 2\n1 1 1.0\n3 1 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 4, "index out of range");
}

TEST(MatrixMarketErrors, DimensionMismatch) {
  TempDir dir;
  const std::string p =
      dir.Write("d.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 3 1\n1 1 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 2, "dimension mismatch");
}

TEST(MatrixMarketErrors, DofMapDoesNotMatchMatrixSize) {
  TempDir dir;
  const std::string p = dir.Write("k.mtx", std::string(kBanner) + "3 3 1\n1 1 1.0\n");
  const std::string csv = dir.Write("k.csv", "node,component\n1,1\n1,2\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p, csv); }, csv, 0, "DOF map has 2 entries");
  const std::string bad = dir.Write("h.csv", "1,1\n1,2\n1,3\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p, bad); }, bad, 1, "header line 'node,component'");
}

TEST(MatrixMarketErrors, SymmetricWithBothTriangles) {
  TempDir dir;
  const std::string p = dir.Write(
      "s.mtx",
      "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1.0\n2 1 1.0\n1 2 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 5, "in both triangles");
}

TEST(MatrixMarketErrors, MoreEntriesThanDeclaredAndDuplicates) {
  TempDir dir;
  const std::string p = dir.Write("m.mtx", std::string(kBanner) + "2 2 1\n1 1 1.0\n2 2 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 4, "more entries than");
  const std::string q = dir.Write("q.mtx", std::string(kBanner) + "2 2 2\n1 1 1.0\n1 1 1.0\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(q); }, q, 4, "given twice");
}

TEST(MatrixMarketErrors, BadBannerAndSize) {
  TempDir dir;
  const std::string p = dir.Write("b.mtx", "%%MatrixMarket matrix array real general\n2 2\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(p); }, p, 1, "expected format 'coordinate'");
  const std::string q = dir.Write("c.mtx", std::string(kBanner) + "2 2 5\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(q); }, q, 2, "expected 0..4 entries");
  const std::string r = dir.Write("h.mtx", "%%MatrixMarket matrix coordinate real hermitian\n");
  ExpectError([&] { fricrom::ReadMatrixMarket(r); }, r, 1, "expected symmetry");
}

}  // namespace
