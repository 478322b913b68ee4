#include "hbm/condensed_jacobian.h"

#include <complex>
#include <stdexcept>
#include <utility>
#include <vector>

#include "linear/dense_lapack.h"
#include "linear/harmonic_receptance.h"

namespace fricrom {
namespace {

class CondensedJacobian final : public JacobianOperator {
 public:
  explicit CondensedJacobian(CondensedJacobianData d) : d_(std::move(d)) {
    nh_ = 2 * d_.harmonics + 1;
    bs_ = d_.num_relative + 1;
  }

  void Apply(const Eigen::VectorXd& v, bool transposed, Eigen::VectorXd* out) const override {
    if (v.size() != nh_ * bs_) throw std::invalid_argument("CondensedJacobian: wrong size");
    // G_h of this ω (a no-op unless ω moved)
    d_.receptance->SetFrequency(d_.omega, d_.harmonics);
    if (compact_.empty()) CompactReceptances();
    if (transposed) {
      ApplyTransposed(v, out);
    } else {
      ApplyDirect(v, out);
    }
  }

 private:
  int Idx(int coefficient, int row) const { return coefficient * bs_ + row; }
  // Coefficients of harmonic h in the layout [c0, a1, b1, ...].
  static int FirstCoefficient(int h) { return h == 0 ? 0 : 2 * h - 1; }
  static int NumCoefficients(int h) { return h == 0 ? 1 : 2; }

  // Ĝ_h (h ≥ 1) on the rows whose force coefficients of harmonic h depend on r at all. A fully
  // stuck contact's forces are linear in r there, so its F̃ = F − k_s u has no harmonics and D's
  // rows vanish (exactly: EffectiveBlocks zeroes the round-off): D r is zero on those rows, and the
  // transposed product needs Ĝ_hᴴ s only on the others. With ~70 % of the laws stuck at the
  // bounds most rows drop out (10-point FE segment 155.1 → 143.3 s); where fewer than a quarter
  // do, the full Ĝ_h is used.
  struct CompactReceptance {
    bool used = false;  // false: the full product
    std::vector<int> rows;
    Eigen::MatrixXcd g;  // Ĝ_h(:, rows)
  };

  void CompactReceptances() const {
    const int nr = d_.num_relative;
    compact_.resize(d_.harmonics + 1);
    for (int h = 1; h <= d_.harmonics; ++h) {
      // Not yet formed at this ω (a continuation in frequency): the products go through the
      // modes, which forming Ĝ_h for the copy would cost more than.
      if (!d_.receptance->GFormed(h)) continue;
      std::vector<char> on(nr, 0);
      for (size_t c = 0; c < d_.blocks.size(); ++c) {
        const EffectiveForceBlocks& b = d_.blocks[c];
        for (int j = FirstCoefficient(h); j < FirstCoefficient(h) + NumCoefficients(h); ++j) {
          on[d_.row_t[c]] |= !b.tu.row(j).isZero(0.0) || !b.tv.row(j).isZero(0.0);
          on[d_.row_n[c]] |= !b.nv.row(j).isZero(0.0);
        }
      }
      std::vector<int> rows;
      for (int i = 0; i < nr; ++i) {
        if (on[i]) rows.push_back(i);
      }
      if (4 * rows.size() > 3 * static_cast<size_t>(nr)) continue;  // the copy would not pay
      compact_[h].g = d_.receptance->GComplexColumns(h, rows);
      compact_[h].rows = std::move(rows);
      compact_[h].used = true;
    }
  }

  // G_h q (direct) or G_hᵀ q on the rows compact_[h] keeps (others left zero), h ≥ 1, as GTimes.
  void CompactTimes(int h, const double* q, bool transposed, Eigen::VectorXd* out) const {
    const int nr = d_.num_relative;
    const CompactReceptance& cp = compact_[h];
    const auto na = static_cast<Eigen::Index>(cp.rows.size());
    const std::complex<double> i(0.0, 1.0);
    out->setZero(2 * nr);
    if (!transposed) {
      Eigen::VectorXcd& z = z_;
      z.resize(na);
      for (Eigen::Index k = 0; k < na; ++k) z[k] = q[cp.rows[k]] - i * q[nr + cp.rows[k]];
      dense::MatVec(cp.g, false, z, &w_);
      out->head(nr) = w_.real();
      out->tail(nr) = -w_.imag();
      return;
    }
    Eigen::VectorXcd& z = z_;
    z.resize(nr);
    for (int k = 0; k < nr; ++k) z[k] = q[k] - i * q[nr + k];
    dense::MatVec(cp.g, true, z, &w_);
    for (Eigen::Index k = 0; k < na; ++k) {
      (*out)[cp.rows[k]] = w_[k].real();
      (*out)[nr + cp.rows[k]] = -w_[k].imag();
    }
  }

