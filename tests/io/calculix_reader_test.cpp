// CalculiX MATRIXSTORAGE reader (ReadCalculix): the fixture written by ccx 2.20 for two C3D8
// bricks (tests/data/calculix/twobricks.inp) checked entry by entry against stiffness and mass
// matrices integrated here independently (trilinear hexahedra, 2x2x2 Gauss), and bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
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

const std::string kPrefix = std::string(FRICROM_SOURCE_DIR) + "/tests/data/calculix/twobricks";

using TempDir = fricrom::testing::ScratchDir;


// twobricks.inp: nodes 1..12 on the grid x in {0,1,2}, y, z in {0,1}; elements
// (1,2,5,4,7,8,11,10) and (2,3,6,5,8,9,12,11); E = 210000, nu = 0.3, rho = 7.8e-9; nodes 1, 4,
// 7, 10 (x = 0) clamped.
struct Mesh {
  std::map<int, Eigen::Vector3d> nodes;
  std::vector<std::array<int, 8>> elements;
};
Mesh TwoBricks() {
  Mesh m;
  int id = 1;
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) m.nodes[id++] = Eigen::Vector3d(x, y, z);
    }
  }
  m.elements = {{1, 2, 5, 4, 7, 8, 11, 10}, {2, 3, 6, 5, 8, 9, 12, 11}};
  return m;
}

// Global stiffness and consistent mass, DOF 3 * (node - 1) + direction - 1.
void Integrate(const Mesh& mesh, Eigen::MatrixXd& k, Eigen::MatrixXd& m) {
  const double e = 210000.0, nu = 0.3, rho = 7.8e-9;
  const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
  d.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) d(i, i) += 2 * mu, d(3 + i, 3 + i) = mu;
  const int n = 3 * static_cast<int>(mesh.nodes.size());
  k = Eigen::MatrixXd::Zero(n, n);
  m = Eigen::MatrixXd::Zero(n, n);
  const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                               {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  for (const auto& el : mesh.elements) {
    Eigen::Matrix<double, 8, 3> x;
    for (int a = 0; a < 8; ++a) x.row(a) = mesh.nodes.at(el[a]).transpose();
    Eigen::MatrixXd ke = Eigen::MatrixXd::Zero(24, 24), me = Eigen::MatrixXd::Zero(24, 24);
    for (int p = 0; p < 8; ++p) {
      const double xi[3] = {corner[p][0] * g, corner[p][1] * g, corner[p][2] * g};
      Eigen::Matrix<double, 8, 1> shape;
      Eigen::Matrix<double, 8, 3> dn;  // dN/dxi
      for (int a = 0; a < 8; ++a) {
        const double f0 = 1 + corner[a][0] * xi[0], f1 = 1 + corner[a][1] * xi[1],
                     f2 = 1 + corner[a][2] * xi[2];
        shape(a) = f0 * f1 * f2 / 8;
        dn(a, 0) = corner[a][0] * f1 * f2 / 8;
        dn(a, 1) = corner[a][1] * f0 * f2 / 8;
        dn(a, 2) = corner[a][2] * f0 * f1 / 8;
      }
      const Eigen::Matrix3d jac = dn.transpose() * x;  // d(x)/d(xi)
      const double det = jac.determinant();
      const Eigen::Matrix<double, 8, 3> dx = dn * jac.inverse().transpose();  // dN/dx
      Eigen::Matrix<double, 6, 24> b = Eigen::Matrix<double, 6, 24>::Zero();
      for (int a = 0; a < 8; ++a) {
        for (int i = 0; i < 3; ++i) b(i, 3 * a + i) = dx(a, i);
        b(3, 3 * a + 0) = dx(a, 1), b(3, 3 * a + 1) = dx(a, 0);  // gamma_xy
        b(4, 3 * a + 1) = dx(a, 2), b(4, 3 * a + 2) = dx(a, 1);  // gamma_yz
        b(5, 3 * a + 0) = dx(a, 2), b(5, 3 * a + 2) = dx(a, 0);  // gamma_zx
      }
      ke += b.transpose() * d * b * det;
      for (int a = 0; a < 8; ++a) {
        for (int c = 0; c < 8; ++c) {
          for (int i = 0; i < 3; ++i) me(3 * a + i, 3 * c + i) += rho * shape(a) * shape(c) * det;
        }
      }
    }
    for (int a = 0; a < 8; ++a) {
      for (int c = 0; c < 8; ++c) {
        k.block<3, 3>(3 * (el[a] - 1), 3 * (el[c] - 1)) += ke.block<3, 3>(3 * a, 3 * c);
        m.block<3, 3>(3 * (el[a] - 1), 3 * (el[c] - 1)) += me.block<3, 3>(3 * a, 3 * c);
      }
    }
  }
}

