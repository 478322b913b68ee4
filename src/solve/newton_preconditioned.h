// Private: Newton whose linear steps may start from a caller's factorisation of a nearby Jacobian
// (e.g. the bound optimiser's last accepted point), so a warm-started solve needs no new LU when
// GMRES preconditioned with it converges.
#pragma once

#include <Eigen/Dense>
#include <memory>

#include "fricrom/solve.h"
#include "linear/dense_lapack.h"

namespace fricrom {

// M⁻¹ b = lu->Solve(b, transposed) with M ≈ the Jacobian; no preconditioner when lu is null.
struct NewtonPreconditioner {
  const dense::Lu* lu = nullptr;
  bool transposed = false;
};

// SolveNewton (solve.h) with `preconditioner` used for the GMRES steps until Newton factorises a
// Jacobian of its own (systems of at least options.krylov_min_size unknowns). If the solve
// factorised, *factorization (when given) receives its last LU, to precondition the next solve.
// `residual_at_start`, when given, is R(x) at the start, already evaluated by the caller (the
// bound optimiser's chord attempt): the solve does not evaluate it again.
NewtonSummary SolveNewtonPreconditioned(const SquareSystem& system, const NewtonOptions& options,
                                        NewtonPreconditioner preconditioner, Eigen::VectorXd* x,
                                        std::shared_ptr<const dense::Lu>* factorization = nullptr,
                                        const Eigen::VectorXd* residual_at_start = nullptr);

}  // namespace fricrom
