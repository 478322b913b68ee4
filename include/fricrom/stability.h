// Hill stability of a harmonic-balance solution: the Floquet exponents of the periodic motion
// from the quadratic eigenvalue problem of the linearised balance. A perturbation p(t) e^{λt} with
// p periodic (the same harmonics) of a solution of M q̈ + C q̇ + K q + f(q) = F(t) satisfies
//   (J + λ Δ1 + λ² Δ2) p̂ = 0,   Δ1 = 2 (∇ ⊗ M) + I ⊗ C,   Δ2 = I ⊗ M,
// with J the balance's Jacobian ∂R/∂x and ∇ the derivative operator on the coefficients (block
// h: (a, b) → (hω b, −hω a)). Its 2n(2H+1) eigenvalues are the 2n Floquet exponents, each repeated
// shifted by i h ω; the 2n whose eigenvectors' weight over e^{ikωt}, k = −H..H, is centred on
// k = 0 are kept (Lazarus & Thomas' symmetry criterion; ties by the smallest |Im λ|, the
// imaginary-part criterion, which alone fails where H is too small for a copy within ±ω/2). The
// solution is stable when every kept exponent has a negative real part. For contact laws that are
// not smooth (stick/slip switches, lift-off) the AFT Jacobian linearises along the sampled path:
// the method is then an approximation (docs/theory.md); time integration from the solution is the
// independent check (verify).
#pragma once

#include <Eigen/Dense>
#include <string>

#include "fricrom/bounds.h"
#include "fricrom/hbm_system.h"

namespace fricrom {

struct HillOptions {
  // A kept exponent with Re λ above this fraction of ω counts as growing: the solution is unstable.
  // (Round-off of the eigen-solve puts neutral exponents at |Re λ| ~ 1e-10 ω.)
  double growth_tolerance = 1e-7;
  bool IsValid(std::string* error) const;
};

struct HillResult {
  Eigen::VectorXcd exponents;  // the 2n kept Floquet exponents [1/s], by decreasing real part
  double max_real = 0.0;       // the largest Re λ [1/s]
  bool stable = false;
  std::string message;  // why, in a line
  std::string BriefReport() const;
};

// The Floquet exponents at a solution with Jacobian `jacobian` of a balance whose unknowns are the
// hbm_system.h layout [q̂0 | a1 | b1 | … | aH | bH] over n DOFs, with mass M (positive definite) and
// damping C. Throws std::invalid_argument on inconsistent sizes or a mass that is not definite.
HillResult HillStability(const Eigen::MatrixXd& jacobian, const Eigen::MatrixXd& mass,
                         const Eigen::MatrixXd& damping, int harmonics, double omega,
                         const HillOptions& options = {});

// The same at a solution x of `system` (full balance: every DOF) at (ω, α), with the static
// tangential stiffness kt of the contacts stuck over the whole period added to the Jacobian's
// static block: the balance prescribes their static tangential force by α (so ∂R/∂q̂0 lacks it),
// while a perturbation of a stuck contact is held by kt.
HillResult HillStability(const HbmSystem& system, const Eigen::VectorXd& x, double omega,
                         const Eigen::VectorXd& alpha, const HillOptions& options = {});

// Hill stability of both bounds of `b` at ω (their x are solutions of `system`): computed for the
// full balance (HbmSystem); for another balance each bound's stability says it was not computed.
void AssessBoundStability(const HarmonicBalance& system, double omega, BoundsResult* b,
                          const HillOptions& options = {});

}  // namespace fricrom
