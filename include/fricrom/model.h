// The mechanical model fricrom solves: linear matrices, 1D friction contacts with varying normal
// load, harmonic excitation, a response DOF. Built from a case file (see case.h) or by hand.
// Units: SI throughout (m, kg, s, N, rad).
#pragma once

#include <Eigen/Dense>
#include <cmath>
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
  // Cyclic symmetry: side B is a node of the next sector, represented by this sector's copy of
  // it. The next sector's displacement along a direction d is (Rᵀd)ᵀ q_B of the copy, with R the
  // sector rotation, one sector later in the travelling wave: its harmonic h lags by h·phase_b.
  // normal_b, tangent_b = Rᵀ normal, Rᵀ tangent (empty: an ordinary contact, side B's directions
  // are normal and tangent); phase_b = 2π·EO/N [rad] (CyclicSectorPhase).
  Eigen::VectorXd normal_b;
  Eigen::VectorXd tangent_b;
  double phase_b = 0.0;

  bool cyclic() const { return normal_b.size() > 0 || phase_b != 0.0; }
  const Eigen::VectorXd& NormalB() const { return normal_b.size() > 0 ? normal_b : normal; }
  const Eigen::VectorXd& TangentB() const { return tangent_b.size() > 0 ? tangent_b : tangent; }
};

// One sector of a bladed disk of `sectors` identical sectors under an engine-order excitation:
// sector s's response is sector 0's delayed by s·φ/ω, φ = 2π·engine_order/sectors, so harmonic h
// of the next sector is harmonic h of this one rotated by h·φ (RotateHarmonic).
struct CyclicSymmetry {
  int sectors = 0;  // 0: no cyclic symmetry
  int engine_order = 0;
  double phase() const;  // φ [rad]
  // Throws std::invalid_argument unless sectors >= 2 and 0 <= engine_order <= sectors / 2.
  void Validate() const;
};

// The cos/sin coefficients (a, b) of one harmonic of a signal delayed by the phase θ:
// a cos(τ − θ) + b sin(τ − θ) = (a cos θ − b sin θ) cos τ + (a sin θ + b cos θ) sin τ.
inline void RotateHarmonic(double theta, double* a, double* b) {
  const double c = std::cos(theta), s = std::sin(theta), a0 = *a;
  *a = c * a0 - s * *b;
  *b = s * a0 + c * *b;
}

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
  // A sector of a cyclic model (its cyclic contacts carry phase_b); sectors = 0: not cyclic.
  CyclicSymmetry cyclic;

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
// For a cyclic sector this is harmonic 0's (the static state, nodal diameter 0).
Eigen::MatrixXd ContactStickStiffness(const Model& model);
// The same for harmonic h in the real block form on [cos; sin] (2n × 2n for h ≥ 1; n × n for
// h = 0): diag(K_s, K_s) for ordinary contacts; a cyclic contact couples cos and sin of side B
// through the phase h·phase_b (nodal diameter h·EO).
Eigen::MatrixXd ContactStickStiffness(const Model& model, int harmonic);
// Whether any contact couples to the next sector (cyclic symmetry).
bool HasCyclicContacts(const Model& model);
// Throws std::invalid_argument naming `who` when the model has cyclic contacts: for the routes
// whose linear part or time stepping cannot represent the delay between sectors.
void RequireNoCyclicContacts(const Model& model, const std::string& who);

}  // namespace fricrom
