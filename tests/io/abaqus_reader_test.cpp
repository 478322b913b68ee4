// Abaqus *MATRIX GENERATE reader (ReadAbaqusMatrix): the real B33 beam sample checked against the
// hand-computed Euler-Bernoulli beam stiffness (after condensing Abaqus' internal node) and the
// beam's mass from its deck (model.inp), the COORDINATE form with its DOF-map sidecar, and bad
// input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
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

const std::string kAbaqusData = std::string(FRICROM_SOURCE_DIR) + "/tests/data/abaqus/";

using TempDir = fricrom::testing::ScratchDir;

// model.inp: one B33 element, nodes (0,0,0) and (3,0,0); *BEAM GENERAL SECTION
// A = 0.25, I11 = 1.5e-4, I12 = 0, I22 = 1.5e-4, J = 3e-4; E = 100e6, G = 80e6; density 100.
constexpr double kL = 3.0, kA = 0.25, kI = 1.5e-4, kJ = 3.0e-4, kE = 100.0e6, kG = 80.0e6,
                 kRho = 100.0;

// Textbook 3D Euler-Bernoulli beam along x, DOFs (u v w rx ry rz) at node 1 then node 2.
Eigen::MatrixXd BeamStiffness() {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(12, 12);
  const double L = kL, ea = kE * kA / L, gj = kG * kJ / L;
  const double b12 = 12 * kE * kI / (L * L * L), b6 = 6 * kE * kI / (L * L), b4 = 4 * kE * kI / L,
               b2 = 2 * kE * kI / L;
  const auto pair = [&](int i, int j, double v) {
    k(i, j) += v;
    if (i != j) k(j, i) += v;
  };
  pair(0, 0, ea), pair(6, 6, ea), pair(0, 6, -ea);
  pair(3, 3, gj), pair(9, 9, gj), pair(3, 9, -gj);
  // x-y plane: v (1, 7), rz (5, 11)
  pair(1, 1, b12), pair(7, 7, b12), pair(1, 7, -b12);
  pair(1, 5, b6), pair(1, 11, b6), pair(7, 5, -b6), pair(7, 11, -b6);
  pair(5, 5, b4), pair(11, 11, b4), pair(5, 11, b2);
  // x-z plane: w (2, 8), ry (4, 10)
  pair(2, 2, b12), pair(8, 8, b12), pair(2, 8, -b12);
  pair(2, 4, -b6), pair(2, 10, -b6), pair(8, 4, b6), pair(8, 10, b6);
  pair(4, 4, b4), pair(10, 10, b4), pair(4, 10, b2);
  return k;
}

// Indices of the 12 nodal DOFs (node 1, 2 x components 1..6) and of the internal ones.
void Partition(const FeMatrix& m, std::vector<int>& nodal, std::vector<int>& internal) {
  nodal.assign(12, -1);
  internal.clear();
  for (size_t i = 0; i < m.row_dofs.size(); ++i) {
    const DofId& d = m.row_dofs[i];
    if (d.node < 0) {
      internal.push_back(static_cast<int>(i));
    } else {
      ASSERT_TRUE((d.node == 1 || d.node == 2) && d.component >= 1 && d.component <= 6);
      nodal[static_cast<size_t>(6 * (d.node - 1) + d.component - 1)] = static_cast<int>(i);
    }
  }
  for (int i : nodal) ASSERT_GE(i, 0);
}

Eigen::MatrixXd Sub(const Eigen::MatrixXd& a, const std::vector<int>& r,
                    const std::vector<int>& c) {
  Eigen::MatrixXd s(r.size(), c.size());
  for (size_t i = 0; i < r.size(); ++i) {
    for (size_t j = 0; j < c.size(); ++j) s(i, j) = a(r[i], c[j]);
  }
  return s;
}

