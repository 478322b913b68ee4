#include "linear/harmonic_receptance.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "linear/dense_lapack.h"

namespace fricrom {

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

// Row `row` of a real matrix times a complex vector.
std::complex<double> RowTimes(const Eigen::MatrixXd& a, Eigen::Index row,
                              const Eigen::VectorXcd& v) {
  return {a.row(row).dot(v.real()), a.row(row).dot(v.imag())};
}

}  // namespace

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
  g_complex_.resize(harmonics_ + 1);
  d_.resize(harmonics_ + 1);
  formed_at_.assign(harmonics_ + 1, std::numeric_limits<double>::quiet_NaN());
  g_formed_at_.assign(harmonics_ + 1, std::numeric_limits<double>::quiet_NaN());
  products_before_g_.assign(harmonics_ + 1, 0);
  if (method_ != ReceptanceMethod::kModal) return;
  // Symmetric parts: the matrices are symmetric up to round-off of the reduction.
  const Eigen::MatrixXd ks = 0.5 * (k_ + k_.transpose()), ms = 0.5 * (m_ + m_.transpose());
  if (Eigen::LLT<Eigen::MatrixXd>(ms).info() != Eigen::Success) {
    throw std::invalid_argument(
        "modal receptance: the mass matrix is not positive definite (massless DOFs?); use the "
        "dense receptance");
  }
  if (!dense::SymmetricGeneralizedEigen(ks, ms, &lambda_, &phi_)) {
    throw std::invalid_argument("modal receptance: the eigen-decomposition of (K, M) failed");
  }
  if (!(lambda_.minCoeff() > 1e-12 * std::max(lambda_.maxCoeff(), 1.0))) {
    throw std::invalid_argument(
        "modal receptance: K is not positive definite on M's modes (smallest eigenvalue " +
        std::to_string(lambda_.minCoeff()) + " rad^2/s^2): a free body is not held");
  }
  // Φ is M-orthonormal. The n³ products go through BLAS (dense_lapack.h).
  w_ = dense::Product(b_, false, phi_, false);
  mphi_ = dense::Product(ms, false, phi_, false);
  const Eigen::MatrixXd cs = 0.5 * (c_ + c_.transpose());
  const Eigen::MatrixXd cm =
      dense::Product(phi_, true, dense::Product(cs, false, phi_, false), false);
  modal_c_ = cm.diagonal();
  const double cmax = std::max(modal_c_.cwiseAbs().maxCoeff(), 1e-300);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      const double scale = std::max(std::sqrt(std::abs(modal_c_[i] * modal_c_[j])), 1e-12 * cmax);
      coupling_ = std::max(coupling_, std::abs(cm(i, j)) / scale);
    }
  }
}

void HarmonicReceptance::SetCyclicRows(Eigen::MatrixXd next, Eigen::VectorXd phase,
                                       Eigen::VectorXd stick) {
  if (method_ != ReceptanceMethod::kDense) {
    throw std::invalid_argument(
        "HarmonicReceptance: cyclic-symmetry sectors need the dense receptance "
        "(analysis.receptance = \"dense\"): the modes of the stuck sector differ per harmonic");
  }
  if (next.rows() != b_.rows() || next.cols() != b_.cols() || phase.size() != b_.rows() ||
      stick.size() != b_.rows() || omega_ >= 0.0) {
    throw std::invalid_argument(
        "HarmonicReceptance::SetCyclicRows: inconsistent sizes, or called "
        "after SetFrequency");
  }
  next_ = std::move(next);
  phase_ = std::move(phase);
  stick_ = std::move(stick);
}

Eigen::MatrixXd HarmonicReceptance::BlockB(int h) const {
  const int n = num_dofs(), nr = num_relative();
  Eigen::MatrixXd bh = Eigen::MatrixXd::Zero(2 * nr, 2 * n);
  bh.topLeftCorner(nr, n) = b_;
  bh.bottomRightCorner(nr, n) = b_;
  if (!cyclic()) return bh;
  // The next sector's coefficients (a, b) read delayed: (c a − s b, s a + c b), c, s of h·phase.
  const Eigen::ArrayXd c = (h * phase_.array()).cos() - 1.0, s = (h * phase_.array()).sin();
  bh.topLeftCorner(nr, n) += c.matrix().asDiagonal() * next_;
  bh.bottomRightCorner(nr, n) += c.matrix().asDiagonal() * next_;
  bh.topRightCorner(nr, n) = -(s.matrix().asDiagonal() * next_);
  bh.bottomLeftCorner(nr, n) = s.matrix().asDiagonal() * next_;
  return bh;
}

