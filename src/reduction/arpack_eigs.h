// Private to src/reduction: lowest eigenpairs of K phi = lambda M phi by ARPACK (dsaupd/dseupd,
// standard mode 1, largest nu) on the Cholesky-transformed operator C = L^-1 P M P^T L^-T of a
// CholeskyTransformOp whose shift is already set: nu = 1 / (lambda - sigma).
#pragma once

#include <Eigen/Dense>
#include <string>

#include "cholmod_factor.h"

namespace fricrom::reduction_detail {

struct EigsResult {
  bool converged = false;
  std::string message;
  Eigen::VectorXd lambda;   // ascending
  Eigen::MatrixXd vectors;  // M-orthonormal, one column per lambda
  int restarts = 0;         // iparam[2] on exit
  int infinite = 0;         // converged nu ~ 0 (massless directions, lambda infinite): dropped
};

// nev eigenpairs nearest to the operator's shift (requires 1 <= nev <= n - 2); fewer when some of
// them are infinite (nu <= 1e-13 max nu: dropped and counted). tol = 0: machine precision.
// Deterministic: the start vector comes from a fixed-seed generator.
EigsResult LowestEigs(CholeskyTransformOp& op, int nev, double tol, int max_iterations);

}  // namespace fricrom::reduction_detail
