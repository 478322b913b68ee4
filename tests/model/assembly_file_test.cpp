// FE assembly case files (fricrom-assembly-1): the lumped benchmark written as FE data gives the
// lumped results through the FE path (condensed balance), and bad assembly input is a clear
// error naming the file and key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/cli_test_util.h"
#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/frf.h"
#include "test_models.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
const std::string kAsFe = std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/as_fe/case.toml";

TEST(Assembly, LumpedCaseAsFeDataGivesTheLumpedResults) {
  const Case lumped = testing::LoadBaseline();
  const Case fe = LoadCase(kAsFe);
  EXPECT_EQ(fe.analysis.balance, BalanceKind::kCondensed);
  ASSERT_EQ(fe.model.num_dofs(), lumped.model.num_dofs());
  ASSERT_EQ(fe.model.contacts.size(), 4u);
  EXPECT_EQ(fe.model.free_dofs.size(), 6u);  // the blades body
  const auto a = MakeBalance(lumped.model, HbmOptions{1, 128}, BalanceKind::kFull);
  const auto b = MakeBalance(fe.model, HbmOptions{1, 128}, fe.analysis.balance);
  const Eigen::Vector4d alpha = Eigen::Vector4d::Zero();
  const auto pa = SolveAtFrequencies(*a, alpha, {258.0, 262.0, 270.0}, FrfOptions{});
  const auto pb = SolveAtFrequencies(*b, alpha, {258.0, 262.0, 270.0}, FrfOptions{});
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(pb[i].status, SolverStatus::kConverged);
    EXPECT_NEAR(pb[i].amplitude, pa[i].amplitude, 1e-8 * pa[i].amplitude) << pa[i].freq_hz;
  }
  const BoundsResult ba = ComputeBounds(*a, 266.0, BoundsOptions{});
  const BoundsResult bb = ComputeBounds(*b, 266.0, BoundsOptions{});
  ASSERT_TRUE(ba.IsUsable() && bb.IsUsable());
  EXPECT_NEAR(bb.min.amplitude, ba.min.amplitude, 1e-8 * ba.min.amplitude);
  EXPECT_NEAR(bb.max.amplitude, ba.max.amplitude, 1e-8 * ba.max.amplitude);
}

// The committed files are exactly what `export-fe` writes today.
TEST(Assembly, CommittedAsFeFilesAreTheExport) {
  const fs::path tmp = fs::temp_directory_path() / "fricrom-as-fe-test";
  fs::remove_all(tmp);
  ExportAssembly(testing::LoadBaseline(), tmp.string());
  const fs::path ref = fs::path(kAsFe).parent_path();
  int files = 0;
  for (const auto& e : fs::directory_iterator(tmp)) {
    const fs::path name = e.path().filename();
    std::string want = testing::ReadFile(ref / name), got = testing::ReadFile(e.path());
    if (name == "case.toml") {  // the first line names the source path
      want = want.substr(want.find('\n'));
      got = got.substr(got.find('\n'));
    }
    EXPECT_EQ(got, want) << name;
    ++files;
  }
  EXPECT_EQ(files, 13);
  fs::remove_all(tmp);
}

