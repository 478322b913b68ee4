#include "linear/harmonic_receptance.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <utility>

namespace fricrom {

HarmonicReceptance::HarmonicReceptance(Eigen::MatrixXd k, Eigen::MatrixXd m, Eigen::MatrixXd c,
                                       Eigen::MatrixXd b, int harmonics, ReceptanceMethod method)
    : k_(std::move(k)),
      m_(std::move(m)),
      c_(std::move(c)),
      b_(std::move(b)),
      harmonics_(harmonics),
      method_(method) {
  const auto n = k_.rows();
  if (k_.cols() != n || m_.rows() != n || m_.cols() != n || c_.rows() != n || c_.cols() != n ||
      b_.cols() != n || harmonics_ < 1) {
    throw std::invalid_argument("HarmonicReceptance: inconsistent sizes or harmonics < 1");
  }
  lu_.resize(harmonics_ + 1);
  p_.resize(harmonics_ + 1);
  g_.resize(harmonics_ + 1);
  d_.resize(harmonics_ + 1);
  if (method_ != ReceptanceMethod::kModal) return;
  // Symmetric parts: the matrices are symmetric up to round-off of the reduction.
  const Eigen::MatrixXd ks = 0.5 * (k_ + k_.transpose()), ms = 0.5 * (m_ + m_.transpose());
  if (Eigen::LLT<Eigen::MatrixXd>(ms).info() != Eigen::Success) {
    throw std::invalid_argument(
        "modal receptance: the mass matrix is not positive definite (massless DOFs?); use the "
        "dense receptance");
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(ks, ms);
  if (es.info() != Eigen::Success) {
    throw std::invalid_argument("modal receptance: the eigen-decomposition of (K, M) failed");
  }
  lambda_ = es.eigenvalues();
  if (!(lambda_.minCoeff() > 1e-12 * std::max(lambda_.maxCoeff(), 1.0))) {
    throw std::invalid_argument(
        "modal receptance: K is not positive definite on M's modes (smallest eigenvalue " +
        std::to_string(lambda_.minCoeff()) + " rad^2/s^2): a free body is not held");
  }
  phi_ = es.eigenvectors();  // M-orthonormal
  w_ = b_ * phi_;
  mphi_ = ms * phi_;
  const Eigen::MatrixXd cm = phi_.transpose() * (0.5 * (c_ + c_.transpose())) * phi_;
  modal_c_ = cm.diagonal();
  const double cmax = std::max(modal_c_.cwiseAbs().maxCoeff(), 1e-300);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      const double scale = std::max(std::sqrt(std::abs(modal_c_[i] * modal_c_[j])), 1e-12 * cmax);
      coupling_ = std::max(coupling_, std::abs(cm(i, j)) / scale);
    }
  }
}

void HarmonicReceptance::SetFrequency(double omega) {
  if (omega == omega_) return;
  if (method_ == ReceptanceMethod::kModal) {
    SetFrequencyModal(omega);
  } else {
    SetFrequencyDense(omega);
  }
  omega_ = omega;
}

void HarmonicReceptance::SetFrequencyDense(double omega) {
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
}

void HarmonicReceptance::SetFrequencyModal(double omega) {
  const int nr = num_relative();
  for (int h = 0; h <= harmonics_; ++h) {
    const double hw = h * omega;
    d_[h] = (lambda_.array().cast<std::complex<double>>() - hw * hw +
             std::complex<double>(0.0, 1.0) * hw * modal_c_.array())
                .inverse()
                .matrix();
    const Eigen::MatrixXd gr = w_ * d_[h].real().asDiagonal() * w_.transpose();
    if (h == 0) {
      g_[0] = gr;
      continue;
    }
    const Eigen::MatrixXd gi = w_ * d_[h].imag().asDiagonal() * w_.transpose();
    g_[h].resize(2 * nr, 2 * nr);
    g_[h] << gr, gi, -gi, gr;
  }
}

