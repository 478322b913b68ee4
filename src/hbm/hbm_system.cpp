#include "fricrom/hbm_system.h"

#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>

#include "fricrom/contact_forces.h"
#include "fricrom/units.h"

namespace fricrom {

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
  return (viscous_dissipation + friction_dissipation()) / (kTwoPi * potential_energy);
}

namespace {

// Harmonic by harmonic, the coefficients of side B of a cyclic contact delayed by one sector
// (`sign` +1) or advanced (−1: the adjoint, which carries forces back to this sector's copy).
void DelaySideB(const Contact& c, double sign, Eigen::VectorXd* coefficients) {
  for (int h = 1; 2 * h < coefficients->size(); ++h) {
    RotateHarmonic(sign * h * c.phase_b, &(*coefficients)[2 * h - 1], &(*coefficients)[2 * h]);
  }
}

// Relative displacement coefficients of a contact along direction `dir` of side A and `dir_b` of
// side B (normal or tangent; they differ on a cyclic contact).
void RelativeCoefficients(const HbmSystem& sys, const Contact& c, const Eigen::VectorXd& dir,
                          const Eigen::VectorXd& dir_b, const Eigen::VectorXd& x,
                          Eigen::VectorXd* out) {
  const int nh = sys.num_coefficients();
  out->setZero(nh);
  if (c.cyclic()) {
    Eigen::VectorXd side_b = Eigen::VectorXd::Zero(nh);
    for (int i = 0; i < dir.size(); ++i) {
      for (int j = 0; j < nh; ++j) {
        if (c.dofs_a[i] >= 0) (*out)[j] += dir[i] * x[sys.Index(c.dofs_a[i], j)];
        if (c.dofs_b[i] >= 0) side_b[j] += dir_b[i] * x[sys.Index(c.dofs_b[i], j)];
      }
    }
    DelaySideB(c, 1.0, &side_b);
    *out -= side_b;
    return;
  }
  for (int i = 0; i < dir.size(); ++i) {
    for (int j = 0; j < nh; ++j) {
      double rel = 0.0;
      if (c.dofs_a[i] >= 0) rel += x[sys.Index(c.dofs_a[i], j)];
      if (c.dofs_b[i] >= 0) rel -= x[sys.Index(c.dofs_b[i], j)];
      (*out)[j] += dir[i] * rel;
    }
  }
}

// The coefficient map of side B: identity, or the delay by one sector (nh × nh).
Eigen::MatrixXd SideBMap(const Contact& c, int nh) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Identity(nh, nh);
  for (int col = 0; col < nh; ++col) {
    Eigen::VectorXd e = p.col(col);
    DelaySideB(c, 1.0, &e);
    p.col(col) = e;
  }
  return p;
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

// ∂(n_i N̂ + t_i T̂)/∂x of one contact added to the Jacobian: the blocks of the relative
// displacement along each direction e, + on a side's own DOFs, − across the two sides. A cyclic
// contact's side B reads its own directions through the delay P: ∂r/∂x_B = −d_b P, forces on B
// −Pᵀ d_b F.
void AddContactJacobian(const HbmSystem& sys, const Contact& c, const ContactForceBlocks& f,
                        Eigen::MatrixXd* jacobian) {
  const int dim = static_cast<int>(c.normal.size());
  const int nh = sys.num_coefficients();
  const bool delayed = c.cyclic();
  const Eigen::MatrixXd p = delayed ? SideBMap(c, nh) : Eigen::MatrixXd();
  const Eigen::VectorXd *dn[2] = {&c.normal, &c.NormalB()}, *dt[2] = {&c.tangent, &c.TangentB()};
  for (int i = 0; i < dim; ++i) {    // row direction
    for (int e = 0; e < dim; ++e) {  // column direction
      const int rows[2] = {c.dofs_a[i], c.dofs_b[i]};
      const int cols[2] = {c.dofs_a[e], c.dofs_b[e]};
      for (int sr = 0; sr < 2; ++sr) {
        if (rows[sr] < 0) continue;
        for (int sc = 0; sc < 2; ++sc) {
          if (cols[sc] < 0) continue;
          const double ni = (*dn[sr])[i], ti = (*dt[sr])[i], ne = (*dn[sc])[e], te = (*dt[sc])[e];
          Eigen::MatrixXd block = ni * ne * f.dn_dv + ti * (te * f.dt_du + ne * f.dt_dv);
          if (delayed && sr == 1) block = p.transpose() * block;
          if (delayed && sc == 1) block = block * p;
          const double sign = (sr == sc) ? 1.0 : -1.0;
          for (int j = 0; j < nh; ++j) {
            for (int l = 0; l < nh; ++l) {
              (*jacobian)(sys.Index(rows[sr], j), sys.Index(cols[sc], l)) += sign * block(j, l);
            }
          }
        }
      }
    }
  }
}

}  // namespace

