#include "fricrom/contact_forces.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fricrom/units.h"

namespace fricrom {
namespace {

// FFTW's planner is not thread-safe; plans are made and destroyed under this lock.
std::mutex& PlannerMutex() {
  static std::mutex m;
  return m;
}

}  // namespace

// Up to this many coefficients (H ≤ 7) the transforms are direct sums over the samples: at
// 2H+1 ≤ 15 they cost fewer operations than FFTW's calls on 64-256 samples and need no copies
// into its buffers; beyond, FFTW.
constexpr int kMaxDirectCoefficients = 15;

struct AftContactForces::Plans {
  int n = 0;   // samples
  int nh = 0;  // coefficients 2H+1
  bool direct = false;
  double* real = nullptr;
  fftw_complex* spec = nullptr;
  fftw_plan forward = nullptr;   // r2c: samples -> spectrum
  fftw_plan backward = nullptr;  // c2r: spectrum -> samples
  Eigen::MatrixXd synthesis;     // N x nh: samples = synthesis * coefficients
  Eigen::MatrixXd analysis_t;    // N x nh: coefficients = analysis_tᵀ * samples
  Eigen::MatrixXd w_tu, w_tv, w_nv;
  Eigen::VectorXd g;

  Plans(int samples, int harmonics)
      : n(samples), nh(2 * harmonics + 1), direct(nh <= kMaxDirectCoefficients) {
    if (!direct) MakeFftwPlans();
    synthesis.resize(n, nh);
    analysis_t.resize(n, nh);
    for (int k = 0; k < n; ++k) {
      const double theta = kTwoPi * k / n;
      synthesis(k, 0) = 1.0;
      analysis_t(k, 0) = 1.0 / n;
      for (int h = 1; h <= harmonics; ++h) {
        synthesis(k, 2 * h - 1) = std::cos(h * theta);
        synthesis(k, 2 * h) = std::sin(h * theta);
        analysis_t(k, 2 * h - 1) = 2.0 / n * std::cos(h * theta);
        analysis_t(k, 2 * h) = 2.0 / n * std::sin(h * theta);
      }
    }
    w_tu.resize(n, nh);
    w_tv.resize(n, nh);
    w_nv.resize(n, nh);
    g.resize(n);
  }
  ~Plans() {
    std::lock_guard<std::mutex> lock(PlannerMutex());
    Release();
  }
  void MakeFftwPlans() {
    std::lock_guard<std::mutex> lock(PlannerMutex());
    real = fftw_alloc_real(static_cast<size_t>(n));
    spec = fftw_alloc_complex(static_cast<size_t>(n / 2 + 1));
    if (real && spec) {
      forward = fftw_plan_dft_r2c_1d(n, real, spec, FFTW_ESTIMATE);
      backward = fftw_plan_dft_c2r_1d(n, spec, real, FFTW_ESTIMATE);
    }
    if (!real || !spec || !forward || !backward) {
      Release();
      throw std::runtime_error("AftContactForces: FFTW could not plan a transform of size " +
                               std::to_string(n));
    }
  }
  void Release() {
    if (forward) fftw_destroy_plan(forward);
    if (backward) fftw_destroy_plan(backward);
    fftw_free(real);
    fftw_free(spec);
    forward = backward = nullptr;
    real = nullptr;
    spec = nullptr;
  }

