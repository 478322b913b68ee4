// Issue 9, defect 5: OUTPUT4 files with huge sparse matrices (Nastran writes 10^7-column BIGMAT
// matrices with a handful of terms) read; a matrix chosen by name is read without assembling the
// others; limits come from the memory a matrix needs, not from its dimensions. Fixtures:
// scripts/make_large_op4.py, shaped like pyyeti's nas_large_dim_bigmat_{binary,ascii}.op4
// (ctest Op4Large.FixturesRegenerate checks they are the script's output).
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace fricrom {
namespace {

const std::string kDir = std::string(FRICROM_SOURCE_DIR) + "/tests/data/op4_large/";
const std::string kFile = kDir + "large_dim_bigmat.op4";

FeReadOptions Limit(uint64_t bytes, bool coordinate = false, const std::string& only = "") {
  FeReadOptions o;
  o.memory_limit_bytes = bytes;
  o.coordinate = coordinate;
  o.only_matrix = only;
  return o;
}

void ExpectMatd21(const FeMatrix& c) {
  ASSERT_EQ(c.rows, 5);
  ASSERT_EQ(c.cols, 7);
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 7; ++j) EXPECT_EQ(c.real.coeff(i, j), 10.0 * (i + 1) + (j + 1));
  }
}

TEST(Op4Large, HugeSparseBigmatMatricesRead) {
  const FeModel m = ReadOp4(kFile);
  ASSERT_EQ(m.matrices.size(), 3u);
  const FeMatrix* a = m.Find("MATD");
  const FeMatrix* b = m.Find("MATD22A");
  const FeMatrix* c = m.Find("MATD21");
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->rows, 19);
  EXPECT_EQ(a->cols, 10'000'001);
  EXPECT_EQ(a->real.nonZeros(), 6);
  EXPECT_EQ(a->real.coeff(0, 0), 1.0);
  EXPECT_EQ(a->real.coeff(1, 0), 2.0);
  EXPECT_EQ(a->real.coeff(18, 4'999'999), 3.5);
  EXPECT_EQ(a->real.coeff(8, 10'000'000), 6.0);
  EXPECT_EQ(b->rows, 10'000'000);
  EXPECT_EQ(b->cols, 10'000'000);
  EXPECT_EQ(b->real.nonZeros(), 4);
  EXPECT_EQ(b->real.coeff(2'499'999, 2'499'999), 20.0);
  EXPECT_EQ(b->real.coeff(9'999'999, 9'999'999), 40.0);
  ExpectMatd21(*c);
}

// Selecting by name skips the others without assembling them: with 1 MB allowed, the 10^7
// columns of MATD (40 MB of column index) would be refused if it were built.
TEST(Op4Large, MatrixChosenByNameSkipsTheOthers) {
  const FeModel m = ReadOp4(kFile, Limit(1 << 20, false, "matd21"));
  ASSERT_EQ(m.matrices.size(), 1u);
  EXPECT_EQ(m.matrices[0].name, "MATD21");
  ExpectMatd21(m.matrices[0]);
  EXPECT_THROW(ReadOp4(kFile, Limit(1 << 20)), FeReadError);  // all three: MATD does not fit
}

TEST(Op4Large, MemoryLimitNamesTheMatrixAndTheNeed) {
  testing::ExpectError([&] { ReadOp4(kFile, Limit(1 << 20)); },
                       {kFile, "byte offset 0", "matrix 'MATD'", "19 x 10000001",
                        "in compressed columns", "more than the 1 MB allowed"});
  // An absent name lists what the file holds.
  testing::ExpectError([&] { ReadOp4(kFile, Limit(0, false, "NOPE")); },
                       {kFile, "no matrix 'NOPE'", "MATD, MATD22A, MATD21"});
}