TEST(AbaqusReader, B33StiffnessMatchesHandComputedBeam) {
  const FeModel model = fricrom::ReadAbaqusMatrix(kAbaqusData + "model_STIF1.mtx");
  EXPECT_EQ(model.format, "abaqus");
  ASSERT_EQ(model.matrices.size(), 1u);
  const FeMatrix& k = model.matrices[0];
  EXPECT_EQ(k.name, "model_STIF1");
  EXPECT_TRUE(k.symmetric);
  // 2 nodes x 6 DOFs + internal node -1 with DOFs 1 and 2; sorted by signed label.
  ASSERT_EQ(k.rows, 14);
  EXPECT_EQ(k.row_dofs[0], (DofId{-1, 1}));
  EXPECT_EQ(k.row_dofs[1], (DofId{-1, 2}));
  EXPECT_EQ(k.row_dofs[2], (DofId{1, 1}));
  EXPECT_EQ(k.row_dofs[13], (DofId{2, 6}));
  EXPECT_EQ(k.col_dofs, k.row_dofs);
  // One triangle in the file (33 lines, 14 on the diagonal), both in storage.
  EXPECT_EQ(k.real.nonZeros(), 14 + 2 * (33 - 14));

  std::vector<int> nodal, internal;
  Partition(k, nodal, internal);
  ASSERT_EQ(internal.size(), 2u);
  const Eigen::MatrixXd kd(k.real);
  EXPECT_EQ((kd - kd.transpose()).norm(), 0.0);
  // Static condensation of the internal (axial) node gives the two-node beam.
  const Eigen::MatrixXd knn = Sub(kd, nodal, nodal), kni = Sub(kd, nodal, internal),
                        kii = Sub(kd, internal, internal);
  const Eigen::MatrixXd condensed = knn - kni * kii.ldlt().solve(kni.transpose());
  const Eigen::MatrixXd expected = BeamStiffness();
  EXPECT_LT((condensed - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff())
      << "condensed:\n"
      << condensed << "\nexpected:\n"
      << expected;
  // Bending and torsion terms do not involve the internal node: equal before condensation.
  EXPECT_NEAR(kd(nodal[1], nodal[1]), 12 * kE * kI / (kL * kL * kL), 1e-8);  // 12EI/L^3
  EXPECT_NEAR(kd(nodal[5], nodal[1]), 6 * kE * kI / (kL * kL), 1e-8);        // 6EI/L^2
  EXPECT_NEAR(kd(nodal[3], nodal[3]), kG * kJ / kL, 1e-8);                   // GJ/L
  EXPECT_NEAR(kd(nodal[11], nodal[5]), 2 * kE * kI / kL, 1e-8);              // 2EI/L
}

// Rigid-body motions (internal DOFs at rest): no force, and the mass they carry is the beam's.
TEST(AbaqusReader, B33MassCarriesTheBeamMass) {
  const FeMatrix k = fricrom::ReadAbaqusMatrix(kAbaqusData + "model_STIF1.mtx").matrices.at(0);
  const FeMatrix m = fricrom::ReadFe(kAbaqusData + "model_MASS1.mtx").matrices.at(0);
  ASSERT_EQ(m.row_dofs, k.row_dofs);
  EXPECT_TRUE(m.symmetric);
  std::vector<int> nodal, internal;
  Partition(m, nodal, internal);
  const Eigen::MatrixXd kd(k.real), md(m.real);
  const double mass = kRho * kA * kL;  // 75
  for (int dir = 0; dir < 3; ++dir) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(14);
    r(nodal[dir]) = r(nodal[6 + dir]) = 1.0;
    EXPECT_LT((kd * r).norm(), 1e-9 * kd.norm()) << "translation " << dir;
    EXPECT_NEAR(r.dot(md * r), mass, 1e-9 * mass) << "translation " << dir;
  }
  // Rotation about the beam axis: polar inertia rho * (I11 + I22) * L.
  Eigen::VectorXd rx = Eigen::VectorXd::Zero(14);
  rx(nodal[3]) = rx(nodal[9]) = 1.0;
  EXPECT_LT((kd * rx).norm(), 1e-9 * kd.norm());
  EXPECT_NEAR(rx.dot(md * rx), kRho * 2 * kI * kL, 1e-12);
  // Rotation about z through node 1: v = x, rz = 1.
  Eigen::VectorXd rz = Eigen::VectorXd::Zero(14);
  rz(nodal[7]) = kL;
  rz(nodal[5]) = rz(nodal[11]) = 1.0;
  EXPECT_LT((kd * rz).norm(), 1e-9 * kd.norm());
}

