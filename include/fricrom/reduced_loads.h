// Loads of the full FE model expressed on a Craig-Bampton reduced model. With u = T [u_b; q],
// T = [I 0; Ψ Φ] (boundary rows first, then the interior in ascending order), the work-equivalent
// reduced load of a full load f is Tᵀ f = [f_b + Ψᵀ f_i; Φᵀ f_i]. A body acceleration a
// (centrifugal preload, gravity) loads the body with f = M g_a (g_a: a at every node's
// translations), so its reduced load is Tᵀ M g_a: exact for the full model's mass, whether the
// body is free or clamped, which M_r [a_b; 0] is only for a free body.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "fricrom/fe_model.h"
#include "fricrom/reduction.h"

namespace fricrom {

// Tᵀ f for a full-model vector f (size = boundary + interior DOFs of `reduced`). Throws
// std::invalid_argument on a size mismatch.
Eigen::VectorXd ProjectLoad(const ReducedModel& reduced, const Eigen::VectorXd& full_load);

// Reduced loads of unit accelerations along x, y, z (columns 0..2) [N per m/s²]: Tᵀ M g_k with
// g_k = 1 at every DOF of component k + 1 (dofs: the full model's DOF map, rows of M).
Eigen::MatrixXd UnitAccelerationLoads(const Eigen::SparseMatrix<double>& mass,
                                      const std::vector<DofId>& dofs, const ReducedModel& reduced);

}  // namespace fricrom
