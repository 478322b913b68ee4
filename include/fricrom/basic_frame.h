// The basic frame of an FE model: node positions given in local coordinate systems (Nastran GRID
// CP) and DOF directions along local axes (GRID CD) expressed in the one frame the rest of
// fricrom works in. Rectangular, cylindrical and spherical systems (CORD2R/C/S), each given in its
// reference system, chained to any depth.
#pragma once

#include <Eigen/Dense>
#include <map>
#include <string>
#include <vector>

#include "fricrom/fe_model.h"

namespace fricrom {

class BasicFrame {
 public:
  // Resolves every system of `model` (errors are raised where a system is used).
  explicit BasicFrame(const FeModel& model);

  // Basic position of coordinates `p` in system `id` (0: basic; cylindrical r, theta [deg], z;
  // spherical r, theta [deg] from z, phi [deg]). Throws std::invalid_argument for a system that
  // is undefined, defined by grid points (CORD1*), in a reference loop or degenerate.
  Eigen::Vector3d ToBasic(int id, const Eigen::Vector3d& p) const;

  // Rows: the unit directions (x, y, z or r, theta, z or r, theta, phi) of system `id` at the basic
  // point `at`, in basic components, so that u_local = Axes(id, at) * u_basic.
  Eigen::Matrix3d Axes(int id, const Eigen::Vector3d& at) const;

 private:
  struct Resolved {
    char type = 'R';
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // rows: the system's x, y, z in basic
    std::string error;                                   // not empty: the system cannot be used
  };
  const Resolved& Get(int id) const;
  Resolved Resolve(int id, int depth) const;

  std::string source_;
  std::map<int, CoordinateSystem> cards_;
  std::map<int, Resolved> systems_;
};

// Puts `model` in the basic frame: node positions to basic coordinates and, for every node with a
// displacement system (CD != 0), the rows and columns of its components 1-3 and 4-6 in every
// matrix turned to basic directions (A -> T^T A T with u_local = T u_basic); afterwards every
// node has CP = CD = 0. `others` are models of the same structure read from other files (a mass
// OP4 beside a stiffness punch): their matrices turn with the same nodes. Throws
// std::invalid_argument naming the file and node where this cannot be done: a node with CD != 0
// and only some of a triple of directions in a matrix, CD = -1 (fluid grid), a matrix in
// coordinate form, or a system that cannot be used (BasicFrame::ToBasic).
void ExpressInBasic(FeModel* model, const std::vector<FeModel*>& others = {});

}  // namespace fricrom
