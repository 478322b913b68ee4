// Private to src/reduction: lowest eigenpairs of K phi = lambda M phi by ARPACK (dsaupd/dseupd)
// in shift-invert mode 3, driven through a SymShiftInvertCholmodOp whose shift is already set.
#pragma once

#include <Eigen/Dense>
#include <string>

#include "cholmod_factor.h"

namespace fricrom::reduction_detail {

struct EigsResult {
  bool converged = false;
  std::string message;
  Eigen::VectorXd lambda;   // ascending
  Eigen::MatrixXd vectors;  // M-orthonormal (as returned by ARPACK), one column per lambda
  int restarts = 0;         // iparam[2] on exit
};

// nev eigenpairs nearest to the operator's shift (requires 1 <= nev <= n - 2). tol = 0: machine
// precision. Deterministic: the start vector comes from a fixed-seed generator.
EigsResult ShiftInvertEigs(SymShiftInvertCholmodOp& op, int nev, double tol, int max_iterations);

}  // namespace fricrom::reduction_detail
