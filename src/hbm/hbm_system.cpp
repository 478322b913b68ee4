#include <fftw3.h>

#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fricrom/hbm.h"

namespace fricrom {
namespace {

// FFTW's planner is not thread-safe; plans are made once per HbmSystem under this lock.
std::mutex& PlannerMutex() {
  static std::mutex m;
  return m;
}

}  // namespace

bool HbmOptions::IsValid(std::string* error) const {
  // The response is the first-harmonic amplitude and the excitation is periodic: H = 0 (a static
  // problem) cannot represent either.
  if (harmonics < 1) {
    *error = "harmonics must be >= 1 (the forced response is harmonic 1), got " +
             std::to_string(harmonics);
    return false;
  }
  if (samples_per_period <= 2 * harmonics || samples_per_period < 4) {
    *error = "samples_per_period must be >= 4 and > 2*harmonics (" + std::to_string(2 * harmonics) +
             "), got " + std::to_string(samples_per_period);
    return false;
  }
  return true;
}

bool LoadsRepresentable(const Model& model, int harmonics, std::string* error) {
  for (const HarmonicLoad& load : model.loads) {
    if (load.harmonic < 0 || load.harmonic > harmonics) {
      *error = "a load at harmonic " + std::to_string(load.harmonic) +
               " cannot be represented with H = " + std::to_string(harmonics) +
               " harmonics (raise H to at least " + std::to_string(load.harmonic) +
               " or remove the load)";
      return false;
    }
  }
  return true;
}

double CycleEnergy::friction_dissipation() const {
  double s = 0.0;
  for (double w : contact_dissipation) s += w;
  return s;
}

double CycleEnergy::loss_factor() const {
  return (viscous_dissipation + friction_dissipation()) / (2.0 * std::numbers::pi * potential_energy);
}

namespace {

// Relative displacement coefficients of a contact along direction `dir` (normal or tangent).
void RelativeCoefficients(const HbmSystem& sys, const Contact& c, const Eigen::VectorXd& dir,
                          const Eigen::VectorXd& x, Eigen::VectorXd* out) {
  const int nh = sys.num_coefficients();
  out->setZero(nh);
  for (int i = 0; i < dir.size(); ++i) {
    for (int j = 0; j < nh; ++j) {
      double rel = 0.0;
      if (c.dofs_a[i] >= 0) rel += x[sys.Index(c.dofs_a[i], j)];
      if (c.dofs_b[i] >= 0) rel -= x[sys.Index(c.dofs_b[i], j)];
      (*out)[j] += dir[i] * rel;
    }
  }
}

ContactLawParams LawParams(const Contact& c) {
  return ContactLawParams{c.kn, c.kt, c.mu, c.normal_preload};
}

void CheckInputs(const HbmSystem& sys, const Eigen::VectorXd& x, const Eigen::VectorXd& alpha) {
  if (x.size() != sys.num_unknowns()) {
    throw std::invalid_argument("HbmSystem: x has " + std::to_string(x.size()) +
                                " entries, expected " + std::to_string(sys.num_unknowns()));
  }
  if (alpha.size() != sys.num_contacts()) {
    throw std::invalid_argument("HbmSystem: alpha has " + std::to_string(alpha.size()) +
                                " entries, expected one per contact (" +
                                std::to_string(sys.num_contacts()) + ")");
  }
  for (int c = 0; c < alpha.size(); ++c) {
    if (!(std::abs(alpha[c]) <= 1.0)) {
      throw std::invalid_argument("HbmSystem: alpha[" + std::to_string(c) +
                                  "] must lie in [-1, 1], got " + std::to_string(alpha[c]));
    }
  }
}

}  // namespace

// FFTW plans, buffers and the dense transform tables used for the Jacobian.
struct HbmSystem::Workspace {
  int n = 0;   // samples
  int nh = 0;  // coefficients 2H+1
  double* real = nullptr;
  fftw_complex* spec = nullptr;
  fftw_plan forward = nullptr;   // r2c: samples -> spectrum
  fftw_plan backward = nullptr;  // c2r: spectrum -> samples
  Eigen::MatrixXd synthesis;     // N x nh: samples = synthesis * coefficients
  Eigen::MatrixXd analysis;      // nh x N: coefficients = analysis * samples
  // Per-evaluation scratch.
  Eigen::VectorXd u, v, uh, vh, th, nh_coef, g;
  Eigen::MatrixXd w_tu, w_tv, w_nv, a_tu, a_tv, a_nv;
  ContactLawResult law;

