// Local coordinate systems (Nastran CORD2R/C/S, GRID CP/CD) resolved to the basic frame: positions
// and directions against hand-computed values, matrices turned back to the basic frame, the real
// EXTSEOUT superelement (grid 11 in CD = 10) keeping its rigid-body modes, and the refusals.
#include "fricrom/basic_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"

namespace {

using fricrom::BasicFrame;
using fricrom::CoordinateSystem;
using fricrom::DofId;
using fricrom::FeMatrix;
using fricrom::FeModel;
using fricrom::FeNode;

const std::string kFixtures = std::string(FRICROM_SOURCE_DIR) + "/tests/data/";

CoordinateSystem System(int id, int ref, char type, Eigen::Vector3d a, Eigen::Vector3d b,
                        Eigen::Vector3d c) {
  CoordinateSystem s{id, ref, a, b, c};
  s.type = type;
  return s;
}

// Rectangular 1: origin (1, 2, 3), z along basic y, x along basic z (so y along basic x).
// Cylindrical 2 in system 1: origin at 1's (0, 0, 1), its axes those of 1.
// Spherical 3 in basic: origin 0, axes basic.
FeModel ThreeSystems() {
  FeModel m;
  m.source = "test";
  m.systems.push_back(System(1, 0, 'R', {1, 2, 3}, {1, 3, 3}, {1, 2, 4}));
  m.systems.push_back(System(2, 1, 'C', {0, 0, 1}, {0, 0, 2}, {1, 0, 1}));
  m.systems.push_back(System(3, 0, 'S', {0, 0, 0}, {0, 0, 1}, {1, 0, 0}));
  return m;
}

TEST(BasicFrame, PositionsInRectangularCylindricalAndSphericalSystems) {
  const BasicFrame f(ThreeSystems());
  // System 1: local (x, y, z) = basic origin + x e_z + y e_x + z e_y.
  EXPECT_LT((f.ToBasic(1, {1, 2, 3}) - Eigen::Vector3d(1 + 2, 2 + 3, 3 + 1)).norm(), 1e-14);
  // System 2 (r, theta, z) = (2, 90 deg, 0.5): in system 1 (0, 2, 1.5), basic (1 + 2, 2 + 1.5, 3).
  EXPECT_LT((f.ToBasic(2, {2, 90, 0.5}) - Eigen::Vector3d(3, 3.5, 3)).norm(), 1e-14);
  // System 3 (r, theta, phi) = (2, 90, 180): basic (-2, 0, 0); theta 0: on +z.
  EXPECT_LT((f.ToBasic(3, {2, 90, 180}) - Eigen::Vector3d(-2, 0, 0)).norm(), 1e-14);
  EXPECT_LT((f.ToBasic(3, {1.5, 0, 37}) - Eigen::Vector3d(0, 0, 1.5)).norm(), 1e-14);
  EXPECT_EQ(f.ToBasic(0, {4, 5, 6}), Eigen::Vector3d(4, 5, 6));
}

TEST(BasicFrame, DirectionsFollowThePoint) {
  const BasicFrame f(ThreeSystems());
  // Rectangular: the axes, wherever the point.
  Eigen::Matrix3d a1;
  a1 << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  EXPECT_LT((f.Axes(1, {9, 9, 9}) - a1).norm(), 1e-14);
  // Cylindrical at theta = 90 deg: r along system 1's y (basic z), theta along -x (basic -z ...).
  const Eigen::Vector3d p = f.ToBasic(2, {2, 90, 0.5});
  const Eigen::Matrix3d a2 = f.Axes(2, p);
  EXPECT_LT((a2.row(0).transpose() - Eigen::Vector3d(1, 0, 0)).norm(), 1e-14);   // 1's y
  EXPECT_LT((a2.row(1).transpose() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-14);  // -1's x
  EXPECT_LT((a2.row(2).transpose() - Eigen::Vector3d(0, 1, 0)).norm(), 1e-14);   // 1's z
  // The radial direction of any point is its offset from the axis, normalised (finite
  // differences of the position in r, theta, z give the three directions).
  for (int id : {2, 3}) {
    const Eigen::Vector3d q(1.3, 40, id == 2 ? 0.7 : 25);
    const Eigen::Matrix3d a = f.Axes(id, f.ToBasic(id, q));
    EXPECT_LT((a * a.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dq = Eigen::Vector3d::Zero();
      dq[k] = 1e-6;
      const Eigen::Vector3d d = (f.ToBasic(id, q + dq) - f.ToBasic(id, q - dq)).normalized();
      EXPECT_LT((d - a.row(k).transpose()).norm(), 1e-8) << "system " << id << " dir " << k;
    }
  }
}

TEST(BasicFrame, SystemsThatCannotBeUsedAreRefusedByName) {
  FeModel m = ThreeSystems();
  CoordinateSystem by_grids;
  by_grids.id = 7;
  by_grids.by_grids = true;
  m.systems.push_back(by_grids);
  m.systems.push_back(System(8, 9, 'R', {0, 0, 0}, {0, 0, 1}, {1, 0, 0}));
  m.systems.push_back(System(9, 8, 'R', {0, 0, 0}, {0, 0, 1}, {1, 0, 0}));
  // A cylindrical reference can turn three distinct points into a degenerate system.
  m.systems.push_back(System(10, 2, 'R', {0, 0, 0}, {0, 360, 0}, {1, 0, 0}));
  const BasicFrame f(m);
  const auto message = [&](int id) {
    try {
      f.ToBasic(id, {0, 0, 0});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(7).find("CORD2R"), std::string::npos) << message(7);
  EXPECT_NE(message(8).find("refers to itself"), std::string::npos) << message(8);
  EXPECT_NE(message(10).find("degenerate"), std::string::npos) << message(10);
  EXPECT_NE(message(11).find("not defined"), std::string::npos) << message(11);
}

// A two-node spring along basic (1, 1, 0) with masses: K and M of its 12 DOFs in basic.
FeMatrix Spring(const std::string& name, double k, double m) {
  FeMatrix a;
  a.name = name;
  a.rows = a.cols = 12;
  for (int64_t node : {1, 2}) {
    for (int c = 1; c <= 6; ++c) a.row_dofs.push_back({node, c});
  }
  a.col_dofs = a.row_dofs;
  const Eigen::Vector3d e = Eigen::Vector3d(1, 1, 0).normalized();
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(12, 12);
  const Eigen::Matrix3d kk = k * e * e.transpose();
  d.block<3, 3>(0, 0) = kk + m * Eigen::Matrix3d::Identity();
  d.block<3, 3>(6, 6) = kk + m * Eigen::Matrix3d::Identity();
  d.block<3, 3>(0, 6) = d.block<3, 3>(6, 0) = -kk;
  d.block<3, 3>(3, 3) = d.block<3, 3>(9, 9) = 0.5 * m * Eigen::Matrix3d::Identity();
  a.real = d.sparseView();
  return a;
}

TEST(BasicFrame, MatricesInLocalSystemsComeBackToTheBasicOnes) {
  FeModel basic;
  basic.matrices.push_back(Spring("K", 1e6, 0.0));
  // The same structure with node 1 in cylindrical system 2 (CP and CD) and node 2 in
  // rectangular 1: its matrix is Tᵀ-inverse of the basic one (u_local = T u_basic).
  FeModel local = ThreeSystems();
  const BasicFrame f(local);
  const Eigen::Vector3d p1(0.3, -0.4, 2.0), p2(1.0, 1.0, 0.0);
  const Eigen::Vector3d q1 = [&] {  // p1 in system 2 by Newton on ToBasic (no inverse is coded)
    Eigen::Vector3d q(1, 10, 0);
    for (int it = 0; it < 50; ++it) {
      Eigen::Matrix3d j;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[k] = 1e-7;
        j.col(k) = (f.ToBasic(2, q + d) - f.ToBasic(2, q - d)) / 2e-7;
      }
      q -= j.lu().solve(f.ToBasic(2, q) - p1);
    }
    return q;
  }();
  local.nodes = {FeNode{1, q1, 2, 2}, FeNode{2, p2, 0, 1}};
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(12, 12);
  const Eigen::Matrix3d a1 = f.Axes(2, p1), a2 = f.Axes(1, p2);
  for (int b : {0, 3}) {
    t.block<3, 3>(b, b) = a1;
    t.block<3, 3>(6 + b, 6 + b) = a2;
  }
  FeMatrix k_local = basic.matrices[0];
  // u_basic = Tᵀ u_local: K_local = T K_basic Tᵀ.
  k_local.real = (t * Eigen::MatrixXd(basic.matrices[0].real) * t.transpose()).sparseView();
  local.matrices.push_back(k_local);
  FeModel mass_file;  // a second file of the same structure: turned by the same nodes
  mass_file.matrices.push_back(k_local);
  mass_file.matrices[0].name = "M";
  fricrom::ExpressInBasic(&local, {&mass_file});
  const Eigen::MatrixXd want(basic.matrices[0].real);
  EXPECT_LT((Eigen::MatrixXd(local.matrices[0].real) - want).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((Eigen::MatrixXd(mass_file.matrices[0].real) - want).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((local.nodes[0].xyz - p1).norm(), 1e-12);
  EXPECT_EQ(local.nodes[0].position_system, 0);
  EXPECT_EQ(local.nodes[0].displacement_system, 0);
  EXPECT_EQ(local.nodes[1].xyz, p2);
  // Left as read, the local matrix differs from the basic one (the test can fail).
  EXPECT_GT((Eigen::MatrixXd(k_local.real) - want).cwiseAbs().maxCoeff(), 1e4);
}

TEST(BasicFrame, ANodeWithOnlySomeOfItsDirectionsCannotBeTurned) {
  FeModel m = ThreeSystems();
  m.source = "body.pch";
  m.nodes = {FeNode{5, {0, 0, 0}, 0, 1}};
  FeMatrix a;
  a.name = "KAAX";
  a.rows = a.cols = 2;
  a.row_dofs = a.col_dofs = {{5, 1}, {5, 2}};
  a.real = Eigen::MatrixXd::Identity(2, 2).sparseView();
  m.matrices.push_back(a);
  try {
    fricrom::ExpressInBasic(&m);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("node 5"), std::string::npos) << w;
    EXPECT_NE(w.find("KAAX"), std::string::npos) << w;
  }
  // A turn about the node's missing direction needs only the two it has (a 2D model).
  FeModel planar;
  planar.systems.push_back(System(4, 0, 'R', {0, 0, 0}, {0, 0, 1}, {1, 1, 0}));
  planar.nodes = {FeNode{5, {0, 0, 0}, 0, 4}};
  planar.matrices.push_back(a);
  planar.matrices[0].real.coeffRef(0, 1) = 0.5;
  planar.matrices[0].real.coeffRef(1, 0) = 0.5;
  EXPECT_NO_THROW(fricrom::ExpressInBasic(&planar));
}

// The EXTSEOUT superelement's grid 11 has CD = 10: its KXX holds that grid's rows in system 10.
// Turned to basic, the basic rigid-body translations and rotations stay in the null space of
// the boundary stiffness; left unturned they do not.
TEST(BasicFrame, ExtseoutSuperelementKeepsItsRigidModesInTheBasicFrame) {
  FeModel model = fricrom::ReadOp4(kFixtures + "extseout/inboard.op4");
  const FeModel punch = fricrom::ReadNastranPunch(kFixtures + "extseout/inboard.pch");
  for (FeMatrix& m : model.matrices) {
    if (m.rows == static_cast<int64_t>(punch.external_dofs.size()) && m.rows == m.cols) {
      m.row_dofs = m.col_dofs = punch.external_dofs;
    }
  }
  model.nodes = punch.nodes;
  model.systems = punch.systems;
  const int nb = 24;
  const auto residual = [&](const FeModel& m) {
    const Eigen::MatrixXd k = Eigen::MatrixXd(m.Find("KXX")->real).topLeftCorner(nb, nb);
    std::vector<DofId> dofs(punch.external_dofs.begin(), punch.external_dofs.begin() + nb);
    const Eigen::MatrixXd r = fricrom::RigidBodyModes(m, dofs, Eigen::Vector3d(600, 150, 150));
    return (k * r).norm() / (k.norm() * r.norm());
  };
  const double as_read = residual(model);  // RigidBodyModes honours CD itself
  FeModel unturned = model;
  for (FeNode& n : unturned.nodes) n.displacement_system = 0;
  const double wrong = residual(unturned);
  fricrom::ExpressInBasic(&model);
  for (const FeNode& n : model.nodes) EXPECT_EQ(n.displacement_system, 0);
  const double turned = residual(model);
  EXPECT_LT(as_read, 1e-8);
  EXPECT_LT(turned, 1e-8);
  EXPECT_GT(wrong, 1e3 * turned);
}

}  // namespace
