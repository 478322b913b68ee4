// Small models built by hand for the tests.
#pragma once

#include <string>

#include "fricrom/case.h"
#include "fricrom/model.h"

namespace fricrom::testing {

inline Case LoadBaseline(const std::vector<ParameterOverride>& overrides = {}) {
  return LoadCase(std::string(FRICROM_SOURCE_DIR) + "/meshes/lumped3/baseline.toml", overrides);
}

// One mass on a spring and dashpot (x), with a Jenkins element (kt, constant normal load N0) to
// ground. The y DOF only carries the contact's normal direction (kn = 0 keeps N = N0).
inline Model JenkinsOscillator(double m, double k, double c, double kt, double mu, double n0,
                               double force) {
  Model model;
  model.dof_names = {"mass.x", "mass.y"};
  model.mass = Eigen::Matrix2d::Identity() * m;
  model.stiffness = Eigen::Vector2d(k, 1e3 * k).asDiagonal();
  model.damping = Eigen::Vector2d(c, c).asDiagonal();
  Contact ct;
  ct.name = "jenkins";
  ct.dofs_a = {0, 1};
  ct.dofs_b = {-1, -1};
  ct.normal = Eigen::Vector2d(0.0, 1.0);
  ct.tangent = Eigen::Vector2d(1.0, 0.0);
  ct.kn = 0.0;
  ct.kt = kt;
  ct.mu = mu;
  ct.normal_preload = n0;
  model.contacts.push_back(ct);
  model.loads.push_back(HarmonicLoad{1, Eigen::Vector2d(force, 0.0), Eigen::Vector2d::Zero()});
  model.response_dof = 0;
  model.free_dofs = {0, 1};
  return model;
}

// A mass pressed against a unilateral elastic stop (kn) by a static load: large vibrations lift
// off, the effective stiffness drops and the response curve bends over (two turning points).
inline Model BouncingOscillator(double force) {
  Model model;
  model.dof_names = {"mass.x", "mass.y"};
  model.mass = Eigen::Matrix2d::Identity();
  model.stiffness = Eigen::Vector2d(1e4, 1e4).asDiagonal();
  model.damping = Eigen::Vector2d(2.0, 2.0).asDiagonal();
  Contact ct;
  ct.name = "stop";
  ct.dofs_a = {0, 1};
  ct.dofs_b = {-1, -1};
  ct.normal = Eigen::Vector2d(1.0, 0.0);
  ct.tangent = Eigen::Vector2d(0.0, 1.0);
  ct.kn = 3e4;
  ct.kt = 1e3;
  ct.mu = 0.0;
  model.contacts.push_back(ct);
  model.loads.push_back(HarmonicLoad{0, Eigen::Vector2d(10.0, 0.0), Eigen::Vector2d::Zero()});
  model.loads.push_back(HarmonicLoad{1, Eigen::Vector2d(force, 0.0), Eigen::Vector2d::Zero()});
  model.response_dof = 0;
  model.free_dofs = {0, 1};
  return model;
}

}  // namespace fricrom::testing
