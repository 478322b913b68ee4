#include "fricrom/reduced_loads.h"

#include <stdexcept>
#include <string>

namespace fricrom {

Eigen::VectorXd ProjectLoad(const ReducedModel& reduced, const Eigen::VectorXd& full_load) {
  const Eigen::Index nb = static_cast<Eigen::Index>(reduced.boundary_dofs.size());
  const Eigen::Index ni = static_cast<Eigen::Index>(reduced.interior_dofs.size());
  if (full_load.size() != nb + ni) {
    throw std::invalid_argument("ProjectLoad: load has " + std::to_string(full_load.size()) +
                                " entries, the reduced model's full model has " +
                                std::to_string(nb + ni) + " DOFs");
  }
  Eigen::VectorXd fb(nb), fi(ni);
  for (Eigen::Index k = 0; k < nb; ++k) fb[k] = full_load[reduced.boundary_dofs[k]];
  for (Eigen::Index k = 0; k < ni; ++k) fi[k] = full_load[reduced.interior_dofs[k]];
  const Eigen::Index nq = reduced.normal_modes.cols();
  Eigen::VectorXd out(nb + nq);
  out.head(nb) = fb;
  if (ni > 0 && reduced.constraint_modes.size() > 0) {
    out.head(nb) += reduced.constraint_modes.transpose() * fi;
  }
  if (nq > 0) out.tail(nq) = reduced.normal_modes.transpose() * fi;
  return out;
}

Eigen::MatrixXd UnitAccelerationLoads(const Eigen::SparseMatrix<double>& mass,
                                      const std::vector<DofId>& dofs, const ReducedModel& reduced) {
  const Eigen::Index n = mass.rows();
  if (mass.cols() != n || static_cast<Eigen::Index>(dofs.size()) != n) {
    throw std::invalid_argument("UnitAccelerationLoads: the mass matrix is " +
                                std::to_string(mass.rows()) + "x" + std::to_string(mass.cols()) +
                                " with a DOF map of " + std::to_string(dofs.size()) + " rows");
  }
  Eigen::MatrixXd out(reduced.stiffness.rows(), 3);
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (Eigen::Index r = 0; r < n; ++r) g[r] = dofs[r].component == k + 1 ? 1.0 : 0.0;
    out.col(k) = ProjectLoad(reduced, mass * g);
  }
  return out;
}

}  // namespace fricrom