  Workspace(int samples, int harmonics) : n(samples), nh(2 * harmonics + 1) {
    std::lock_guard<std::mutex> lock(PlannerMutex());
    real = fftw_alloc_real(static_cast<size_t>(n));
    spec = fftw_alloc_complex(static_cast<size_t>(n / 2 + 1));
    forward = fftw_plan_dft_r2c_1d(n, real, spec, FFTW_ESTIMATE);
    backward = fftw_plan_dft_c2r_1d(n, spec, real, FFTW_ESTIMATE);
    if (!real || !spec || !forward || !backward) {
      throw std::runtime_error("HbmSystem: FFTW could not allocate or plan a transform of size " +
                               std::to_string(n));
    }
    synthesis.resize(n, nh);
    analysis.resize(nh, n);
    for (int k = 0; k < n; ++k) {
      const double theta = 2.0 * std::numbers::pi * k / n;
      synthesis(k, 0) = 1.0;
      analysis(0, k) = 1.0 / n;
      for (int h = 1; h <= harmonics; ++h) {
        synthesis(k, 2 * h - 1) = std::cos(h * theta);
        synthesis(k, 2 * h) = std::sin(h * theta);
        analysis(2 * h - 1, k) = 2.0 / n * std::cos(h * theta);
        analysis(2 * h, k) = 2.0 / n * std::sin(h * theta);
      }
    }
    u.resize(n);
    v.resize(n);
    w_tu.resize(n, nh);
    w_tv.resize(n, nh);
    w_nv.resize(n, nh);
    g.resize(n);
  }
  ~Workspace() {
    std::lock_guard<std::mutex> lock(PlannerMutex());
    if (forward) fftw_destroy_plan(forward);
    if (backward) fftw_destroy_plan(backward);
    fftw_free(real);
    fftw_free(spec);
  }