void HarmonicReceptance::SetFrequency(double omega, int harmonics) {
  const int top = harmonics < 0 ? harmonics_ : std::min(harmonics, harmonics_);
  omega_ = omega;
  for (int h = 0; h <= top; ++h) {
    const double at = formed_at_[h];
    if (at == omega || (h == 0 && !std::isnan(at))) continue;  // Z_0 = K: any ω
    FormHarmonic(h, omega);
  }
}

int HarmonicReceptance::Formed(int h) const {
  if (h < 0 || h > harmonics_) {
    throw std::logic_error("HarmonicReceptance: harmonic " + std::to_string(h) + " out of range");
  }
  if (std::isnan(formed_at_[h]) || (h > 0 && formed_at_[h] != omega_)) {
    throw std::logic_error("HarmonicReceptance: harmonic " + std::to_string(h) +
                           " is not formed at the current frequency (SetFrequency)");
  }
  return h;
}

void HarmonicReceptance::FormHarmonic(int h, double omega) {
  formed_at_[h] = omega;
  products_before_g_[h] = 0;
  if (method_ == ReceptanceMethod::kModal) {
    const double hw = h * omega;
    d_[h] = (lambda_.array().cast<std::complex<double>>() - hw * hw +
             std::complex<double>(0.0, 1.0) * hw * modal_c_.array())
                .inverse()
                .matrix();
    // Ĝ_h (h ≥ 1) is formed when first needed (FormG): a continuation in frequency evaluates
    // each ω with a few products only, through W (ModalProduct), where forming costs two
    // symmetric rank-n products (FE cascade: 8.5 ms per ω, 10 % of a bound curve's time).
    if (h == 0) FormG(0);
  } else {
    FormDense(h, omega);
    g_formed_at_[h] = omega;
    if (h > 0) ComplexForm(h);
  }
  UpdateFixedLoads(h);
}

void HarmonicReceptance::ComplexForm(int h) const {
  const int nr = num_relative();
  g_complex_[h].resize(nr, nr);
  g_complex_[h].real() = g_[h].topLeftCorner(nr, nr);
  g_complex_[h].imag() = g_[h].topRightCorner(nr, nr);
}

bool HarmonicReceptance::GFormed(int h) const { return g_formed_at_[Formed(h)] == formed_at_[h]; }

void HarmonicReceptance::FormG(int h) const {
  if (g_formed_at_[h] == formed_at_[h]) return;
  const int nr = num_relative();
  // G_h = W diag(d_h) Wᵀ is symmetric in its real and imaginary parts: WeightedGram forms each
  // for half a general product (G_0 = W Λ⁻¹ Wᵀ).
  if (h == 0) {
    g_[0] = dense::WeightedGram(w_, d_[0].real());
  } else {
    const Eigen::MatrixXd gr = dense::WeightedGram(w_, d_[h].real());
    const Eigen::MatrixXd gi = dense::WeightedGram(w_, d_[h].imag());
    g_[h].resize(2 * nr, 2 * nr);
    g_[h] << gr, gi, -gi, gr;
    ComplexForm(h);
  }
  g_formed_at_[h] = formed_at_[h];
}

