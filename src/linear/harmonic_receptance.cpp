#include "linear/harmonic_receptance.h"

#include <stdexcept>
#include <utility>

namespace fricrom {

HarmonicReceptance::HarmonicReceptance(Eigen::MatrixXd k, Eigen::MatrixXd m, Eigen::MatrixXd c,
                                       Eigen::MatrixXd b, int harmonics)
    : k_(std::move(k)),
      m_(std::move(m)),
      c_(std::move(c)),
      b_(std::move(b)),
      harmonics_(harmonics) {
  const auto n = k_.rows();
  if (k_.cols() != n || m_.rows() != n || m_.cols() != n || c_.rows() != n || c_.cols() != n ||
      b_.cols() != n || harmonics_ < 1) {
    throw std::invalid_argument("HarmonicReceptance: inconsistent sizes or harmonics < 1");
  }
  lu_.resize(harmonics_ + 1);
  p_.resize(harmonics_ + 1);
  g_.resize(harmonics_ + 1);
}

void HarmonicReceptance::SetFrequency(double omega) {
  if (omega == omega_) return;
  const int n = num_dofs(), nr = num_relative();
  for (int h = 0; h <= harmonics_; ++h) {
    Eigen::MatrixXd bt;
    if (h == 0) {
      lu_[0].compute(k_);
      bt = b_.transpose();
    } else {
      const double hw = h * omega;
      const Eigen::MatrixXd kd = k_ - hw * hw * m_;
      Eigen::MatrixXd z(2 * n, 2 * n);
      z << kd, hw * c_, -hw * c_, kd;
      lu_[h].compute(z);
      bt.setZero(2 * n, 2 * nr);
      bt.topLeftCorner(n, nr) = b_.transpose();
      bt.bottomRightCorner(n, nr) = b_.transpose();
    }
    p_[h] = lu_[h].solve(bt);
    g_[h] = bt.transpose() * p_[h];
  }
  omega_ = omega;
}

Eigen::VectorXd HarmonicReceptance::Solve(int h, const Eigen::VectorXd& rhs) const {
  return lu_[h].solve(rhs);
}

Eigen::VectorXd HarmonicReceptance::DzDomegaTimes(int h, const Eigen::VectorXd& x) const {
  const int n = num_dofs();
  if (h == 0) return Eigen::VectorXd::Zero(n);
  Eigen::VectorXd out(2 * n);
  const auto a = x.head(n), b = x.tail(n);
  // d/dω of [[K − h²ω²M, hωC], [−hωC, K − h²ω²M]]
  out.head(n) = -2.0 * h * h * omega_ * (m_ * a) + h * (c_ * b);
  out.tail(n) = -2.0 * h * h * omega_ * (m_ * b) - h * (c_ * a);
  return out;
}

Eigen::VectorXd HarmonicReceptance::Relative(int h, const Eigen::VectorXd& x) const {
  const int n = num_dofs(), nr = num_relative();
  if (h == 0) return b_ * x;
  Eigen::VectorXd r(2 * nr);
  r.head(nr) = b_ * x.head(n);
  r.tail(nr) = b_ * x.tail(n);
  return r;
}

}  // namespace fricrom