class BadAssembly : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("fricrom-bad-assembly-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::copy(fs::path(kAsFe).parent_path(), dir_);
    text_ = testing::ReadFile(dir_ / "case.toml");
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Replaces `from` by `to` in the case, loads it, and returns the error message.
  std::string Error(const std::string& from, const std::string& to) {
    std::string t = text_;
    const auto pos = t.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) t.replace(pos, from.size(), to);
    std::ofstream(dir_ / "case.toml") << t;
    try {
      LoadCase((dir_ / "case.toml").string());
    } catch (const CaseError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
  std::string text_;
};

TEST_F(BadAssembly, ErrorsNameTheFileKeyAndProblem) {
  const std::string file = (dir_ / "case.toml").string();
  std::string e = Error("stiffness = \"damper1.K.mtx\"", "stiffness = \"nope.mtx\"");
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find("bodies[1].stiffness"), std::string::npos) << e;
  e = Error("b = { body = \"blades\", node = 1 }", "b = { body = \"blades\", node = 9 }");
  EXPECT_NE(e.find("contacts[0].b.node"), std::string::npos) << e;
  EXPECT_NE(e.find("no node 9"), std::string::npos) << e;
  e = Error("b = { body = \"blades\", node = 1 }", "b = { body = \"bladez\", node = 1 }");
  EXPECT_NE(e.find("no body named 'bladez'"), std::string::npos) << e;
  e = Error("normal = [-0.70710678118654746, 0.70710678118654757, 0.0]",
            "normal = [-0.7, 0.7, 0.14142135623730964]");
  EXPECT_NE(e.find("z DOF"), std::string::npos) << e;
  e = Error("normal = [-0.70710678118654746, 0.70710678118654757, 0.0]",
            "normal = [-0.70710678118654746, 0.70710678118654757, 0.1]");
  EXPECT_NE(e.find("contacts[0].normal"), std::string::npos) << e;
  EXPECT_NE(e.find("unit vector"), std::string::npos) << e;
  e = Error("[response]\nbody = \"blades\"\nnode = 2\ncomponent = 2",
            "[response]\nbody = \"blades\"\nnode = 2\ncomponent = 3");
  EXPECT_NE(e.find("response.component"), std::string::npos) << e;
  e = Error("dof_map = \"damper2.dofs.csv\"", "dof_map = \"blades.dofs.csv\"");
  EXPECT_NE(e.find("bodies[2]"), std::string::npos) << e;
  e = Error("harmonics = 1", "harmonics = 0");
  EXPECT_NE(e.find("analysis.harmonics"), std::string::npos) << e;
}

// A matrix file of the copied case with `from` replaced by `to`, then the case's error.
class BadBodyMatrix : public BadAssembly {
 protected:
  std::string MatrixError(const std::string& file, const std::string& from, const std::string& to) {
    std::string m = testing::ReadFile(dir_ / file);
    const auto pos = m.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) m.replace(pos, from.size(), to);
    std::ofstream(dir_ / file) << m;
    const std::string e = Error("name = \"lumped3-baseline-as-fe\"", "name = \"x\"");
    std::ofstream(dir_ / file) << testing::ReadFile(fs::path(kAsFe).parent_path() / file);
    return e;
  }
};

// Input the analysis cannot represent is an error naming the body (it used to crash, or to give a
// number: a segfault with no blade, exit 0 with an asymmetric, indefinite or 1e308 stiffness and a
// negative or zero damper mass).
TEST_F(BadBodyMatrix, BodiesTheAnalysisCannotRepresentAreErrors) {
  std::string e = MatrixError("blades.K.mtx", "3 1 -700000", "3 1 -600000");
  EXPECT_NE(e.find("stiffness matrix of body 'blades' is not symmetric"), std::string::npos) << e;
  e = MatrixError("blades.K.mtx", "1 1 1000000", "1 1 -1000000");
  EXPECT_NE(e.find("stiffness matrix of body 'blades' is indefinite"), std::string::npos) << e;
  e = MatrixError("blades.K.mtx", "2 2 1000000", "2 2 1e308");
  EXPECT_NE(e.find("overflow"), std::string::npos) << e;
  e = MatrixError("damper1.M.mtx", "1 1 0.10000000000000001", "1 1 -0.1");
  EXPECT_NE(e.find("mass matrix of body 'damper1' is indefinite"), std::string::npos) << e;
  e = MatrixError("damper1.M.mtx", "1 1 0.10000000000000001\n2 2 0.10000000000000001",
                  "1 1 0\n2 2 0");
  EXPECT_NE(e.find("mass matrix of body 'damper1' is zero"), std::string::npos) << e;
  EXPECT_EQ(MatrixError("damper1.M.mtx", "% name", "% name"), "");  // the original loads
}

TEST_F(BadAssembly, CasesWithoutMeaningAreErrors) {
  std::string e = Error("role = \"blade\"", "role = \"damper\"");
  EXPECT_NE(e.find("no body is a blade"), std::string::npos) << e;
  e = Error("name = \"c2\"", "name = \"c1\"");
  EXPECT_NE(e.find("contacts[1].name': duplicate contact name"), std::string::npos) << e;
  std::string no_load = text_;
  for (const char* c : {"cos = 5.0", "cos = 20.0", "cos = -5.0", "cos = 20.0"}) {
    no_load.replace(no_load.find(c), std::string(c).size(), "cos = 0.0");
  }
  e = Error(text_, no_load);
  EXPECT_NE(e.find("no harmonic load"), std::string::npos) << e;
}

}  // namespace
}  // namespace fricrom