// Coordinate form: memory by entries only, so every matrix reads within 1 MB.
TEST(Op4Large, CoordinateFormCostsOnlyTheEntries) {
  const FeModel m = ReadOp4(kFile, Limit(1 << 20, true));
  ASSERT_EQ(m.matrices.size(), 3u);
  const FeMatrix& a = m.matrices[0];
  EXPECT_TRUE(a.coordinate);
  EXPECT_EQ(a.real.cols(), 0);  // no column index
  ASSERT_EQ(a.coo.re.size(), 6u);
  EXPECT_EQ(a.coo.row, (std::vector<int64_t>{0, 1, 18, 6, 7, 8}));
  EXPECT_EQ(a.coo.col, (std::vector<int64_t>{0, 0, 4'999'999, 10'000'000, 10'000'000, 10'000'000}));
  EXPECT_EQ(a.coo.re, (std::vector<double>{1.0, 2.0, 3.5, -4.25, 5.0, 6.0}));
  EXPECT_EQ(m.matrices[1].coo.re.size(), 4u);
  EXPECT_EQ(m.matrices[2].coo.re.size(), 35u);
}

// 10^9 columns with one term (beyond the old fixed cap of 10^8): reads in coordinate form; in
// compressed columns it needs 4 GB of column index and a smaller allowance says so.
TEST(Op4Large, BillionColumnsReadByMemoryNotByCap) {
  testing::ScratchDir dir;
  std::string b;
  const auto i32 = [&](int32_t v) {
    for (int k = 0; k < 4; ++k) b += static_cast<char>((static_cast<uint32_t>(v) >> (8 * k)) & 255);
  };
  const auto f64 = [&](double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    for (int k = 0; k < 8; ++k) b += static_cast<char>((u >> (8 * k)) & 255);
  };
  const int32_t cols = 1'000'000'000;
  i32(24), i32(cols), i32(-3), i32(2), i32(2), b += "HUGE    ", i32(24);  // header
  i32(28), i32(cols), i32(0), i32(4), i32(3), i32(2), f64(7.5), i32(28);  // row 2
  i32(20), i32(cols + 1), i32(1), i32(2), f64(0.0), i32(20);              // end
  const std::string path = dir.Write("huge.op4", b);
  const FeModel m = ReadOp4(path, Limit(1 << 20, true));
  ASSERT_EQ(m.matrices.size(), 1u);
  EXPECT_EQ(m.matrices[0].cols, cols);
  EXPECT_EQ(m.matrices[0].coo.row, std::vector<int64_t>{1});
  EXPECT_EQ(m.matrices[0].coo.col, std::vector<int64_t>{cols - 1});
  EXPECT_EQ(m.matrices[0].coo.re, std::vector<double>{7.5});
  testing::ExpectError([&] { ReadOp4(path, Limit(uint64_t{1} << 30)); },
                       {path, "matrix 'HUGE'", "3815 MB", "more than the 1024 MB allowed"});
}

// The layouts Nastran uses for such files: 64-bit words with names of 4 characters per 8-byte
// word ("MATD    22A     "), and ASCII headers with 16-character counts flagged "|I16".
TEST(Op4Large, NastranWideLayoutsRead) {
  for (const char* f : {"large_dim_bigmat_i64.op4", "large_dim_bigmat_ascii.op4"}) {
    SCOPED_TRACE(f);
    const FeModel m = ReadOp4(kDir + f);
    ASSERT_EQ(m.matrices.size(), 4u);
    EXPECT_EQ(m.matrices[1].name, "MATDT");
    EXPECT_EQ(m.matrices[2].name, "MATD22A");
    const FeMatrix* t = m.Find("MATDT");
    ASSERT_TRUE(t);
    EXPECT_EQ(t->rows, 10'000'001);
    EXPECT_EQ(t->cols, 19);
    EXPECT_EQ(t->real.coeff(4'999'999, 18), 3.5);
    EXPECT_EQ(t->real.coeff(10'000'000, 8), 6.0);
    const FeMatrix* d = m.Find("MATD");
    ASSERT_TRUE(d);
    const Eigen::SparseMatrix<double> dt = d->real.transpose();
    EXPECT_EQ(Eigen::SparseMatrix<double>(dt - t->real).norm(), 0.0);
    ExpectMatd21(*m.Find("MATD21"));
    const FeModel one = ReadOp4(kDir + f, Limit(1 << 20, false, "MATD21"));
    ExpectMatd21(one.matrices.at(0));
  }
}

}  // namespace
}  // namespace fricrom
