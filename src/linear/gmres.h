// Private: GMRES right-preconditioned by the LU of a nearby matrix. Why: consecutive Newton
// Jacobians of the condensed balance differ only in the blocks of the contacts whose state moved,
// so A M⁻¹ (M = an earlier Jacobian) is the identity plus a small or low-rank change and GMRES
// converges in a few matrix-vector products - far cheaper than a new dense LU
// (docs/decisions/0009-matrix-free-newton.md).
#pragma once

#include <Eigen/Dense>
#include <functional>

#include "linear/dense_lapack.h"

namespace fricrom::dense {

struct GmresResult {
  bool converged = false;
  int iterations = 0;              // matrix-vector products with A
  double relative_residual = 1.0;  // ‖b − A x‖ / ‖b‖ (GMRES' own recurrence)
};

// Solves A x = b from x = 0 by GMRES on A M⁻¹ z = b, x = M⁻¹ z, with M⁻¹ applied by the LU `m`
// (m.Solve(·, transpose_m)) and A = a, or aᵀ when transpose_a. Stops when the residual is
// ≤ tolerance·‖b‖ or after max_iterations products (no restart); on failure x holds the last
// iterate and `converged` is false.
GmresResult PreconditionedGmres(const Eigen::MatrixXd& a, bool transpose_a, const Lu& m,
                                bool transpose_m, const Eigen::VectorXd& b, double tolerance,
                                int max_iterations, Eigen::VectorXd* x);

// The same with A given by its products: apply(v, &out) sets out = A v.
using LinearMap = std::function<void(const Eigen::VectorXd&, Eigen::VectorXd*)>;
GmresResult PreconditionedGmres(const LinearMap& apply, const Lu& m, bool transpose_m,
                                const Eigen::VectorXd& b, double tolerance, int max_iterations,
                                Eigen::VectorXd* x);

}  // namespace fricrom::dense
