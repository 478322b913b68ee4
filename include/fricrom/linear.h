// Linear analyses of a model: natural frequencies of the free and full-stick systems and linear
// forced responses, the two reference limits of the friction response.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"

namespace fricrom {

struct ModalResult {
  Eigen::VectorXd frequencies_hz;  // ascending
  Eigen::MatrixXd shapes;          // mass-normalised, one column per mode
  // Directions without mass (M positive semi-definite): no finite frequency, not among the modes.
  int massless = 0;
};

// Undamped modes of (K, M). M may be positive semi-definite (an exporter's superelement mass):
// its massless directions are counted, not listed. Throws std::invalid_argument if M has a
// negative eigenvalue beyond round-off.
ModalResult ComputeModes(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass);
ModalResult FreeSystemModes(const Model& model);  // blades only: model.free_dofs
// The receptance of the condensed balance where a case does not name one: modal where it is
// exact and pays — at least `min_dofs` DOFs, a positive definite mass and a damping that the
// full-stick modes diagonalise (|Φᵀ C Φ| off the diagonal ≤ 1e-8 of its largest entry, as for
// mass-proportional or modal damping of the whole assembly) — else dense.
ReceptanceMethod ChooseReceptance(const Model& model, int min_dofs = 500);
ModalResult StickSystemModes(const Model& model);  // all bodies, contacts as kn/kt springs

enum class LinearSystemKind { kFree, kStick };

// First-harmonic amplitude [m] of the response DOF of the linear free or full-stick system under
// the model's harmonic-1 loads, at each frequency [Hz]. kDense: one complex LU per frequency
// (exact); kModal: one eigen-decomposition, damping from diag(Φᵀ C Φ) (HarmonicReceptance).
std::vector<double> LinearResponseAmplitude(const Model& model, LinearSystemKind kind,
                                            const std::vector<double>& freqs_hz,
                                            ReceptanceMethod method = ReceptanceMethod::kDense);

}  // namespace fricrom
