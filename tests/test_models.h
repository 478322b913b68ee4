// Small models built by hand for the tests.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <string>

#include "fricrom/case_file.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/hbm_system.h"
#include "fricrom/model.h"

namespace fricrom::testing {

// The repository's meshes/ directory (with the trailing slash).
inline const std::string kMeshes = FRICROM_SOURCE_DIR "/meshes/";

inline Case LoadBaseline(const std::vector<ParameterOverride>& overrides = {}) {
  // One string built once: GCC 12 warns (-Warray-bounds, falsely) on `+` of the literals inlined.
  static const std::string path = FRICROM_SOURCE_DIR "/meshes/lumped3/baseline.toml";
  return LoadCase(path, overrides);
}

// The baseline lumped system at H = 1 with 128 time samples, built once per test program.
inline HbmSystem& BaselineH1() {
  static HbmSystem sys(LoadBaseline().model, HbmOptions{1, 128});
  return sys;
}

// A reproducible random matrix (Eigen's Random after std::srand(seed)), entries in [-1, 1].
inline Eigen::MatrixXd SeededRandom(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::srand(seed);
  return Eigen::MatrixXd::Random(rows, cols);
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
  ct.normal = Eigen::VectorXd{{0.0, 1.0}};
  ct.tangent = Eigen::VectorXd{{1.0, 0.0}};
  ct.kn = 0.0;
  ct.kt = kt;
  ct.mu = mu;
  ct.normal_preload = n0;
  model.contacts.push_back(ct);
  model.loads.push_back(HarmonicLoad{1, Eigen::VectorXd{{force, 0.0}}, Eigen::VectorXd::Zero(2)});
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
  ct.normal = Eigen::VectorXd{{1.0, 0.0}};
  ct.tangent = Eigen::VectorXd{{0.0, 1.0}};
  ct.kn = 3e4;
  ct.kt = 1e3;
  ct.mu = 0.0;
  model.contacts.push_back(ct);
  model.loads.push_back(HarmonicLoad{0, Eigen::VectorXd{{10.0, 0.0}}, Eigen::VectorXd::Zero(2)});
  model.loads.push_back(HarmonicLoad{1, Eigen::VectorXd{{force, 0.0}}, Eigen::VectorXd::Zero(2)});
  model.response_dof = 0;
  model.free_dofs = {0, 1};
  return model;
}

// An FE-like assembly with `pairs` node-to-node contacts: a "platform" strip of `pairs` nodes
// (3 DOFs each, neighbour springs, grounded like a blade root) and a "damper" strip of as many
// nodes (neighbour springs, weak grounding), node i of each strip in contact along z (normal,
// damper pressed down by a static load per node) with friction along x or y (alternating, so
// both in-plane directions carry friction). Harmonic forces at the platform's first quarter.
// Stick, slip and lift-off all occur over 800-1400 Hz at the default load.
inline Model ContactStrip(int pairs, double force = 40.0) {
  const int n = 6 * pairs;
  Model m;
  m.mass = Eigen::MatrixXd::Zero(n, n);
  m.stiffness = Eigen::MatrixXd::Zero(n, n);
  m.damping = Eigen::MatrixXd::Zero(n, n);
  const char* comp[] = {"x", "y", "z"};
  auto dof = [pairs](int strip, int node, int c) { return 3 * (strip * pairs + node) + c; };
  for (int strip = 0; strip < 2; ++strip) {
    for (int i = 0; i < pairs; ++i) {
      for (int c = 0; c < 3; ++c) {
        const int d = dof(strip, i, c);
        m.dof_names.push_back(std::string(strip ? "damper." : "platform.") + std::to_string(i) +
                              "." + comp[c]);
        m.mass(d, d) = strip ? 0.002 : 0.01;
        m.stiffness(d, d) += strip ? 2e3 : 4e5;  // grounding
        if (strip == 0) m.free_dofs.push_back(d);
        if (i + 1 < pairs) {  // neighbour spring
          const int e = dof(strip, i + 1, c);
          const double k = strip ? 5e5 : 2e6;
          m.stiffness(d, d) += k;
          m.stiffness(e, e) += k;
          m.stiffness(d, e) -= k;
          m.stiffness(e, d) -= k;
        }
      }
    }
  }
  m.damping = 2e-6 * m.stiffness;  // Rayleigh, stiffness-proportional
  HarmonicLoad stat{0, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  HarmonicLoad dyn{1, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  for (int i = 0; i < pairs; ++i) {
    Contact ct;
    ct.name = "pair" + std::to_string(i);
    ct.dofs_a = {dof(1, i, 0), dof(1, i, 1), dof(1, i, 2)};  // damper node (A) ...
    ct.dofs_b = {dof(0, i, 0), dof(0, i, 1), dof(0, i, 2)};  // ... on the platform node (B)
    ct.normal = Eigen::VectorXd{{0.0, 0.0, -1.0}};           // from A into B: down
    ct.tangent = i % 2 == 0 ? Eigen::VectorXd{{1.0, 0.0, 0.0}} : Eigen::VectorXd{{0.0, 1.0, 0.0}};
    ct.kn = 1e6;
    ct.kt = 8e5;
    ct.mu = 0.4;
    m.contacts.push_back(ct);
    stat.cos[dof(1, i, 2)] = -20.0;  // presses the damper down onto the platform
    if (i < std::max(1, pairs / 4)) {
      dyn.cos[dof(0, i, 0)] = force;
      dyn.cos[dof(0, i, 1)] = 0.5 * force;
      dyn.cos[dof(0, i, 2)] = 0.3 * force;
    }
  }
  m.loads = {stat, dyn};
  m.response_dof = dof(0, pairs / 2, 0);
  return m;
}

// Nonzeros of an evaluated [∂R/∂x | ∂R/∂α] that the balance's structural pattern leaves out
// (a sparse solver given the pattern would silently drop them), and the pattern's duplicates.
inline int EntriesOutsidePattern(const JacobianPattern& p, const HbmEvaluation& e) {
  const Eigen::Index nx = e.jacobian.rows(), n = nx + e.alpha_jacobian.cols();
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic> count =
      Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic>::Zero(nx, n);
  int bad = 0;
  for (int k = 0; k < p.nnz(); ++k) {
    const int r = p.rows[static_cast<size_t>(k)], c = p.cols[static_cast<size_t>(k)];
    if (r < 0 || r >= nx || c < 0 || c >= n || ++count(r, c) > 1) ++bad;
  }
  for (Eigen::Index c = 0; c < n; ++c) {
    for (Eigen::Index r = 0; r < nx; ++r) {
      const double v = c < nx ? e.jacobian(r, c) : e.alpha_jacobian(r, c - nx);
      if (v != 0.0 && count(r, c) == 0) ++bad;
    }
  }
  return bad;
}

}  // namespace fricrom::testing