  // coefficients [a0, a1, b1, ...] -> N samples
  void ToTime(const Eigen::VectorXd& coef, Eigen::VectorXd* samples) {
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
  // AFT of one contact: relative displacement coefficients -> samples -> law -> force
  // coefficients (uh, vh, u, v, law, th, nh_coef).
  void Aft(const HbmSystem& sys, const Contact& c, const Eigen::VectorXd& x, double alpha,
           bool derivatives) {
    RelativeCoefficients(sys, c, c.tangent, x, &uh);
    RelativeCoefficients(sys, c, c.normal, x, &vh);
    ToTime(uh, &u);
    ToTime(vh, &v);
    EvaluateContactLaw(LawParams(c), u, v, alpha, derivatives, &law);
    ToFrequency(law.tangential, &th);
    ToFrequency(law.normal, &nh_coef);
  }
  // N samples -> coefficients
  void ToFrequency(const Eigen::VectorXd& samples, Eigen::VectorXd* coef) {
    for (int k = 0; k < n; ++k) real[k] = samples[k];
    fftw_execute(forward);
    coef->resize(nh);
    (*coef)[0] = spec[0][0] / n;
    for (int h = 1; 2 * h < nh; ++h) {
      (*coef)[2 * h - 1] = 2.0 / n * spec[h][0];
      (*coef)[2 * h] = -2.0 / n * spec[h][1];
    }
  }
};

HbmSystem::HbmSystem(Model model, const HbmOptions& options)
    : model_(std::move(model)), options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("HbmOptions: " + error);
  model_.Validate();
  if (!LoadsRepresentable(model_, options_.harmonics, &error)) {
    throw std::invalid_argument("HbmSystem: " + error);
  }
  work_ = std::make_unique<Workspace>(options_.samples_per_period, options_.harmonics);
}

HbmSystem::~HbmSystem() = default;


void HbmSystem::Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                         const HbmRequest& request, HbmEvaluation* out) const {
  CheckInputs(*this, x, alpha);
  const int n = num_dofs();
  const int nh = num_coefficients();
  const int nx = num_unknowns();
  const Eigen::MatrixXd& M = model_.mass;
  const Eigen::MatrixXd& C = model_.damping;
  const Eigen::MatrixXd& K = model_.stiffness;

  // Linear part Z(ω) x − F̂exc, block by block.
  Eigen::VectorXd& r = out->residual;
  r.resize(nx);
  r.segment(0, n).noalias() = K * x.segment(0, n);
  if (request.jacobian) {
    out->jacobian.setZero(nx, nx);
    out->jacobian.block(0, 0, n, n) = K;
  }
  if (request.omega_derivative) out->omega_derivative.setZero(nx);
  for (int h = 1; h <= options_.harmonics; ++h) {
    const int ia = Index(0, 2 * h - 1), ib = Index(0, 2 * h);
    const double hw = h * omega;
    const Eigen::MatrixXd kd = K - hw * hw * M;
    r.segment(ia, n).noalias() = kd * x.segment(ia, n) + hw * (C * x.segment(ib, n));
    r.segment(ib, n).noalias() = kd * x.segment(ib, n) - hw * (C * x.segment(ia, n));
    if (request.jacobian) {
      out->jacobian.block(ia, ia, n, n) = kd;
      out->jacobian.block(ib, ib, n, n) = kd;
      out->jacobian.block(ia, ib, n, n) = hw * C;
      out->jacobian.block(ib, ia, n, n) = -hw * C;
    }
    if (request.omega_derivative) {
      out->omega_derivative.segment(ia, n) =
          -2.0 * h * hw * (M * x.segment(ia, n)) + h * (C * x.segment(ib, n));
      out->omega_derivative.segment(ib, n) =
          -2.0 * h * hw * (M * x.segment(ib, n)) - h * (C * x.segment(ia, n));
    }
  }
  for (const HarmonicLoad& load : model_.loads) {
    if (load.harmonic == 0) {
      r.segment(0, n) -= load.cos;
    } else {
      r.segment(Index(0, 2 * load.harmonic - 1), n) -= load.cos;
      r.segment(Index(0, 2 * load.harmonic), n) -= load.sin;
    }
  }
  if (request.alpha_jacobian) out->alpha_jacobian.setZero(nx, num_contacts());

  // Contact forces by AFT.
  Workspace& w = *work_;
  const bool derivs = request.jacobian || request.alpha_jacobian;
  for (int ci = 0; ci < num_contacts(); ++ci) {
    const Contact& c = model_.contacts[ci];
    w.Aft(*this, c, x, alpha[ci], derivs);

    const int dim = static_cast<int>(c.normal.size());
    // Residual: side A gets +(N n + T t), side B the opposite.
    for (int i = 0; i < dim; ++i) {
      for (int j = 0; j < nh; ++j) {
        const double f = c.normal[i] * w.nh_coef[j] + c.tangent[i] * w.th[j];
        if (c.dofs_a[i] >= 0) r[Index(c.dofs_a[i], j)] += f;
        if (c.dofs_b[i] >= 0) r[Index(c.dofs_b[i], j)] -= f;
      }
    }
    if (!derivs) continue;

    // Sample-level sparse derivatives -> coefficient-level nh x nh blocks: A = P · (dF/ds) · Q.
    w.w_tu.setZero();
    w.w_tv.setZero();
    w.g.setZero();
    for (int k = 0; k < w.n; ++k) {
      const TangentialDerivative& d = w.law.dT[k];
      if (d.u_plus >= 0 && d.u_plus != d.u_minus) {
        w.w_tu.row(k) = c.kt * (w.synthesis.row(d.u_plus) - w.synthesis.row(d.u_minus));
      }
      if (d.v_index >= 0 && d.dv != 0.0) w.w_tv.row(k) = d.dv * w.synthesis.row(d.v_index);
      w.w_nv.row(k) = w.law.dN_dv[k] * w.synthesis.row(k);
      w.g[k] = d.dalpha;
    }
    if (request.jacobian) {
      w.a_tu.noalias() = w.analysis * w.w_tu;
      w.a_tv.noalias() = w.analysis * w.w_tv;
      w.a_nv.noalias() = w.analysis * w.w_nv;
      for (int i = 0; i < dim; ++i) {      // row direction
        for (int e = 0; e < dim; ++e) {    // column direction
          // d(n_i N̂ + t_i T̂)/d(relative displacement along e)
          const Eigen::MatrixXd block = c.normal[i] * c.normal[e] * w.a_nv +
                                        c.tangent[i] * (c.tangent[e] * w.a_tu +
                                                        c.normal[e] * w.a_tv);
          const int rows[2] = {c.dofs_a[i], c.dofs_b[i]};
          const int cols[2] = {c.dofs_a[e], c.dofs_b[e]};
          for (int sr = 0; sr < 2; ++sr) {
            if (rows[sr] < 0) continue;
            for (int sc = 0; sc < 2; ++sc) {
              if (cols[sc] < 0) continue;
              const double sign = (sr == sc) ? 1.0 : -1.0;
              for (int j = 0; j < nh; ++j) {
                for (int l = 0; l < nh; ++l) {
                  out->jacobian(Index(rows[sr], j), Index(cols[sc], l)) += sign * block(j, l);
                }
              }
            }
          }
        }
      }
    }
    if (request.alpha_jacobian) {
      const Eigen::VectorXd gh = w.analysis * w.g;
      for (int i = 0; i < dim; ++i) {
        for (int j = 0; j < nh; ++j) {
          if (c.dofs_a[i] >= 0) out->alpha_jacobian(Index(c.dofs_a[i], j), ci) += c.tangent[i] * gh[j];
          if (c.dofs_b[i] >= 0) out->alpha_jacobian(Index(c.dofs_b[i], j), ci) -= c.tangent[i] * gh[j];
        }
      }
    }
  }
}