// The shared AFT (contact_forces.h) and the per-evaluation scratch of one contact.
struct HbmSystem::Workspace {
  AftContactForces aft;
  Eigen::VectorXd uh, vh;
  ContactForceBlocks f;
  explicit Workspace(const HbmOptions& options) : aft(options) {}
  // AFT of one contact of `sys` at x: relative coefficients (uh, vh) -> forces f.
  void Aft(const HbmSystem& sys, const Contact& c, const Eigen::VectorXd& x, double alpha,
           AftDerivatives derivatives = {}) {
    RelativeCoefficients(sys, c, c.tangent, c.TangentB(), x, &uh);
    RelativeCoefficients(sys, c, c.normal, c.NormalB(), x, &vh);
    aft.Evaluate(LawParams(c), uh, vh, alpha, derivatives, &f);
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
  work_ = std::make_unique<Workspace>(options_);
}

HbmSystem::~HbmSystem() = default;

std::unique_ptr<HarmonicBalance> HbmSystem::WithFewerHarmonics(int harmonics) const {
  std::string error;
  if (harmonics < 1 || harmonics >= options_.harmonics ||
      !LoadsRepresentable(model_, harmonics, &error)) {
    return nullptr;
  }
  HbmOptions o = options_;
  o.harmonics = harmonics;
  return std::make_unique<HbmSystem>(model_, o);
}

JacobianPattern HbmSystem::StructuralPattern() const {
  // Column-wise sets of rows: the linear blocks per harmonic (K at h = 0; K, M on the diagonal
  // blocks and C on the cos/sin coupling blocks at h ≥ 1), then every coefficient of every DOF of
  // a contact against every coefficient of that contact's DOFs (the AFT couples harmonics), and
  // each α against the coefficients of the DOFs its tangent moves.
  const int n = num_dofs(), nh = num_coefficients(), nx = num_unknowns();
  std::vector<std::set<int>> col_rows(static_cast<size_t>(nx + num_contacts()));
  auto add = [&](int row, int col) { col_rows[static_cast<size_t>(col)].insert(row); };
  const Eigen::MatrixXd& K = model_.stiffness;
  const Eigen::MatrixXd& M = model_.mass;
  const Eigen::MatrixXd& C = model_.damping;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const bool km = K(i, k) != 0.0 || M(i, k) != 0.0, c = C(i, k) != 0.0;
      if (K(i, k) != 0.0) add(Index(i, 0), Index(k, 0));
      for (int h = 1; h <= options_.harmonics; ++h) {
        const int a = 2 * h - 1, b = 2 * h;
        if (km) add(Index(i, a), Index(k, a)), add(Index(i, b), Index(k, b));
        if (c) add(Index(i, a), Index(k, b)), add(Index(i, b), Index(k, a));
      }
    }
  }
  for (int ci = 0; ci < num_contacts(); ++ci) {
    const Contact& ct = model_.contacts[static_cast<size_t>(ci)];
    std::vector<int> dofs, moved;  // the contact's DOFs; those its tangent moves
    for (size_t i = 0; i < ct.dofs_a.size(); ++i) {
      for (const int d : {ct.dofs_a[i], ct.dofs_b[i]}) {
        if (d < 0) continue;
        dofs.push_back(d);
        const Eigen::VectorXd& t = d == ct.dofs_a[i] ? ct.tangent : ct.TangentB();
        if (t[static_cast<Eigen::Index>(i)] != 0.0 || ct.cyclic()) moved.push_back(d);
      }
    }
    for (const int r : dofs) {
      for (const int c : dofs) {
        for (int j = 0; j < nh; ++j) {
          for (int l = 0; l < nh; ++l) add(Index(r, j), Index(c, l));
        }
      }
    }
    for (const int r : moved) {
      for (int j = 0; j < nh; ++j) add(Index(r, j), nx + ci);
    }
  }
  JacobianPattern p;
  for (size_t c = 0; c < col_rows.size(); ++c) {
    for (const int r : col_rows[c]) {
      p.rows.push_back(r);
      p.cols.push_back(static_cast<int>(c));
    }
  }
  return p;
}

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
    w.Aft(*this, c, x, alpha[ci], AftDerivatives{request.jacobian, request.alpha_jacobian});

    const int dim = static_cast<int>(c.normal.size());
    if (c.cyclic()) {
      AddCyclicContactForces(c, ci, request, &r, out);
      continue;
    }
    // Residual: side A gets +(N n + T t), side B the opposite.
    for (int i = 0; i < dim; ++i) {
      for (int j = 0; j < nh; ++j) {
        const double f = c.normal[i] * w.f.n[j] + c.tangent[i] * w.f.t[j];
        if (c.dofs_a[i] >= 0) r[Index(c.dofs_a[i], j)] += f;
        if (c.dofs_b[i] >= 0) r[Index(c.dofs_b[i], j)] -= f;
      }
    }
    if (!derivs) continue;

    if (request.jacobian) AddContactJacobian(*this, c, w.f, &out->jacobian);
    if (request.alpha_jacobian) {
      const Eigen::VectorXd& gh = w.f.dt_dalpha;
      for (int i = 0; i < dim; ++i) {
        for (int j = 0; j < nh; ++j) {
          if (c.dofs_a[i] >= 0)
            out->alpha_jacobian(Index(c.dofs_a[i], j), ci) += c.tangent[i] * gh[j];
          if (c.dofs_b[i] >= 0)
            out->alpha_jacobian(Index(c.dofs_b[i], j), ci) -= c.tangent[i] * gh[j];
        }
      }
    }
  }
}

