// Private: the condensed balance's Jacobian ∂R/∂x = W (I + G_h D) (condensed_system.h) applied
// without forming it. Why: GMRES steps with a reused LU (solve/newton.cpp) only need products, and
// G_h is block-diagonal over the harmonics while the dense Jacobian couples them all through D.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "fricrom/solve.h"

namespace fricrom {

class HarmonicReceptance;

// One contact's ∂F̃/∂r on its rows: F̃_T(j) = Σ_l tu(j,l) r_T(l) + tv(j,l) r_N(l),
// F̃_N(j) = Σ_l nv(j,l) r_N(l), over the 2H+1 coefficients (round-off of stuck contacts zeroed as
// in the dense Jacobian, so both routes agree).
struct EffectiveForceBlocks {
  Eigen::MatrixXd tu, tv, nv;
};

struct CondensedJacobianData {
  int harmonics = 1;
  int num_relative = 0;
  Eigen::VectorXd w;  // row weights of R_r
  double sy = 1.0;    // weight of R_y
  std::vector<int> row_t, row_n;
  std::vector<EffectiveForceBlocks> blocks;  // per contact
  std::shared_ptr<HarmonicReceptance> receptance;
  double omega = 0.0;
};

std::unique_ptr<JacobianOperator> MakeCondensedJacobian(CondensedJacobianData data);

}  // namespace fricrom