double HbmSystem::ResidualScale() const {
  double s2 = 0.0;
  for (const HarmonicLoad& load : model_.loads) {
    s2 += load.cos.squaredNorm() + load.sin.squaredNorm();
  }
  return s2 > 0.0 ? std::sqrt(s2) : 1.0;
}

Eigen::VectorXd HbmSystem::StickLinearSolution(double omega) const {
  const int n = num_dofs();
  const Eigen::MatrixXd k = model_.stiffness + ContactStickStiffness(model_);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_unknowns());
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(n);
  for (const Contact& c : model_.contacts) {  // preloaded normal springs push A and B apart
    for (int i = 0; i < c.normal.size(); ++i) {
      if (c.dofs_a[i] >= 0) f0[c.dofs_a[i]] -= c.normal_preload * c.normal[i];
      if (c.dofs_b[i] >= 0) f0[c.dofs_b[i]] += c.normal_preload * c.normal[i];
    }
  }
  for (int h = 0; h <= options_.harmonics; ++h) {
    Eigen::VectorXd fc = Eigen::VectorXd::Zero(n), fs = Eigen::VectorXd::Zero(n);
    for (const HarmonicLoad& load : model_.loads) {
      if (load.harmonic != h) continue;
      fc += load.cos;
      if (h > 0) fs += load.sin;
    }
    if (h == 0) {
      x.segment(0, n) = k.ldlt().solve(fc + f0);
      continue;
    }
    const double hw = h * omega;
    Eigen::MatrixXd a(2 * n, 2 * n);
    const Eigen::MatrixXd kd = k - hw * hw * model_.mass;
    a << kd, hw * model_.damping, -hw * model_.damping, kd;
    Eigen::VectorXd rhs(2 * n);
    rhs << fc, fs;
    const Eigen::VectorXd sol = a.partialPivLu().solve(rhs);
    x.segment(Index(0, 2 * h - 1), n) = sol.head(n);
    x.segment(Index(0, 2 * h), n) = sol.tail(n);
  }
  return x;
}