void HarmonicReceptance::ModalProduct(int h, const Eigen::VectorXd& v, bool transposed,
                                      Eigen::VectorXd* out) const {
  const int nr = num_relative();
  // Ĝ v̂ = W (d ∘ (Wᵀ v̂)) with v̂ = c − i s, and Ĝᴴ v̂ with conj(d) (Ĝ is complex symmetric).
  Eigen::MatrixXd z(nr, 2);
  z.col(0) = v.head(nr);
  z.col(1) = -v.tail(nr);
  Eigen::MatrixXd t = dense::Product(w_, true, z, false);
  for (Eigen::Index k = 0; k < t.rows(); ++k) {
    const std::complex<double> d = transposed ? std::conj(d_[h][k]) : d_[h][k];
    const std::complex<double> u = d * std::complex<double>(t(k, 0), t(k, 1));
    t(k, 0) = u.real();
    t(k, 1) = u.imag();
  }
  const Eigen::MatrixXd w = dense::Product(w_, false, t, false);
  out->resize(2 * nr);
  out->head(nr) = w.col(0);
  out->tail(nr) = -w.col(1);
}

void HarmonicReceptance::GTimes(int h, const Eigen::VectorXd& v, bool transposed,
                                Eigen::VectorXd* out) const {
  const int nr = num_relative();
  if (Formed(h) == 0) {
    // The modal G_0 = W Λ⁻¹ Wᵀ is symmetric to the bit (WeightedGram): its upper triangle serves
    // both products at half the memory traffic (FE bound curve: 7 % of the time in these). Small
    // (lumped) systems keep the general product, and their results to the bit.
    if (method_ == ReceptanceMethod::kModal && nr >= dense::kLapackMinSize) {
      dense::SymmetricMatVec(g_[0], v, out);
    } else {
      dense::MatVec(g_[0], transposed, v, out);
    }
    return;
  }
  // Through W until this many products at one ω would have paid for forming Ĝ_h: a product
  // through W reads W twice (2 n_r n), Ĝ_h once (n_r²), and forming costs ~n_r² n.
  constexpr int kProductsBeforeForming = 32;
  if (!GFormed(h) && products_before_g_[h] < kProductsBeforeForming) {
    ++products_before_g_[h];
    ModalProduct(h, v, transposed, out);
    return;
  }
  FormG(h);
  // [[A, B], [−B, A]] [c; s] = [p; q]  <=>  (A + iB)(c − is) = p − iq; the transpose is Ĝᴴ.
  const Eigen::VectorXcd z =
      v.head(nr).cast<std::complex<double>>() -
      std::complex<double>(0.0, 1.0) * v.tail(nr).cast<std::complex<double>>();
  Eigen::VectorXcd w;
  dense::MatVec(g_complex_[h], transposed, z, &w);
  out->resize(2 * nr);
  out->head(nr) = w.real();
  out->tail(nr) = -w.imag();
}

Eigen::MatrixXcd HarmonicReceptance::GComplexColumns(int h, const std::vector<int>& cols) const {
  if (h < 1 || h > harmonics_) {
    throw std::invalid_argument("HarmonicReceptance::GComplexColumns: harmonic out of range");
  }
  FormG(Formed(h));
  const Eigen::MatrixXcd& g = g_complex_[h];
  Eigen::MatrixXcd out(g.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    if (cols[k] < 0 || cols[k] >= g.cols()) {
      throw std::invalid_argument("HarmonicReceptance::GComplexColumns: column out of range");
    }
    out.col(static_cast<Eigen::Index>(k)) = g.col(cols[k]);
  }
  return out;
}

void HarmonicReceptance::SetFixedLoads(std::vector<Eigen::VectorXd> loads, int dof) {
  const int n = num_dofs();
  if (static_cast<int>(loads.size()) != harmonics_ + 1 || dof < 0 || dof >= n) {
    throw std::invalid_argument(
        "HarmonicReceptance::SetFixedLoads: one load per harmonic and a "
        "DOF in range expected");
  }
  for (int h = 0; h <= harmonics_; ++h) {
    if (loads[h].size() == 0) loads[h] = Eigen::VectorXd::Zero(h == 0 ? n : 2 * n);
    if (loads[h].size() != (h == 0 ? n : 2 * n)) {
      throw std::invalid_argument("HarmonicReceptance::SetFixedLoads: load size of harmonic " +
                                  std::to_string(h));
    }
  }
  loads_ = std::move(loads);
  dof_ = dof;
  load_response_.assign(harmonics_ + 1, Eigen::VectorXd());
  load_response_at_.assign(harmonics_ + 1, std::numeric_limits<double>::quiet_NaN());
  load_relative_.assign(harmonics_ + 1, Eigen::VectorXd());
  load_at_dof_.assign(harmonics_ + 1, Eigen::VectorXd());
  dof_p_rows_.assign(harmonics_ + 1, Eigen::MatrixXd());
  modal_load_.assign(harmonics_ + 1, Eigen::VectorXcd());
  modal_load_q_.assign(harmonics_ + 1, Eigen::VectorXcd());
  if (method_ == ReceptanceMethod::kModal) {
    for (int h = 0; h <= harmonics_; ++h) {
      modal_load_[h] = phi_.transpose() * (h == 0 ? loads_[0].cast<std::complex<double>>().eval()
                                                  : ToComplex(loads_[h], n));
    }
  }
  // Every harmonic is formed again, with these loads, at the next SetFrequency.
  formed_at_.assign(harmonics_ + 1, std::numeric_limits<double>::quiet_NaN());
}

