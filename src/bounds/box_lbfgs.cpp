#include "box_lbfgs.h"

#include <vector>

namespace fricrom::bounds_detail {

void BoxLbfgs::Push(const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
  if (memory_ <= 0 || !s.allFinite() || !y.allFinite()) return;
  if (!(s.dot(y) > 1e-12 * s.norm() * y.norm())) return;
  s_.push_back(s);
  y_.push_back(y);
  if (static_cast<int>(s_.size()) > memory_) {
    s_.pop_front();
    y_.pop_front();
  }
}

Eigen::VectorXd BoxLbfgs::Direction(const Eigen::VectorXd& alpha, const Eigen::VectorXd& g,
                                    double fallback_step) const {
  const Eigen::Index n = alpha.size();
  // 1 on the free variables, 0 where a bound holds the variable (a projected step leaves it).
  Eigen::VectorXd free(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool held =
        (alpha[i] <= -1.0 + 1e-12 && g[i] > 0.0) || (alpha[i] >= 1.0 - 1e-12 && g[i] < 0.0);
    free[i] = held ? 0.0 : 1.0;
  }
  const int k = pairs();
  std::vector<double> a(k, 0.0), rho(k, 0.0);
  Eigen::VectorXd q = g.cwiseProduct(free);
  double gamma = 0.0;
  for (int i = k - 1; i >= 0; --i) {
    const Eigen::VectorXd si = s_[i].cwiseProduct(free), yi = y_[i].cwiseProduct(free);
    const double sy = si.dot(yi);
    if (!(sy > 1e-12 * si.norm() * yi.norm())) continue;
    rho[i] = 1.0 / sy;
    if (gamma == 0.0) gamma = sy / yi.squaredNorm();
    a[i] = rho[i] * si.dot(q);
    q -= a[i] * yi;
  }
  if (gamma == 0.0) return -fallback_step * q;  // no pair used: q is g on the free variables
  Eigen::VectorXd r = gamma * q;
  for (int i = 0; i < k; ++i) {
    if (rho[i] == 0.0) continue;
    const double b = rho[i] * y_[i].cwiseProduct(free).dot(r);
    r += s_[i].cwiseProduct(free) * (a[i] - b);
  }
  Eigen::VectorXd d = -r.cwiseProduct(free);
  if (!d.allFinite() || !(g.dot(d) < 0.0)) return -fallback_step * g;
  return d;
}

}  // namespace fricrom::bounds_detail