double HbmSystem::DofAmplitude(const Eigen::VectorXd& x, int dof) const {
  if (dof < 0) dof = model_.response_dof;
  return std::hypot(x[Index(dof, 1)], x[Index(dof, 2)]);
}

Eigen::VectorXd HbmSystem::AmplitudeSquaredGradient(const Eigen::VectorXd& x) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(num_unknowns());
  const int ia = Index(model_.response_dof, 1), ib = Index(model_.response_dof, 2);
  g[ia] = 2.0 * x[ia];
  g[ib] = 2.0 * x[ib];
  return g;
}

std::vector<ContactHistory> HbmSystem::ContactHistories(const Eigen::VectorXd& x, double omega,
                                                        const Eigen::VectorXd& alpha) const {
  CheckInputs(*this, x, alpha);
  Workspace& w = *work_;
  std::vector<ContactHistory> out;
  const double period = 2.0 * std::numbers::pi / omega;
  for (int ci = 0; ci < num_contacts(); ++ci) {
    const Contact& c = model_.contacts[ci];
    ContactHistory hist;
    w.Aft(*this, c, x, alpha[ci], false);
    hist.u = w.u;
    hist.v = w.v;
    hist.tangential = w.law.tangential;
    hist.normal = w.law.normal;
    hist.states = w.law.states;
    hist.regime = ClassifyRegime(w.law.states);
    hist.time_s = Eigen::VectorXd::LinSpaced(w.n, 0.0, period * (w.n - 1) / w.n);
    out.push_back(std::move(hist));
  }
  return out;
}

CycleEnergy HbmSystem::Energies(const Eigen::VectorXd& x, double omega,
                                const Eigen::VectorXd& alpha) const {
  CheckInputs(*this, x, alpha);
  const int n = num_dofs();
  const double pi = std::numbers::pi;
  CycleEnergy e;
  for (const HarmonicLoad& load : model_.loads) {
    const int h = load.harmonic;
    if (h < 1 || h > options_.harmonics) continue;
    e.excitation_work += pi * h *
                         (load.cos.dot(x.segment(Index(0, 2 * h), n)) -
                          load.sin.dot(x.segment(Index(0, 2 * h - 1), n)));
  }
  for (int h = 1; h <= options_.harmonics; ++h) {
    const auto a = x.segment(Index(0, 2 * h - 1), n);
    const auto b = x.segment(Index(0, 2 * h), n);
    e.viscous_dissipation +=
        pi * h * h * omega * (a.dot(model_.damping * a) + b.dot(model_.damping * b));
    e.potential_energy += 0.5 * (a.dot(model_.stiffness * a) + b.dot(model_.stiffness * b));
  }
  Workspace& w = *work_;
  for (int ci = 0; ci < num_contacts(); ++ci) {
    const Contact& c = model_.contacts[ci];
    w.Aft(*this, c, x, alpha[ci], false);
    double diss = 0.0;  // ∮ (T du + N dv), harmonic by harmonic
    for (int h = 1; h <= options_.harmonics; ++h) {
      diss += pi * h *
              (w.th[2 * h - 1] * w.uh[2 * h] - w.th[2 * h] * w.uh[2 * h - 1] +
               w.nh_coef[2 * h - 1] * w.vh[2 * h] - w.nh_coef[2 * h] * w.vh[2 * h - 1]);
    }
    e.contact_dissipation.push_back(diss);
    for (int j = 1; j < num_coefficients(); ++j) {
      e.potential_energy += 0.5 * (w.th[j] * w.uh[j] + w.nh_coef[j] * w.vh[j]);
    }
  }
  return e;
}

}  // namespace fricrom