TEST(CalculixReader, TwoBricksMatchIndependentIntegration) {
  const FeModel model = fricrom::ReadCalculix(kPrefix);
  EXPECT_EQ(model.format, "calculix");
  const FeMatrix* k = model.Find("stiffness");
  const FeMatrix* m = model.Find("MASS");
  ASSERT_NE(k, nullptr);
  ASSERT_NE(m, nullptr);
  // The .dof map: the 8 free nodes x 3 directions; clamped nodes 1, 4, 7, 10 are absent.
  ASSERT_EQ(k->rows, 24);
  ASSERT_EQ(k->row_dofs.size(), 24u);
  EXPECT_EQ(k->row_dofs[0], (DofId{2, 1}));
  for (const DofId& d : k->row_dofs) {
    EXPECT_TRUE(d.node != 1 && d.node != 4 && d.node != 7 && d.node != 10);
  }
  EXPECT_EQ(m->row_dofs, k->row_dofs);
  EXPECT_TRUE(k->symmetric);
  EXPECT_TRUE(m->symmetric);
  // Upper triangle in the files (300 lines each: 24 * 25 / 2), both in storage.
  EXPECT_EQ(k->real.nonZeros(), 24 * 24);

  Eigen::MatrixXd kref, mref;
  Integrate(TwoBricks(), kref, mref);
  const Eigen::MatrixXd kd(k->real), md(m->real);
  const double kscale = kref.cwiseAbs().maxCoeff(), mscale = mref.cwiseAbs().maxCoeff();
  for (int i = 0; i < 24; ++i) {
    for (int j = 0; j < 24; ++j) {
      const DofId a = k->row_dofs[static_cast<size_t>(i)], b = k->row_dofs[static_cast<size_t>(j)];
      const auto g = [](const DofId& x) {
        return static_cast<int>(3 * (x.node - 1) + x.component - 1);
      };
      EXPECT_NEAR(kd(i, j), kref(g(a), g(b)), 1e-11 * kscale) << i << "," << j;
      EXPECT_NEAR(md(i, j), mref(g(a), g(b)), 1e-11 * mscale) << i << "," << j;
    }
  }
  // Hand check of one term: node 2, x: two unit cubes, each (lambda + 4 mu) / 9.
  const double lambda = 210000.0 * 0.3 / (1.3 * 0.4), mu = 210000.0 / 2.6;
  EXPECT_NEAR(kd(0, 0), 2 * (lambda + 4 * mu) / 9, 1e-8);
  EXPECT_NEAR(md(0, 0), 2 * 7.8e-9 / 27, 1e-22);
}

TEST(CalculixReader, ReadFeFromAnyOfTheThreeFiles) {
  for (const char* ext : {".sti", ".mas", ".dof"}) {
    const FeModel model = fricrom::ReadFe(kPrefix + ext);
    EXPECT_EQ(model.format, "calculix");
    EXPECT_EQ(model.matrices.size(), 2u);
  }
}

TEST(CalculixReader, StiffnessOnly) {
  TempDir dir;
  dir.Write("k.dof", "1.1\n1.2\n");
  dir.Write("k.sti", "1 1 2.0\n1 2 -1.0\n2 2 2.0\n");
  const FeModel model = fricrom::ReadCalculix(dir.Path("k"));
  ASSERT_EQ(model.matrices.size(), 1u);
  EXPECT_EQ(model.matrices[0].real.coeff(1, 0), -1.0);
}

TEST(CalculixReaderErrors, MissingDofFile) {
  TempDir dir;
  dir.Write("k.sti", "1 1 2.0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, dir.Path("k.dof"), 0,
              "missing .dof file");
}

TEST(CalculixReaderErrors, IndexOutOfRange) {
  TempDir dir;
  dir.Write("k.dof", "1.1\n1.2\n");
  const std::string sti = dir.Write("k.sti", "1 1 2.0\n1 3 -1.0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, sti, 2, "index out of range");
}

TEST(CalculixReaderErrors, InfValue) {
  TempDir dir;
  dir.Write("k.dof", "1.1\n");
  dir.Write("k.sti", "1 1 2.0\n");
  const std::string mas = dir.Write("k.mas", "1 1 inf\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, mas, 1, "finite real number");
}

TEST(CalculixReaderErrors, BothTriangles) {
  TempDir dir;
  dir.Write("k.dof", "1.1\n1.2\n");
  const std::string sti = dir.Write("k.sti", "1 1 2.0\n1 2 -1.0\n2 1 -1.0\n2 2 2.0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, sti, 3, "in both triangles");
}

TEST(CalculixReaderErrors, MalformedDofLineAndTruncatedEntry) {
  TempDir dir;
  const std::string dof = dir.Write("a.dof", "1.1\n1-2\n");
  dir.Write("a.sti", "1 1 2.0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("a")); }, dof, 2, "node.direction");
  dir.Write("b.dof", "1.1\n1.1\n");
  dir.Write("b.sti", "1 1 2.0\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("b")); }, dir.Path("b.dof"), 2, "listed twice");
  dir.Write("c.dof", "1.1\n1.2\n");
  const std::string sti = dir.Write("c.sti", "1 1 2.0\n2 2\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("c")); }, sti, 2, "truncated line");
}

TEST(CalculixReaderErrors, NoMatrixFiles) {
  TempDir dir;
  dir.Write("k.dof", "1.1\n");
  ExpectError([&] { fricrom::ReadCalculix(dir.Path("k")); }, dir.Path("k"), 0,
              "no CalculiX matrix files");
}

}  // namespace
