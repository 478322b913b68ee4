#include "gauss_newton_target.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace fricrom::bounds_detail {

bool GaussNewtonTarget(const Eigen::VectorXd& a, const Eigen::VectorXd& g, double phi,
                       const Eigen::VectorXd& jq, Eigen::VectorXd* target) {
  const Eigen::Index n = a.size();
  const double gn = g.norm(), qn = jq.norm();
  if (!(gn > 0.0) || !std::isfinite(gn)) return false;
  Eigen::MatrixXd rows(2, n);
  rows.row(0) = g.transpose() / gn;
  rows.row(1) = qn > 0.0 && std::isfinite(qn) ? Eigen::RowVectorXd(jq.transpose() / qn)
                                              : Eigen::RowVectorXd::Zero(n);
  const Eigen::Vector2d rhs(-2.0 * phi / gn, 0.0);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
  Eigen::Array<bool, Eigen::Dynamic, 1> fixed = Eigen::Array<bool, Eigen::Dynamic, 1>::Zero(n);
  for (int round = 0; round < 20; ++round) {
    Eigen::MatrixXd free_rows = rows;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (fixed[i]) free_rows.col(i).setZero();
    }
    const Eigen::Vector2d r = rhs - (rows - free_rows) * delta;
    Eigen::Matrix2d gram = free_rows * free_rows.transpose();
    const bool turns = gram(0, 0) * gram(1, 1) - gram(0, 1) * gram(1, 0) >
                       1e-8 * std::max(gram(0, 0) * gram(1, 1), 1e-300);
    Eigen::VectorXd d;
    if (turns) {
      d = free_rows.transpose() * gram.ldlt().solve(r);
    } else if (gram(0, 0) > 1e-24) {
      d = free_rows.row(0).transpose() * (r[0] / gram(0, 0));
    } else {
      return false;
    }
    bool clipped = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (fixed[i]) continue;
      const double to = a[i] + d[i];
      if (to > 1.0 || to < -1.0) {
        fixed[i] = true;
        delta[i] = std::clamp(to, -1.0, 1.0) - a[i];
        clipped = true;
      } else {
        delta[i] = d[i];
      }
    }
    if (!clipped) break;
  }
  *target = (a + delta).cwiseMax(-1.0).cwiseMin(1.0);
  return (*target - a).lpNorm<Eigen::Infinity>() > 1e-14;
}

}  // namespace fricrom::bounds_detail