void HarmonicReceptance::UpdateFixedLoads(int h) {
  if (loads_.empty()) return;
  dof_p_rows_[h] = PRows(h, dof_);
  if (method_ == ReceptanceMethod::kDense) {
    load_response_[h] = Solve(h, loads_[h]);
    load_response_at_[h] = formed_at_[h];
    load_relative_[h] = Relative(h, load_response_[h]);
    const int n = num_dofs();
    load_at_dof_[h] = h == 0
                          ? Eigen::VectorXd::Constant(1, load_response_[h][dof_])
                          : Eigen::VectorXd{{load_response_[h][dof_], load_response_[h][n + dof_]}};
    return;
  }
  // Modal coordinates q = d_h ∘ Φᵀ f̂_h: the relative part W q and the DOF's Φ(dof, :) q cost
  // n n_r; the whole response Φ q (n²) only when asked for.
  const Eigen::VectorXcd& q = modal_load_q_[h] = d_[h].cwiseProduct(modal_load_[h]);
  const std::complex<double> at = RowTimes(phi_, dof_, q);
  if (h == 0) {
    load_relative_[0] = w_ * q.real();
    load_at_dof_[0] = Eigen::VectorXd::Constant(1, at.real());
  } else {
    load_relative_[h] = FromComplex(w_ * q);
    load_at_dof_[h] = Eigen::VectorXd{{at.real(), -at.imag()}};
  }
}

const Eigen::VectorXd& HarmonicReceptance::LoadResponse(int h) const {
  if (loads_.empty()) throw std::logic_error("HarmonicReceptance: no fixed loads (SetFixedLoads)");
  if (load_response_at_[Formed(h)] != formed_at_[h]) {
    load_response_[h] = h == 0 ? Eigen::VectorXd(phi_ * modal_load_q_[0].real())
                               : FromComplex(phi_ * modal_load_q_[h]);
    load_response_at_[h] = formed_at_[h];
  }
  return load_response_[h];
}

void HarmonicReceptance::OmegaDerivative(int h, const Eigen::VectorXd& fs,
                                         Eigen::VectorXd* relative, Eigen::VectorXd* at_dof) const {
  const int n = num_dofs(), nr = num_relative();
  Formed(h);
  if (loads_.empty()) throw std::logic_error("HarmonicReceptance: no fixed loads (SetFixedLoads)");
  if (h == 0) {
    *relative = Eigen::VectorXd::Zero(nr);
    *at_dof = Eigen::VectorXd::Zero(1);
    return;
  }
  if (method_ == ReceptanceMethod::kDense) {
    const Eigen::VectorXd xt = LoadResponse(h) - TimesP(h, fs);
    const Eigen::VectorXd dxt = -Solve(h, DzDomegaTimes(h, xt));
    *relative = Relative(h, dxt);
    *at_dof = Eigen::VectorXd{{dxt[dof_], dxt[n + dof_]}};
    return;
  }
  // x̂ = Φ q with q = d ∘ (Φᵀ f̂ − Wᵀ f̂s); Φᵀ (∂Ẑ/∂ω) Φ = diag(−2h²ω + i h c) (Φ M-orthonormal,
  // the damping modal), so ∂q/∂ω = −d ∘ (−2h²ω + i h c) ∘ q.
  const Eigen::VectorXcd wf = w_.transpose() * ToComplex(fs, nr);
  const Eigen::VectorXcd q = modal_load_q_[h] - d_[h].cwiseProduct(wf);
  Eigen::VectorXcd dq(q.size());
  for (Eigen::Index k = 0; k < q.size(); ++k) {
    const std::complex<double> dz(-2.0 * h * h * omega_, h * modal_c_[k]);
    dq[k] = -d_[h][k] * dz * q[k];
  }
  *relative = FromComplex(w_ * dq);
  const std::complex<double> at = RowTimes(phi_, dof_, dq);
  *at_dof = Eigen::VectorXd{{at.real(), -at.imag()}};
}