namespace {

// Complex amplitude x̂ = x_c − i x_s of a real [cos; sin] block (x = Re(x̂ e^{iωt})).
Eigen::VectorXcd ToComplex(const Eigen::VectorXd& v, int n) {
  return v.head(n).cast<std::complex<double>>() -
         std::complex<double>(0.0, 1.0) * v.tail(n).cast<std::complex<double>>();
}

Eigen::VectorXd FromComplex(const Eigen::VectorXcd& z) {
  Eigen::VectorXd v(2 * z.size());
  v << z.real(), -z.imag();
  return v;
}

}  // namespace

Eigen::VectorXd HarmonicReceptance::Solve(int h, const Eigen::VectorXd& rhs) const {
  if (method_ == ReceptanceMethod::kDense) return lu_[h].solve(rhs);
  if (h == 0) return phi_ * (lambda_.cwiseInverse().asDiagonal() * (phi_.transpose() * rhs));
  const Eigen::VectorXcd q = d_[h].asDiagonal() * (phi_.transpose() * ToComplex(rhs, num_dofs()));
  return FromComplex(phi_ * q);
}

Eigen::VectorXd HarmonicReceptance::TimesP(int h, const Eigen::VectorXd& v) const {
  if (method_ == ReceptanceMethod::kDense) return p_[h] * v;
  const int nr = num_relative();
  if (h == 0) return Solve(0, b_.transpose() * v);
  Eigen::VectorXd f(2 * num_dofs());
  f << b_.transpose() * v.head(nr), b_.transpose() * v.tail(nr);
  return Solve(h, f);
}

Eigen::VectorXd HarmonicReceptance::TransposeTimesP(int h, const Eigen::VectorXd& g) const {
  if (method_ == ReceptanceMethod::kDense) return p_[h].transpose() * g;
  if (h == 0) return Relative(0, Solve(0, g));
  // Z_h⁻ᵀ is the conjugate receptance (Φ diag(d̄) Φᵀ in complex form).
  const Eigen::VectorXcd q =
      d_[h].conjugate().asDiagonal() * (phi_.transpose() * ToComplex(g, num_dofs()));
  return Relative(h, FromComplex(phi_ * q));
}

Eigen::MatrixXd HarmonicReceptance::PRows(int h, int dof) const {
  const int n = num_dofs(), nr = num_relative();
  if (method_ == ReceptanceMethod::kDense) {
    if (h == 0) return p_[0].row(dof);
    Eigen::MatrixXd r(2, 2 * nr);
    r << p_[h].row(dof), p_[h].row(n + dof);
    return r;
  }
  if (h == 0)
    return (phi_.row(dof).cwiseProduct(lambda_.cwiseInverse().transpose())) * w_.transpose();
  const Eigen::RowVectorXcd a =
      (phi_.row(dof).cast<std::complex<double>>().cwiseProduct(d_[h].transpose())) * w_.transpose();
  Eigen::MatrixXd r(2, 2 * nr);
  r << a.real(), a.imag(), -a.imag(), a.real();
  return r;
}

Eigen::VectorXd HarmonicReceptance::DzDomegaTimes(int h, const Eigen::VectorXd& x) const {
  const int n = num_dofs();
  if (h == 0) return Eigen::VectorXd::Zero(n);
  Eigen::VectorXd out(2 * n);
  const auto a = x.head(n), b = x.tail(n);
  // d/dω of [[K − h²ω²M, hωC], [−hωC, K − h²ω²M]]
  out.head(n) = -2.0 * h * h * omega_ * (m_ * a) + h * DampingTimes(b);
  out.tail(n) = -2.0 * h * h * omega_ * (m_ * b) - h * DampingTimes(a);
  return out;
}

Eigen::VectorXd HarmonicReceptance::DampingTimes(const Eigen::VectorXd& x) const {
  if (method_ == ReceptanceMethod::kDense) return c_ * x;
  return mphi_ * modal_c_.cwiseProduct(mphi_.transpose() * x);
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