TEST(AbaqusReader, CoordinateFormWithDofSidecar) {
  TempDir dir;
  // Lower triangle of a 3x3 matrix, blanks or commas.
  const std::string p =
      dir.Write("spring_STIF1.mtx", "1 1 2.0\n2,1, -1.0\n2 2 2.0\n3 2 -1.0\n3 3 1.0\n");
  FeModel model = fricrom::ReadAbaqusMatrix(p);
  FeMatrix m = model.matrices.at(0);
  EXPECT_TRUE(m.symmetric);
  EXPECT_EQ(m.rows, 3);
  EXPECT_TRUE(m.row_dofs.empty());
  EXPECT_EQ(m.real.coeff(0, 1), -1.0);
  EXPECT_EQ(m.real.coeff(1, 0), -1.0);
  // With the sidecar `<name>.dof.csv`; it may list trailing DOFs without terms.
  dir.Write("spring_STIF1.dof.csv", "node,component\n10,1\n11,1\n12,1\n13,1\n");
  m = fricrom::ReadAbaqusMatrix(p).matrices.at(0);
  EXPECT_EQ(m.rows, 4);
  EXPECT_EQ(m.row_dofs[3], (DofId{13, 1}));
  EXPECT_EQ(m.col_dofs, m.row_dofs);
  // Both triangles present: a full (general) matrix, taken as written.
  const std::string g = dir.Write("g.mtx", "1 1 1.0\n1 2 5.0\n2 1 3.0\n2 2 1.0\n");
  m = fricrom::ReadAbaqusMatrix(g).matrices.at(0);
  EXPECT_FALSE(m.symmetric);
  EXPECT_EQ(m.real.coeff(0, 1), 5.0);
  EXPECT_EQ(m.real.coeff(1, 0), 3.0);
}

TEST(AbaqusReaderErrors, NanValue) {
  TempDir dir;
  const std::string p = dir.Write("nan.mtx", "1,1, 1,1, 1.0\n2,1, 1,1, nan\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(p); }, p, 2, "finite real number");
}

TEST(AbaqusReaderErrors, TruncatedLine) {
  TempDir dir;
  const std::string p = dir.Write("trunc.mtx", "1,1, 1,1, 1.0\n2,1, 1,1\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(p); }, p, 2, "truncated line");
}

TEST(AbaqusReaderErrors, DofOutOfRange) {
  TempDir dir;
  const std::string p = dir.Write("dof.mtx", "1,1, 1,1, 1.0\n1,99, 1,1, 1.0\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(p); }, p, 2, "degree of freedom 1..30");
}

TEST(AbaqusReaderErrors, DuplicateEntry) {
  TempDir dir;
  const std::string p = dir.Write("dup.mtx", "1,1, 1,1, 1.0\n1,1, 1,1, 2.0\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(p); }, p, 2, "given twice");
}

TEST(AbaqusReaderErrors, SidecarSmallerThanMatrix) {
  TempDir dir;
  const std::string p = dir.Write("s.mtx", "1 1 1.0\n3 3 1.0\n");
  const std::string csv = dir.Write("s.dof.csv", "node,component\n1,1\n2,1\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(p); }, csv, 0, "DOF map has 2 entries");
}

TEST(AbaqusReaderErrors, EmptyFileAndZeroIndex) {
  TempDir dir;
  const std::string e = dir.Write("e.mtx", "** only a comment\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(e); }, e, 0, "no matrix entries");
  const std::string z = dir.Write("z.mtx", "0 1 1.0\n");
  ExpectError([&] { fricrom::ReadAbaqusMatrix(z); }, z, 1, "index out of range");
}

}  // namespace