void HarmonicReceptance::FormDense(int h, double omega) {
  const int n = num_dofs(), nr = num_relative();
  Eigen::MatrixXd bt;
  if (h == 0) {
    lu_[0].Compute(k_);
    bt = b_.transpose();
  } else {
    const double hw = h * omega;
    const Eigen::MatrixXd kd = k_ - hw * hw * m_;
    Eigen::MatrixXd z(2 * n, 2 * n);
    z << kd, hw * c_, -hw * c_, kd;
    if (cyclic()) {
      // k holds harmonic 0's stick springs B_0ᵀ K_s B_0; harmonic h's are B_hᵀ K_s B_h.
      const Eigen::MatrixXd bh = BlockB(h);
      const Eigen::VectorXd ks2 = stick_.replicate(2, 1);
      const Eigen::MatrixXd k0 = b_.transpose() * stick_.asDiagonal() * b_;
      z += bh.transpose() * ks2.asDiagonal() * bh;
      z.topLeftCorner(n, n) -= k0;
      z.bottomRightCorner(n, n) -= k0;
      bt = bh.transpose();
    } else {
      bt.setZero(2 * n, 2 * nr);
      bt.topLeftCorner(n, nr) = b_.transpose();
      bt.bottomRightCorner(n, nr) = b_.transpose();
    }
    lu_[h].Compute(z);
  }
  p_[h] = lu_[h].Solve(bt);
  g_[h] = dense::Product(bt, true, p_[h], false);
}

Eigen::VectorXd HarmonicReceptance::Solve(int h, const Eigen::VectorXd& rhs) const {
  Formed(h);
  if (method_ == ReceptanceMethod::kDense) return lu_[h].Solve(rhs);
  if (h == 0) return phi_ * (lambda_.cwiseInverse().asDiagonal() * (phi_.transpose() * rhs));
  const Eigen::VectorXcd q = d_[h].asDiagonal() * (phi_.transpose() * ToComplex(rhs, num_dofs()));
  return FromComplex(phi_ * q);
}

Eigen::VectorXd HarmonicReceptance::TimesP(int h, const Eigen::VectorXd& v) const {
  Formed(h);
  if (method_ == ReceptanceMethod::kDense) return p_[h] * v;
  const int nr = num_relative();
  if (h == 0) return Solve(0, b_.transpose() * v);
  Eigen::VectorXd f(2 * num_dofs());
  f << b_.transpose() * v.head(nr), b_.transpose() * v.tail(nr);
  return Solve(h, f);
}

Eigen::VectorXd HarmonicReceptance::TransposeTimesP(int h, const Eigen::VectorXd& g) const {
  Formed(h);
  if (method_ == ReceptanceMethod::kDense) return p_[h].transpose() * g;
  if (h == 0) return Relative(0, Solve(0, g));
  // Z_h⁻ᵀ is the conjugate receptance (Φ diag(d̄) Φᵀ in complex form).
  const Eigen::VectorXcd q =
      d_[h].conjugate().asDiagonal() * (phi_.transpose() * ToComplex(g, num_dofs()));
  return Relative(h, FromComplex(phi_ * q));
}

Eigen::MatrixXd HarmonicReceptance::PRows(int h, int dof) const {
  Formed(h);
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
  if (cyclic()) return BlockB(h) * x;
  Eigen::VectorXd r(2 * nr);
  r.head(nr) = b_ * x.head(n);
  r.tail(nr) = b_ * x.tail(n);
  return r;
}

}  // namespace fricrom
