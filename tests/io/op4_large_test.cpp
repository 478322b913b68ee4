// Issue 9, defect 5: OUTPUT4 files with huge sparse matrices (Nastran writes 10^7-column BIGMAT
// matrices with a handful of terms) read, each at the cost of its column index only; the small
// matrix beside them reads exactly. Fixture: scripts/make_large_op4.py, shaped like pyyeti's
// nas_large_dim_bigmat_binary.op4 (ctest Op4Large.FixtureRegenerates checks it is the script's).
#include <gtest/gtest.h>

#include <string>

#include "fricrom/fe_model.h"

namespace fricrom {
namespace {

const std::string kFile =
    std::string(FRICROM_SOURCE_DIR) + "/tests/data/op4_large/large_dim_bigmat.op4";

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
  ASSERT_EQ(c->rows, 5);
  ASSERT_EQ(c->cols, 7);
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 7; ++j) EXPECT_EQ(c->real.coeff(i, j), 10.0 * (i + 1) + (j + 1));
  }
}

}  // namespace
}  // namespace fricrom
