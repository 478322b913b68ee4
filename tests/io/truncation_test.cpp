// Issue 9, defect 3: a truncated FE text file is an error, never a different matrix. Every sample
// written by an exporter is cut at every byte offset; the cut file must fail to read, or read as
// matrices each identical to the same-named matrix of the whole file (a cut can drop whole
// matrices of a multi-matrix file, never alter one). Cuts exactly at a line end of the formats
// without declared counts or terminators (Abaqus .mtx, between DMIG columns) cannot be detected
// in principle: they are counted, checked to be line-end cuts, and documented
// (docs/formats-abaqus-calculix-mtx.md, docs/formats-nastran-punch.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "fricrom/fe_model.h"
#include "io/io_test_util.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool SameMatrix(const FeMatrix& a, const FeMatrix& b) {
  return a.rows == b.rows && a.cols == b.cols && a.row_dofs == b.row_dofs &&
         a.col_dofs == b.col_dofs && a.real.nonZeros() == b.real.nonZeros() &&
         (Eigen::SparseMatrix<double>(a.real - b.real)).norm() == 0.0;
}

struct CutStats {
  int cuts = 0, errors = 0, identical = 0, undetectable_line_end = 0, wrong_inside_line = 0;
};

// Cuts `text` (the content of file `name`, read by `read`) at every offset.
CutStats CutEverywhere(const std::string& text, const std::string& name,
                       const std::function<FeModel(const std::string&)>& read,
                       const std::function<std::string(const std::string&)>& write_cut) {
  const FeModel full = read(write_cut(text));
  std::map<std::string, const FeMatrix*> by_name;
  for (const FeMatrix& m : full.matrices) by_name[m.name] = &m;
  CutStats s;
  for (size_t off = 0; off < text.size(); ++off) {
    ++s.cuts;
    FeModel cut;
    try {
      cut = read(write_cut(text.substr(0, off)));
    } catch (const FeReadError&) {
      ++s.errors;
      continue;
    }
    bool same = true;
    for (const FeMatrix& m : cut.matrices) {
      const auto it = by_name.find(m.name);
      same = same && it != by_name.end() && SameMatrix(m, *it->second);
    }
    if (same) {
      ++s.identical;
    } else if (off > 0 && text[off - 1] == '\n') {
      ++s.undetectable_line_end;
    } else {
      ++s.wrong_inside_line;
      ADD_FAILURE() << name << " cut at byte " << off << " (inside a line) read as valid";
    }
  }
  return s;
}

const std::string kData = std::string(FRICROM_SOURCE_DIR) + "/tests/data/";
const std::string kSamples = std::string(FRICROM_SOURCE_DIR) + "/../shared/fe-samples/";

TEST(Truncation, MatrixMarketCutsAreAllDetected) {
  testing::ScratchDir dir;
  for (const char* f : {"mtx/spring3.mtx", "mtx/incidence.mtx"}) {
    const CutStats s = CutEverywhere(
        Slurp(kData + f), f, [](const std::string& p) { return ReadMatrixMarket(p); },
        [&](const std::string& t) { return dir.Write("cut.mtx", t); });
    EXPECT_EQ(s.identical, 0) << f;  // declared counts: no cut reads
    EXPECT_EQ(s.undetectable_line_end, 0) << f;
    EXPECT_EQ(s.errors, s.cuts) << f;
  }
}

TEST(Truncation, CalculixMatrixCutsAreAllDetected) {
  testing::ScratchDir dir;
  const fs::path base = kData + "calculix/twobricks";
  for (const char* ext : {".sti", ".mas", ".dof"}) {
    for (const char* other : {".sti", ".mas", ".dof"}) {
      fs::copy_file(base.string() + other, dir.Path(std::string("c") + other),
                    fs::copy_options::overwrite_existing);
    }
    const CutStats s = CutEverywhere(
        Slurp(base.string() + ext), ext,
        [&](const std::string&) { return ReadCalculix(dir.Path("c")); },
        [&](const std::string& t) { return dir.Write(std::string("c") + ext, t); });
    EXPECT_EQ(s.errors, s.cuts) << ext;  // every DOF has a diagonal term; .dof against indices
  }
}

TEST(Truncation, AbaqusCutsInsideALineAreDetected) {
  testing::ScratchDir dir;
  for (const std::string& f :
       {kData + "abaqus/model_STIF1.mtx", kData + "abaqus/model_MASS1.mtx"}) {
    const CutStats s = CutEverywhere(
        Slurp(f), f, [](const std::string& p) { return ReadAbaqusMatrix(p); },
        [&](const std::string& t) { return dir.Write("cut.mtx", t); });
    EXPECT_EQ(s.wrong_inside_line, 0) << f;
    EXPECT_GT(s.errors, 0.9 * s.cuts) << f;
    std::printf("[truncation] %s: %d cuts, %d errors, %d undetectable line-end cuts\n", f.c_str(),
                s.cuts, s.errors, s.undetectable_line_end);
  }
}