  // coefficients [c0, a1, b1, ...] -> N samples
  void ToTime(const Eigen::VectorXd& coef, Eigen::VectorXd* samples) {
    samples->resize(n);
    if (direct) {
      // Blocks of samples held in registers over the coefficients: one store per sample, where
      // a pass per coefficient loads and stores every sample nh times. Each sample's sum keeps
      // the order c0 + c1 s1 + c2 s2 + ... (bit for bit the per-coefficient passes').
      constexpr int kBlock = 16;
      double* out = samples->data();
      for (int k0 = 0; k0 < n; k0 += kBlock) {
        const int m = std::min(kBlock, n - k0);
        double acc[kBlock];
        for (int k = 0; k < m; ++k) acc[k] = coef[0];
        for (int j = 1; j < nh; ++j) {
          const double c = coef[j];
          const double* col = synthesis.col(j).data() + k0;
          for (int k = 0; k < m; ++k) acc[k] += c * col[k];
        }
        for (int k = 0; k < m; ++k) out[k0 + k] = acc[k];
      }
      return;
    }
    const int half = n / 2 + 1;
    for (int i = 0; i < half; ++i) spec[i][0] = spec[i][1] = 0.0;
    spec[0][0] = coef[0];
    for (int h = 1; 2 * h < nh; ++h) {
      spec[h][0] = 0.5 * coef[2 * h - 1];
      spec[h][1] = -0.5 * coef[2 * h];
    }
    fftw_execute(backward);
    for (int k = 0; k < n; ++k) (*samples)[k] = real[k];
  }
  // N samples -> coefficients
  void ToFrequency(const Eigen::VectorXd& samples, Eigen::VectorXd* coef) {
    coef->resize(nh);
    if (direct) {
      for (int j = 0; j < nh; ++j) (*coef)[j] = analysis_t.col(j).dot(samples);
      return;
    }
    for (int k = 0; k < n; ++k) real[k] = samples[k];
    fftw_execute(forward);
    (*coef)[0] = spec[0][0] / n;
    for (int h = 1; 2 * h < nh; ++h) {
      (*coef)[2 * h - 1] = 2.0 / n * spec[h][0];
      (*coef)[2 * h] = -2.0 / n * spec[h][1];
    }
  }
  // A contact stuck over the period from its initial instant: T = α μ N(0) + kt (u − u(0)) and
  // N = N0 + kn v are linear in the samples, so their coefficients and derivatives are those
  // of the transforms of the general route in closed form (equal to round-off; the harmonics
  // h ≥ 1 of T − kt u and N − kn v exactly zero). 70 % of the FE cascade's laws at its bounds.
  void StuckBlocks(const ContactLawParams& c, const Eigen::VectorXd& uh, const Eigen::VectorXd& vh,
                   double u0, double v0, double alpha, AftDerivatives derivatives,
                   ContactForceBlocks* out) const {
    const double n0 = c.normal_preload + c.kn * v0;
    out->t = c.kt * uh;
    out->t[0] += alpha * c.mu * n0 - c.kt * u0;
    out->n = c.kn * vh;
    out->n[0] += c.normal_preload;
    if (derivatives.displacement) {
      // Row 0 (the mean) of ∂/∂û and ∂/∂v̂ through u(0), v(0): synthesis row 0.
      out->dt_du = c.kt * Eigen::MatrixXd::Identity(nh, nh);
      out->dt_du.row(0) -= c.kt * synthesis.row(0);
      out->dt_dv.setZero(nh, nh);
      out->dt_dv.row(0) = alpha * c.mu * c.kn * synthesis.row(0);
      out->dn_dv = c.kn * Eigen::MatrixXd::Identity(nh, nh);
    }
    if (derivatives.alpha) {
      out->dt_dalpha.setZero(nh);
      out->dt_dalpha[0] = c.mu * n0;
    }
  }
  // analysis · w (nh x nh) as nh² dot products over the samples: a general matrix product
  // spends more on packing these thin operands than on the arithmetic.
  void Analyse(const Eigen::MatrixXd& w, Eigen::MatrixXd* out) const {
    out->resize(nh, nh);
    for (int l = 0; l < nh; ++l) {
      for (int j = 0; j < nh; ++j) (*out)(j, l) = analysis_t.col(j).dot(w.col(l));
    }
  }
};

AftContactForces::AftContactForces(const HbmOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("AftContactForces: " + error);
  plans_ = std::make_unique<Plans>(options.samples_per_period, options.harmonics);
}

AftContactForces::~AftContactForces() = default;

int AftContactForces::num_coefficients() const { return plans_->nh; }
int AftContactForces::num_samples() const { return plans_->n; }

void AftContactForces::Evaluate(const ContactLawParams& params, const Eigen::VectorXd& uh,
                                const Eigen::VectorXd& vh, double alpha, AftDerivatives derivatives,
                                ContactForceBlocks* out) const {
  Plans& p = *plans_;
  if (uh.size() != p.nh || vh.size() != p.nh) {
    throw std::invalid_argument("AftContactForces: expected " + std::to_string(p.nh) +
                                " coefficients per relative displacement");
  }
  p.ToTime(uh, &out->u);
  p.ToTime(vh, &out->v);
  // The closed form's blocks need no sample-level derivatives of the law.
  out->stuck_form = EvaluateStuckContactLaw(params, out->u, out->v, alpha, false, &out->law);
  if (out->stuck_form) {
    p.StuckBlocks(params, uh, vh, out->u[0], out->v[0], alpha, derivatives, out);
    return;
  }
  EvaluateContactLaw(params, out->u, out->v, alpha, derivatives.any(), &out->law);
  p.ToFrequency(out->law.tangential, &out->t);
  p.ToFrequency(out->law.normal, &out->n);
  if (!derivatives.any()) return;
  // Sample-level sparse derivatives -> coefficient-level blocks: A = analysis · (dF/ds) ·
  // synthesis. The N x nh products are written column by column, each entry once: rows of these
  // column-major matrices would be strided stores after a clearing pass.
  if (derivatives.displacement) {
    const std::vector<TangentialDerivative>& dT = out->law.dT;
    const Eigen::VectorXd& dN = out->law.dN_dv;
    for (int l = 0; l < p.nh; ++l) {
      const double* s = p.synthesis.col(l).data();
      double* tu = p.w_tu.col(l).data();
      double* tv = p.w_tv.col(l).data();
      double* nv = p.w_nv.col(l).data();
      for (int k = 0; k < p.n; ++k) {
        const TangentialDerivative& d = dT[k];
        tu[k] =
            d.u_plus >= 0 && d.u_plus != d.u_minus ? params.kt * (s[d.u_plus] - s[d.u_minus]) : 0.0;
        tv[k] = d.v_index >= 0 && d.dv != 0.0 ? d.dv * s[d.v_index] : 0.0;
        nv[k] = dN[k] * s[k];
      }
    }
    p.Analyse(p.w_tu, &out->dt_du);
    p.Analyse(p.w_tv, &out->dt_dv);
    p.Analyse(p.w_nv, &out->dn_dv);
  }
  if (derivatives.alpha) {
    for (int k = 0; k < p.n; ++k) p.g[k] = out->law.dT[k].dalpha;
    out->dt_dalpha.noalias() = p.analysis_t.transpose() * p.g;
  }
}

void AftContactForces::AddDerivatives(const ContactLawParams& params, const Eigen::VectorXd& uh,
                                      const Eigen::VectorXd& vh, double alpha,
                                      AftDerivatives derivatives, ContactForceBlocks* out) const {
  if (!out->stuck_form || uh.size() != plans_->nh || vh.size() != plans_->nh ||
      out->u.size() != plans_->n || out->v.size() != plans_->n) {
    Evaluate(params, uh, vh, alpha, derivatives, out);
    return;
  }
  plans_->StuckBlocks(params, uh, vh, out->u[0], out->v[0], alpha, derivatives, out);
}

}  // namespace fricrom
