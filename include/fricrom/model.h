// The mechanical model fricrom solves: linear matrices, 1D friction contacts with varying normal
// load, harmonic excitation, a response DOF. Built from a case file (see case.h) or by hand.
// Units: SI throughout (m, kg, s, N, rad).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace fricrom {

// One 1D friction contact with varying normal load (paper Eq. 3) between side A and side B.
// Relative displacements: v = normalᵀ(q_A − q_B) (positive = pressing), u = tangentᵀ(q_A − q_B).
// The contact force F = N·normal + T·tangent acts on B; −F acts on A.
struct Contact {
  std::string name;
  std::vector<int> dofs_a;      // DOF indices of side A along each space direction; −1 = ground
  std::vector<int> dofs_b;      // DOF indices of side B; −1 = ground
  Eigen::VectorXd normal;       // unit vector, pointing from A into B, same length as dofs_a
  Eigen::VectorXd tangent;      // unit vector, orthogonal to normal
  double kn = 0.0;              // normal contact stiffness [N/m]
  double kt = 0.0;              // tangential contact stiffness [N/m]
  double mu = 0.0;              // friction coefficient [-]
  double normal_preload = 0.0;  // N0 [N] added to kn·v (0 in the coupled static/dynamic approach)
};

// Harmonic force h: f(t) = cos·cos(hωt) + sin·sin(hωt) [N]; h = 0 is the static load (cos only).
struct HarmonicLoad {
  int harmonic = 1;
  Eigen::VectorXd cos;
  Eigen::VectorXd sin;
};

struct Model {
  std::vector<std::string> dof_names;  // e.g. "blade2.y"
  Eigen::MatrixXd mass;                // [kg]
  Eigen::MatrixXd damping;             // [N s/m] viscous
  Eigen::MatrixXd stiffness;           // [N/m]
  std::vector<Contact> contacts;
  std::vector<HarmonicLoad> loads;
  int response_dof = 0;
  std::vector<int> free_dofs;  // DOFs of the "free system" (blades without dampers)
  // α group of each contact (contacts sharing one α, e.g. one per FE interface); empty: one α
  // per contact.
  std::vector<int> alpha_group;

  int num_dofs() const { return static_cast<int>(dof_names.size()); }
  int num_alpha() const;  // α the solvers vary: groups, or contacts without groups
  // Node pairs in contact: contacts acting between the same DOFs (the two tangential
  // directions of one FE node pair) count once.
  int num_contact_pairs() const;
  // α per contact from the solvers' α (one per group); throws on a wrong size.
  Eigen::VectorXd ContactAlpha(const Eigen::VectorXd& alpha) const;
  // Throws std::invalid_argument naming the first inconsistency (sizes, indices, signs).
  void Validate() const;
  int DofIndex(const std::string& name) const;  // −1 if absent
};

// Linearised stiffness of every contact (kn·n nᵀ + kt·t tᵀ between A and B): the full-stick system.
Eigen::MatrixXd ContactStickStiffness(const Model& model);

}  // namespace fricrom