TEST(Truncation, PunchCutsInsideALineOrACardAreDetected) {
  testing::ScratchDir dir;
  for (const std::string& f : {kData + "dmig/dmig.pch", kData + "extseout/inboard.pch"}) {
    if (!fs::exists(f)) continue;
    const CutStats s = CutEverywhere(
        Slurp(f), f, [](const std::string& p) { return ReadNastranPunch(p); },
        [&](const std::string& t) { return dir.Write("cut.pch", t); });
    EXPECT_EQ(s.wrong_inside_line, 0) << f;
    std::printf(
        "[truncation] %s: %d cuts, %d errors, %d identical (whole matrices dropped), %d "
        "undetectable line-end cuts\n",
        f.c_str(), s.cuts, s.errors, s.identical, s.undetectable_line_end);
  }
}

// OUTPUT4 has record markers (binary) and end-of-matrix records (both encodings): every cut fails
// or drops whole matrices, never alters one (the file has no matrix count: a cut between two
// matrices reads the first ones, documented in docs/formats-nastran-op4.md).
TEST(Truncation, Op4CutsFailOrDropWholeMatrices) {
  testing::ScratchDir dir;
  for (const char* f :
       {"op4/double_dense_ascii.op4", "op4/double_bigmat_ascii_i64.op4", "op4/double_dense_le.op4",
        "op4/double_bigmat_be.op4", "op4/cdbin.op4", "op4_large/large_dim_bigmat_i64.op4",
        "op4_large/large_dim_bigmat_ascii.op4"}) {
    FeReadOptions coordinate;  // the 10^7-column fixtures, cut 2000 times, in coordinate form
    coordinate.coordinate = std::string(f).find("large") != std::string::npos;
    const auto read = [&](const std::string& p) {
      FeModel m = ReadOp4(p, coordinate);
      for (FeMatrix& x : m.matrices) {
        if (!x.coordinate) continue;
        x.real.resize(1, static_cast<Eigen::Index>(x.coo.re.size()));  // entries as one row
        for (size_t k = 0; k < x.coo.re.size(); ++k) {
          x.real.insert(0, static_cast<Eigen::Index>(k)) =
              x.coo.re[k] + 1e-3 * static_cast<double>(x.coo.row[k] + 7 * x.coo.col[k]);
        }
      }
      return m;
    };
    const CutStats s = CutEverywhere(Slurp(kData + f), f, read,
                                     [&](const std::string& t) { return dir.Write("cut.op4", t); });
    EXPECT_EQ(s.undetectable_line_end + s.wrong_inside_line, 0) << f;
    EXPECT_GT(s.errors, 0.9 * s.cuts) << f;
  }
}

// CalculiX closes every matrix with the last DOF's diagonal: a line-end cut is caught even when
// the lines before it are not in CalculiX's order (the diagonal check alone would not catch it).
TEST(Truncation, CalculixLineEndCutOfAReorderedFileIsCaught) {
  testing::ScratchDir dir;
  const fs::path base = kData + "calculix/twobricks";
  for (const char* ext : {".dof", ".mas"}) {
    fs::copy_file(base.string() + ext, dir.Path(std::string("c") + ext));
  }
  std::string sti = Slurp(base.string() + ".sti");
  // Move the last line (24 24) to the top: every diagonal is still present.
  const size_t last = sti.rfind('\n', sti.size() - 2) + 1;
  sti = sti.substr(last) + sti.substr(0, last);
  const size_t cut = sti.rfind('\n', sti.size() - 2) + 1;  // drop the new last line (23 24)
  dir.Write("c.sti", sti.substr(0, cut));
  testing::ExpectError([&] { ReadCalculix(dir.Path("c")); },
                       {"c.sti:", "expected the diagonal (24, 24) of the last DOF", "truncated"});
}

TEST(Truncation, RandomBytesAreNotAnEmptyPunch) {
  testing::ScratchDir dir;
  std::string junk(4096, '\0');
  unsigned x = 12345;
  for (char& c : junk) c = static_cast<char>((x = x * 1103515245u + 12345u) >> 16);
  junk.back() = '\n';  // even with a final line break
  EXPECT_THROW(ReadNastranPunch(dir.Write("junk.pch", junk)), FeReadError);
  EXPECT_THROW(ReadNastranPunch(dir.Write("text.pch", "hello\nworld\n")), FeReadError);
}

}  // namespace
}  // namespace fricrom