// A cyclic contact's forces (after w.Aft): side A gets +(N n + T t); this sector's copy of side
// B gets −(N n_b + T t_b) advanced by one sector (the previous sector's contact acts on it).
void HbmSystem::AddCyclicContactForces(const Contact& c, int ci, const HbmRequest& request,
                                       Eigen::VectorXd* r, HbmEvaluation* out) const {
  const Workspace& w = *work_;
  const int dim = static_cast<int>(c.normal.size()), nh = num_coefficients();
  Eigen::VectorXd fb_n = w.f.n, fb_t = w.f.t, gb = w.f.dt_dalpha;
  DelaySideB(c, -1.0, &fb_n);
  DelaySideB(c, -1.0, &fb_t);
  if (request.alpha_jacobian) DelaySideB(c, -1.0, &gb);
  for (int i = 0; i < dim; ++i) {
    for (int j = 0; j < nh; ++j) {
      if (c.dofs_a[i] >= 0)
        (*r)[Index(c.dofs_a[i], j)] += c.normal[i] * w.f.n[j] + c.tangent[i] * w.f.t[j];
      if (c.dofs_b[i] >= 0)
        (*r)[Index(c.dofs_b[i], j)] -= c.NormalB()[i] * fb_n[j] + c.TangentB()[i] * fb_t[j];
      if (!request.alpha_jacobian) continue;
      if (c.dofs_a[i] >= 0)
        out->alpha_jacobian(Index(c.dofs_a[i], j), ci) += c.tangent[i] * w.f.dt_dalpha[j];
      if (c.dofs_b[i] >= 0)
        out->alpha_jacobian(Index(c.dofs_b[i], j), ci) -= c.TangentB()[i] * gb[j];
    }
  }
  if (request.jacobian) AddContactJacobian(*this, c, w.f, &out->jacobian);
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
  const bool cyclic = HasCyclicContacts(model_);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_unknowns());
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(n);
  for (const Contact& c : model_.contacts) {  // preloaded normal springs push A and B apart
    for (int i = 0; i < c.normal.size(); ++i) {
      if (c.dofs_a[i] >= 0) f0[c.dofs_a[i]] -= c.normal_preload * c.normal[i];
      if (c.dofs_b[i] >= 0) f0[c.dofs_b[i]] += c.normal_preload * c.NormalB()[i];
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
    const Eigen::MatrixXd kd = (cyclic ? model_.stiffness : k) - hw * hw * model_.mass;
    a << kd, hw * model_.damping, -hw * model_.damping, kd;
    if (cyclic) a += ContactStickStiffness(model_, h);  // couples cos and sin through the phase
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
  const double period = kTwoPi / omega;
  for (int ci = 0; ci < num_contacts(); ++ci) {
    const Contact& c = model_.contacts[ci];
    ContactHistory hist;
    w.Aft(*this, c, x, alpha[ci]);
    const int n = w.aft.num_samples();
    hist.u = w.f.u;
    hist.v = w.f.v;
    hist.tangential = w.f.law.tangential;
    hist.normal = w.f.law.normal;
    hist.states = w.f.law.states;
    hist.regime = ClassifyRegime(w.f.law.states);
    hist.time_s = Eigen::VectorXd::LinSpaced(n, 0.0, period * (n - 1) / n);
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
    w.Aft(*this, c, x, alpha[ci]);
    double diss = 0.0;  // ∮ (T du + N dv), harmonic by harmonic
    for (int h = 1; h <= options_.harmonics; ++h) {
      diss += pi * h *
              (w.f.t[2 * h - 1] * w.uh[2 * h] - w.f.t[2 * h] * w.uh[2 * h - 1] +
               w.f.n[2 * h - 1] * w.vh[2 * h] - w.f.n[2 * h] * w.vh[2 * h - 1]);
    }
    e.contact_dissipation.push_back(diss);
    for (int j = 1; j < num_coefficients(); ++j) {
      e.potential_energy += 0.5 * (w.f.t[j] * w.uh[j] + w.f.n[j] * w.vh[j]);
    }
  }
  return e;
}

}  // namespace fricrom
