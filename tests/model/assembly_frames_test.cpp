// An assembly body written by Nastran in local coordinate systems (GRID CP/CD in a cylindrical
// CORD2C) gives the results of the same body written in the basic system: the lumped benchmark's
// blades as DMIG matrices in a punch, named from the multi-matrix file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fricrom/balance.h"
#include "fricrom/basic_frame.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/fe_model.h"
#include "fricrom/frf.h"
#include "fricrom/linear.h"

namespace fricrom {
namespace {

namespace fs = std::filesystem;
const fs::path kAsFeDir = fs::path(FRICROM_SOURCE_DIR) / "meshes/lumped3/as_fe";

// Nastran large-field cards: the name, then 4 fields of 16 per line.
std::string LargeField(const std::string& s) {
  char b[40];
  std::snprintf(b, sizeof b, "%-16.16s", s.c_str());
  return b;
}
std::string LargeReal(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%16.9E", v);
  return b;
}
std::string LargeInt(long v) { return LargeField(std::to_string(v)); }

// DMIG (IFO 1, TIN 2) of `a` over the DOFs `dofs` of the as_fe blades (nodes 1-3, x and y).
std::string LargeDmig(const std::string& name, const Eigen::MatrixXd& a) {
  std::ostringstream os;
  os << "DMIG*   " << LargeField(name) << LargeInt(0) << LargeInt(1) << LargeInt(2) << "\n*       "
     << LargeInt(0) << "\n";
  for (int j = 0; j < a.cols(); ++j) {
    os << "DMIG*   " << LargeField(name) << LargeInt(j / 2 + 1) << LargeInt(j % 2 + 1) << "\n";
    for (int i = 0; i < a.rows(); ++i) {
      os << "*       " << LargeInt(i / 2 + 1) << LargeInt(i % 2 + 1) << LargeReal(a(i, j)) << "\n";
    }
  }
  return os.str();
}

TEST(AssemblyFrames, ABodyInACylindricalSystemGivesTheBasicResults) {
  const fs::path dir = fs::temp_directory_path() / ("fricrom-frames-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(kAsFeDir, dir);
  // CORD2C 7: origin (0.3, -0.2, 0), z along basic z, x along (1, 0.5, 0).
  FeModel geometry;
  CoordinateSystem c7{7, 0, {0.3, -0.2, 0}, {0.3, -0.2, 1}, {1.3, 0.3, 0}};
  c7.type = 'C';
  geometry.systems.push_back(c7);
  const BasicFrame frame(geometry);
  // The blades at basic (i, 0.5 i, 0); each node's x and y turned by its own angle.
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(6, 6);
  std::ostringstream grids;
  for (int i = 1; i <= 3; ++i) {
    const Eigen::Vector3d p(i, 0.5 * i, 0);
    const Eigen::Vector3d q = frame.Axes(7, p) * (p - Eigen::Vector3d(0.3, -0.2, 0));
    const double r = std::hypot(q[0], q[1]);
    // Coordinates in system 7 (r, theta, z): the radial direction's angle from its x axis.
    const Eigen::Matrix3d ax = frame.Axes(7, Eigen::Vector3d(1.3, 0.3, 0));
    const Eigen::Vector3d d = ax * (p - Eigen::Vector3d(0.3, -0.2, 0));
    const double theta = std::atan2(d[1], d[0]) * 180.0 / M_PI;
    ASSERT_LT((frame.ToBasic(7, {r, theta, 0}) - p).norm(), 1e-12);
    grids << "GRID*   " << LargeInt(i) << LargeInt(7) << LargeReal(r) << LargeReal(theta)
          << "\n*       " << LargeReal(0) << LargeInt(7) << "\n";
    t.block<2, 2>(2 * (i - 1), 2 * (i - 1)) = frame.Axes(7, p).topLeftCorner<2, 2>();
  }
  const auto read = [&](const std::string& file) {
    return Eigen::MatrixXd(ReadFe((kAsFeDir / file).string()).matrices.at(0).real);
  };
  std::ofstream pch(dir / "blades.pch");
  pch << "$ the lumped blades in cylindrical system 7 (CP = CD = 7)\n"
      << "CORD2C* " << LargeInt(7) << LargeInt(0) << LargeReal(0.3) << LargeReal(-0.2)
      << "\n*       " << LargeReal(0) << LargeReal(0.3) << LargeReal(-0.2) << LargeReal(1)
      << "\n*       " << LargeReal(1.3) << LargeReal(0.3) << LargeReal(0) << "\n"
      << grids.str();
  // u_basic = tᵀ u_local: A_local = t A_basic tᵀ.
  pch << LargeDmig("KAAX", t * read("blades.K.mtx") * t.transpose())
      << LargeDmig("MAAX", t * read("blades.M.mtx") * t.transpose())
      << LargeDmig("BAAX", t * read("blades.C.mtx") * t.transpose());
  pch.close();
  std::ifstream in(kAsFeDir / "case.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = toml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    toml.replace(at, from.size(), to);
  };
  replace("stiffness = \"blades.K.mtx\"", "stiffness = {file = \"blades.pch\", matrix = \"KAAX\"}");
  replace("mass = \"blades.M.mtx\"", "mass = {file = \"blades.pch\", matrix = \"MAAX\"}");
  replace("damping = \"blades.C.mtx\"", "damping = {file = \"blades.pch\", matrix = \"BAAX\"}");
  replace("dof_map = \"blades.dofs.csv\"\n", "");
  std::ofstream(dir / "case.toml") << toml;

  const Case basic = LoadCase((kAsFeDir / "case.toml").string());
  const Case local = LoadCase((dir / "case.toml").string());
  // The turned matrices differ from the basic ones as written (the test can fail) ...
  EXPECT_GT((t * read("blades.K.mtx") * t.transpose() - read("blades.K.mtx")).norm(), 1e5);
  // ... and come back to them.
  EXPECT_LT((local.model.stiffness - basic.model.stiffness).cwiseAbs().maxCoeff(), 1e-3);
  // The same free and full-stick modes.
  const ModalResult ma = StickSystemModes(basic.model), mb = StickSystemModes(local.model);
  ASSERT_EQ(ma.frequencies_hz.size(), mb.frequencies_hz.size());
  EXPECT_LT((ma.frequencies_hz - mb.frequencies_hz).cwiseAbs().maxCoeff(),
            1e-9 * ma.frequencies_hz.maxCoeff());
  const auto a = MakeBalance(basic.model, HbmOptions{1, 128}, basic.analysis.balance);
  const auto b = MakeBalance(local.model, HbmOptions{1, 128}, local.analysis.balance);
  const Eigen::Vector4d alpha(0.3, -0.5, 0.1, 0.9);
  const auto pa = SolveAtFrequencies(*a, alpha, {258.0, 266.0, 270.0}, FrfOptions{});
  const auto pb = SolveAtFrequencies(*b, alpha, {258.0, 266.0, 270.0}, FrfOptions{});
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(pb[i].status, SolverStatus::kConverged);
    EXPECT_NEAR(pb[i].amplitude, pa[i].amplitude, 1e-8 * pa[i].amplitude) << pa[i].freq_hz;
  }
  const BoundsResult ba = ComputeBounds(*a, 266.0, BoundsOptions{});
  const BoundsResult bb = ComputeBounds(*b, 266.0, BoundsOptions{});
  ASSERT_TRUE(ba.IsUsable() && bb.IsUsable());
  EXPECT_NEAR(bb.min.amplitude, ba.min.amplitude, 1e-8 * ba.min.amplitude);
  EXPECT_NEAR(bb.max.amplitude, ba.max.amplitude, 1e-8 * ba.max.amplitude);
  fs::remove_all(dir);
}

TEST(AssemblyFrames, AMultiMatrixFileNeedsTheMatrixNamed) {
  const fs::path dir =
      fs::temp_directory_path() / ("fricrom-frames-named-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy(fs::path(FRICROM_SOURCE_DIR) / "tests/data/extseout", dir / "se");
  std::ofstream(dir / "case.toml") << R"(schema = "fricrom-assembly-1"
units = "SI"
name = "named"
[[bodies]]
name = "se1"
stiffness = "se/inboard.op4"
mass = {file = "se/inboard.op4", matrix = "MXX"}
dof_map = "se/inboard.pch"
)";
  try {
    LoadCase((dir / "case.toml").string());
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("bodies[0].stiffness"), std::string::npos) << w;
    EXPECT_NE(w.find("KXX"), std::string::npos) << w;
    EXPECT_NE(w.find("matrix = \"NAME\""), std::string::npos) << w;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fricrom

namespace fricrom {
namespace {

// `rotate` turns a body's matrices into the assembly frame: a planar body (x and y only) turned
// about z needs no z, and its stiffness is T K Tᵀ with T the rotation per node. (The blades'
// stiffness made anisotropic first: an isotropic one would not see the rotation.)
TEST(AssemblyFrames, APlanarBodyRotatedInItsPlane) {
  const fs::path dir =
      fs::temp_directory_path() / ("fricrom-frames-rotate-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(kAsFeDir, dir);
  const auto edit = [&](const fs::path& file, const std::string& from, const std::string& to) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const size_t at = s.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    std::ofstream(file) << s;
  };
  edit(dir / "blades.K.mtx", "1 1 1000000", "1 1 2000000");
  const Case plain = LoadCase((dir / "case.toml").string());
  edit(dir / "case.toml", "dof_map = \"blades.dofs.csv\"\n",
       "dof_map = \"blades.dofs.csv\"\nrotate = {axis = [0.0, 0.0, 1.0], angle_deg = 90.0}\n");
  const Case turned = LoadCase((dir / "case.toml").string());
  // Rotation by 90 deg about z: x -> y, y -> -x.
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 3; ++i) t.block<2, 2>(2 * i, 2 * i) << 0, -1, 1, 0;
  const Eigen::MatrixXd k = plain.model.stiffness.topLeftCorner(6, 6);
  const Eigen::MatrixXd want = t * k * t.transpose();
  EXPECT_GT((want - k).cwiseAbs().maxCoeff(), 1e5);  // the rotation shows
  EXPECT_LT((turned.model.stiffness.topLeftCorner(6, 6) - want).cwiseAbs().maxCoeff(), 1e-6);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fricrom