  // J v = W (v + [G_h; P_h] D r) with r the relative part of v.
  void ApplyDirect(const Eigen::VectorXd& v, Eigen::VectorXd* out) const {
    const int nr = d_.num_relative;
    Eigen::MatrixXd& q = q_;  // D r, column = coefficient
    q.setZero(nr, nh_);
    Eigen::VectorXd rt(nh_), rn(nh_);
    for (size_t c = 0; c < d_.blocks.size(); ++c) {
      const EffectiveForceBlocks& b = d_.blocks[c];
      const int t = d_.row_t[c], n = d_.row_n[c];
      for (int l = 0; l < nh_; ++l) {
        rt[l] = v[Idx(l, t)];
        rn[l] = v[Idx(l, n)];
      }
      // The (2H+1)² blocks by plain loops: Eigen's general product kernel costs more in set-up
      // than these few multiplications. Each sum runs over l in order from 0, as in that kernel.
      for (int j = 0; j < nh_; ++j) {
        double st = 0.0, sv = 0.0, sn = 0.0;
        for (int l = 0; l < nh_; ++l) {
          st += b.tu(j, l) * rt[l];
          sv += b.tv(j, l) * rn[l];
          sn += b.nv(j, l) * rn[l];
        }
        q(t, j) += st + sv;  // rows may be shared: add
        q(n, j) += sn;
      }
    }
    out->resize(v.size());
    for (int h = 0; h <= d_.harmonics; ++h) {
      const int j0 = FirstCoefficient(h), m = NumCoefficients(h);
      const Eigen::Map<const Eigen::VectorXd> qs(q.col(j0).data(), m * nr);  // stacked (j0, j0+1)
      Eigen::VectorXd& gq = gq_;
      if (h > 0 && compact_[h].used) {
        CompactTimes(h, qs.data(), false, &gq);
      } else {
        d_.receptance->GTimes(h, qs, false, &gq);
      }
      Eigen::VectorXd& pq = pq_;
      pq.noalias() = d_.receptance->DofPRows(h) * qs;
      for (int jj = 0; jj < m; ++jj) {
        const int j = j0 + jj;
        for (int i = 0; i < nr; ++i) (*out)[Idx(j, i)] = d_.w[i] * (v[Idx(j, i)] + gq[jj * nr + i]);
        (*out)[Idx(j, nr)] = d_.sy * (v[Idx(j, nr)] + pq[jj]);
      }
    }
  }

  // Jᵀ v = s + Dᵀ [G_hᵀ s_r + P_hᵀ s_y] with s = W v.
  void ApplyTransposed(const Eigen::VectorXd& v, Eigen::VectorXd* out) const {
    const int nr = d_.num_relative;
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(nr, nh_);  // G_hᵀ s_r + P_hᵀ s_y per coefficient
    Eigen::MatrixXd sr(nr, 2);
    Eigen::Vector2d sy;
    for (int h = 0; h <= d_.harmonics; ++h) {
      const int j0 = FirstCoefficient(h), m = NumCoefficients(h);
      for (int jj = 0; jj < m; ++jj) {
        for (int i = 0; i < nr; ++i) sr(i, jj) = d_.w[i] * v[Idx(j0 + jj, i)];
        sy[jj] = d_.sy * v[Idx(j0 + jj, nr)];
      }
      const Eigen::Map<const Eigen::VectorXd> srs(sr.data(), m * nr);
      Eigen::Map<Eigen::VectorXd> ts(t.col(j0).data(), m * nr);
      Eigen::VectorXd gs;
      if (h > 0 && compact_[h].used) {
        CompactTimes(h, srs.data(), true, &gs);
      } else {
        d_.receptance->GTimes(h, srs, true, &gs);
      }
      ts = gs;
      ts.noalias() += d_.receptance->DofPRows(h).transpose() * sy.head(m);
    }
    out->resize(v.size());
    for (int j = 0; j < nh_; ++j) {
      for (int i = 0; i < nr; ++i) (*out)[Idx(j, i)] = d_.w[i] * v[Idx(j, i)];
      (*out)[Idx(j, nr)] = d_.sy * v[Idx(j, nr)];
    }
    Eigen::VectorXd tt(nh_), tn(nh_);
    for (size_t c = 0; c < d_.blocks.size(); ++c) {
      const EffectiveForceBlocks& b = d_.blocks[c];
      const int rt = d_.row_t[c], rn = d_.row_n[c];
      tt = t.row(rt).transpose();
      tn = t.row(rn).transpose();
      const Eigen::VectorXd dt = b.tu.transpose() * tt;
      const Eigen::VectorXd dn = b.tv.transpose() * tt + b.nv.transpose() * tn;
      for (int l = 0; l < nh_; ++l) {
        (*out)[Idx(l, rt)] += dt[l];
        (*out)[Idx(l, rn)] += dn[l];
      }
    }
  }

  CondensedJacobianData d_;
  int nh_ = 3, bs_ = 1;
  // Scratch of ApplyDirect, kept between GMRES's products (an operator serves one thread): its
  // allocations were ~2 % of an FE bound.
  mutable Eigen::MatrixXd q_;
  mutable Eigen::VectorXd gq_, pq_;
  mutable Eigen::VectorXcd z_, w_;
  mutable std::vector<CompactReceptance> compact_;  // per harmonic, built at the first product
};

}  // namespace

std::unique_ptr<JacobianOperator> MakeCondensedJacobian(CondensedJacobianData data) {
  return std::make_unique<CondensedJacobian>(std::move(data));
}

}  // namespace fricrom
