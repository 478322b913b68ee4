#include "fricrom/condensed_system.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "fricrom/contact_forces.h"
#include "fricrom/hbm_system.h"
#include "hbm/condensed_jacobian.h"
#include "linear/harmonic_receptance.h"

namespace fricrom {
namespace {

// Coefficients of harmonic h in the layout [c0, a1, b1, ...].
std::vector<int> Coefficients(int h) {
  return h == 0 ? std::vector<int>{0} : std::vector<int>{2 * h - 1, 2 * h};
}

bool FullStick(const ContactForceBlocks& f) {
  return std::all_of(f.law.states.begin(), f.law.states.end(),
                     [](ContactState s) { return s == ContactState::kStick; });
}

// One contact's relative-displacement row along `dir` (tangent or normal), as sorted (DOF,
// coefficient) terms: the key that finds rows two contacts share.
// A cyclic contact's side-B terms act on the next sector's DOFs: keyed as DOF + n, so that
// they stay apart from this sector's and the row knows them.
using SparseRow = std::vector<std::pair<int, double>>;
SparseRow ContactRow(const Contact& ct, const Eigen::VectorXd& dir, const Eigen::VectorXd& dir_b,
                     int n) {
  std::map<int, double> terms;
  const int next = ct.cyclic() ? n : 0;
  for (int i = 0; i < dir.size(); ++i) {
    if (ct.dofs_a[i] >= 0) terms[ct.dofs_a[i]] += dir[i];
    if (ct.dofs_b[i] >= 0) terms[ct.dofs_b[i] + next] -= dir_b[i];
  }
  SparseRow row;
  for (const auto& [dof, value] : terms) {
    if (value != 0.0) row.emplace_back(dof, value);
  }
  return row;
}

}  // namespace

void CondensedSystem::BuildRelativeRows() {
  // Identical rows become one unknown: the two 1D laws of a pair with two tangential directions
  // share the pair's normal gap, so their normal forces add on one row (per coefficient three
  // unknowns t1, t2, n instead of four: the dense LU costs (3/4)³ of what it did).
  const int nc = num_contacts();
  std::map<SparseRow, int> index;
  std::vector<SparseRow> rows;
  auto row_of = [&](const SparseRow& r) {
    const auto [it, added] = index.try_emplace(r, static_cast<int>(rows.size()));
    if (added) rows.push_back(r);
    return it->second;
  };
  row_t_.resize(nc);
  row_n_.resize(nc);
  for (int c = 0; c < nc; ++c) {
    const Contact& ct = model_.contacts[c];
    const int n = model_.num_dofs();
    row_t_[c] = row_of(ContactRow(ct, ct.tangent, ct.TangentB(), n));
    row_n_[c] = row_of(ContactRow(ct, ct.normal, ct.NormalB(), n));
    if (row_t_[c] == row_n_[c]) {
      throw std::invalid_argument("CondensedSystem: contact " + std::to_string(c) +
                                  " has the same tangential and normal relative displacement");
    }
  }
  const int nr = static_cast<int>(rows.size()), n = model_.num_dofs();
  b_ = Eigen::MatrixXd::Zero(nr, n);
  const bool cyclic = HasCyclicContacts(model_);
  if (cyclic) {
    next_ = Eigen::MatrixXd::Zero(nr, n);
    phase_ = Eigen::VectorXd::Zero(nr);
  }
  for (int r = 0; r < nr; ++r) {
    for (const auto& [key, value] : rows[r]) {
      b_(r, key % n) += value;  // harmonic 0: the next sector's static state is this one's
      if (key >= n) next_(r, key - n) += value;
    }
  }
  for (int c = 0; c < nc && cyclic; ++c) {
    const Contact& ct = model_.contacts[c];
    if (!ct.cyclic()) continue;
    phase_[row_t_[c]] = ct.phase_b;
    phase_[row_n_[c]] = ct.phase_b;
  }
  ks_ = Eigen::VectorXd::Zero(nr);
  w_ = Eigen::VectorXd::Zero(nr);
  for (int c = 0; c < nc; ++c) {
    const Contact& ct = model_.contacts[c];
    ks_[row_t_[c]] += ct.kt;
    ks_[row_n_[c]] += ct.kn;
    const double w = std::max(ct.kn, ct.kt);
    w_[row_t_[c]] = std::max(w_[row_t_[c]], w);
    w_[row_n_[c]] = std::max(w_[row_n_[c]], w);
  }
}

CondensedSystem::CondensedSystem(Model model, const HbmOptions& options)
    : model_(std::move(model)), options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("HbmOptions: " + error);
  model_.Validate();
  if (!LoadsRepresentable(model_, options_.harmonics, &error)) {
    throw std::invalid_argument("CondensedSystem: " + error);
  }
  const int nc = num_contacts();
  BuildRelativeRows();
  sy_ = nc > 0 ? w_.mean() : std::max(model_.stiffness.diagonal().cwiseAbs().maxCoeff(), 1.0);
  const Eigen::MatrixXd k_stick = model_.stiffness + b_.transpose() * ks_.asDiagonal() * b_;
  receptance_ = std::make_shared<HarmonicReceptance>(k_stick, model_.mass, model_.damping, b_,
                                                     options_.harmonics, options_.receptance);
  if (next_.size() > 0) receptance_->SetCyclicRows(next_, phase_, ks_);
  std::vector<Eigen::VectorXd> loads;
  for (int h = 0; h <= options_.harmonics; ++h) loads.push_back(Excitation(h));
  receptance_->SetFixedLoads(std::move(loads), model_.response_dof);
  aft_ = std::make_unique<AftContactForces>(options_);
  full_ = std::make_unique<HbmSystem>(model_, options_);
  blocks_.resize(nc);
}

CondensedSystem::CondensedSystem(const CondensedSystem& higher, int harmonics)
    : model_(higher.model_),
      options_(higher.options_),
      b_(higher.b_),
      next_(higher.next_),
      phase_(higher.phase_),
      row_t_(higher.row_t_),
      row_n_(higher.row_n_),
      ks_(higher.ks_),
      w_(higher.w_),
      sy_(higher.sy_),
      receptance_(higher.receptance_) {
  options_.harmonics = harmonics;
  aft_ = std::make_unique<AftContactForces>(options_);
  full_ = std::make_unique<HbmSystem>(model_, options_);
  blocks_.resize(num_contacts());
}

std::unique_ptr<HarmonicBalance> CondensedSystem::WithFewerHarmonics(int harmonics) const {
  std::string error;
  if (harmonics < 1 || harmonics >= options_.harmonics ||
      !LoadsRepresentable(model_, harmonics, &error)) {
    return nullptr;
  }
  return std::unique_ptr<HarmonicBalance>(new CondensedSystem(*this, harmonics));
}

CondensedSystem::~CondensedSystem() = default;

int CondensedSystem::num_unknowns() const { return block_size() * (2 * options_.harmonics + 1); }

void CondensedSystem::CheckInputs(const Eigen::VectorXd& x, const Eigen::VectorXd& alpha) const {
  if (x.size() != num_unknowns()) {
    throw std::invalid_argument("CondensedSystem: x has " + std::to_string(x.size()) +
                                " entries, expected " + std::to_string(num_unknowns()));
  }
  if (alpha.size() != num_contacts()) {
    throw std::invalid_argument("CondensedSystem: alpha has " + std::to_string(alpha.size()) +
                                " entries, expected one per contact (" +
                                std::to_string(num_contacts()) + ")");
  }
  for (int c = 0; c < alpha.size(); ++c) {
    if (!(std::abs(alpha[c]) <= 1.0)) {
      throw std::invalid_argument("CondensedSystem: alpha[" + std::to_string(c) +
                                  "] must lie in [-1, 1], got " + std::to_string(alpha[c]));
    }
  }
}

Eigen::VectorXd CondensedSystem::ContactForces(const Eigen::VectorXd& x,
                                               const Eigen::VectorXd& alpha,
                                               AftDerivatives derivatives) const {
  // The forces depend on (x, α) only, not on ω: the last point's are reused where they (and the
  // derivatives asked for) are at hand, bit for bit what a new AFT would give.
  ForceMemo& memo = memo_;
  const bool same_point = memo.valid && memo.x.size() == x.size() && memo.x == x &&
                          memo.alpha.size() == alpha.size() && memo.alpha == alpha;
  if (same_point && (memo.displacement || !derivatives.displacement) &&
      (memo.alpha_derivative || !derivatives.alpha)) {
    return memo.ft;
  }
  const int nc = num_contacts(), nr = num_relative(), nh = 2 * options_.harmonics + 1;
  Eigen::VectorXd uh(nh), vh(nh);
  const auto gather = [&](int c) {
    for (int j = 0; j < nh; ++j) {
      uh[j] = x[Idx(j, row_t_[c])];
      vh[j] = x[Idx(j, row_n_[c])];
    }
  };
  if (same_point) {
    // Forces at hand, derivatives missing (a Newton step linearises where it evaluated): the
    // contacts stuck in closed form get theirs without another pass over the samples.
    memo.valid = false;  // until every block is complete
    for (int c = 0; c < nc; ++c) {
      const Contact& ct = model_.contacts[c];
      gather(c);
      aft_->AddDerivatives(ContactLawParams{ct.kn, ct.kt, ct.mu, ct.normal_preload}, uh, vh,
                           alpha[c], AftDerivatives{true, true}, &blocks_[c]);
    }
    memo.displacement = memo.alpha_derivative = memo.valid = true;
    return memo.ft;
  }
  // Derivatives in x come with those in α, which cost one more analysis per contact: a bound
  // run's gradient linearises and then asks for ∂R/∂α at the same point. (Plain evaluations do
  // not compute derivatives on speculation: a Newton step linearises where its line search
  // evaluated, but the derivatives cost about as much as the second AFT they would save —
  // 10-point FE segment 128.3 → 133.0 s side by side.)
  if (derivatives.any()) derivatives = AftDerivatives{true, true};
  Eigen::VectorXd ft = Eigen::VectorXd::Zero(nr * nh);
  memo.valid = false;  // blocks_ are overwritten below
  for (int c = 0; c < nc; ++c) {
    const Contact& ct = model_.contacts[c];
    gather(c);
    aft_->Evaluate(ContactLawParams{ct.kn, ct.kt, ct.mu, ct.normal_preload}, uh, vh, alpha[c],
                   derivatives, &blocks_[c]);
    for (int j = 0; j < nh; ++j) {
      ft[j * nr + row_t_[c]] += blocks_[c].t[j] - ct.kt * uh[j];  // rows may be shared: add
      ft[j * nr + row_n_[c]] += blocks_[c].n[j] - ct.kn * vh[j];
    }
  }
  memo.x = x;
  memo.alpha = alpha;
  memo.ft = ft;
  memo.displacement = derivatives.displacement;
  memo.alpha_derivative = derivatives.alpha;
  memo.valid = true;
  return ft;
}

Eigen::VectorXd CondensedSystem::Stack(int h, const Eigen::VectorXd& coefficient_major) const {
  const int nr = num_relative();
  const std::vector<int> js = Coefficients(h);
  Eigen::VectorXd out(nr * static_cast<int>(js.size()));
  for (size_t jj = 0; jj < js.size(); ++jj) {
    out.segment(static_cast<int>(jj) * nr, nr) = coefficient_major.segment(js[jj] * nr, nr);
  }
  return out;
}

Eigen::VectorXd CondensedSystem::Excitation(int h) const {
  const int n = model_.num_dofs();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(h == 0 ? n : 2 * n);
  for (const HarmonicLoad& load : model_.loads) {
    if (load.harmonic != h) continue;
    f.head(n) += load.cos;
    if (h > 0) f.tail(n) += load.sin;
  }
  return f;
}

void CondensedSystem::EffectiveBlocks(int c, EffectiveForceBlocks* out) const {
  const ContactForceBlocks& f = blocks_[c];
  const double kt = model_.contacts[c].kt, kn = model_.contacts[c].kn;
  const int nh = 2 * options_.harmonics + 1;
  // Fully stuck, T and N are linear in the harmonics h ≥ 1 with the stick stiffness, so those
  // entries of F̃ = F − k u vanish but for the AFT's round-off: they are set to exact zeros, which
  // leaves unit columns in the Jacobian that the dense LU eliminates (the mean, which sets no
  // static tangential force under α, keeps its derivative).
  const double floor = FullStick(f) ? 1e-12 : 0.0;
  const auto clean = [floor](double value, double k) {
    return std::abs(value) <= floor * k ? 0.0 : value;
  };
  out->tu.resize(nh, nh);
  out->tv.resize(nh, nh);
  out->nv.resize(nh, nh);
  for (int l = 0; l < nh; ++l) {
    for (int j = 0; j < nh; ++j) {
      const double stick = j == l ? 1.0 : 0.0;
      out->tu(j, l) = clean(f.dt_du(j, l) - kt * stick, kt);
      out->tv(j, l) = clean(f.dt_dv(j, l), kn);
      out->nv(j, l) = clean(f.dn_dv(j, l) - kn * stick, kn);
    }
  }
}

Eigen::MatrixXd CondensedSystem::TimesForceJacobian(int h, const Eigen::MatrixXd& a) const {
  const int nc = num_contacts(), nr = num_relative(), nh = 2 * options_.harmonics + 1;
  const std::vector<int> js = Coefficients(h);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(a.rows(), nr * nh);
  EffectiveForceBlocks d;
  for (int c = 0; c < nc; ++c) {
    EffectiveBlocks(c, &d);
    const int rt = row_t_[c], rn = row_n_[c];
    for (size_t jj = 0; jj < js.size(); ++jj) {
      const int j = js[jj];
      const auto col_t = a.col(static_cast<int>(jj) * nr + rt);  // rows of F̃ (j, T)
      const auto col_n = a.col(static_cast<int>(jj) * nr + rn);  // rows of F̃ (j, N)
      for (int l = 0; l < nh; ++l) {
        const double tu = d.tu(j, l), tv = d.tv(j, l), nv = d.nv(j, l);
        if (tu != 0.0) out.col(l * nr + rt) += tu * col_t;
        if (tv != 0.0) out.col(l * nr + rn) += tv * col_t;
        if (nv != 0.0) out.col(l * nr + rn) += nv * col_n;
      }
    }
  }
  return out;
}

Eigen::MatrixXd CondensedSystem::ContactForceJacobian(const Eigen::VectorXd& x,
                                                      const Eigen::VectorXd& alpha,
                                                      const std::vector<bool>& as_springs) const {
  CheckInputs(x, alpha);
  ContactForces(x, alpha, AftDerivatives{true, false});
  const int nr = num_relative(), nh = 2 * options_.harmonics + 1;
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(nh * nr, nh * nr);
  EffectiveForceBlocks e;
  for (int c = 0; c < num_contacts(); ++c) {
    if (static_cast<size_t>(c) < as_springs.size() && as_springs[static_cast<size_t>(c)]) continue;
    EffectiveBlocks(c, &e);
    const int rt = row_t_[c], rn = row_n_[c];
    for (int j = 0; j < nh; ++j) {
      for (int l = 0; l < nh; ++l) {
        d(j * nr + rt, l * nr + rt) += e.tu(j, l);
        d(j * nr + rt, l * nr + rn) += e.tv(j, l);
        d(j * nr + rn, l * nr + rn) += e.nv(j, l);
      }
    }
  }
  return d;
}

std::unique_ptr<JacobianOperator> CondensedSystem::Linearize(const Eigen::VectorXd& x, double omega,
                                                             const Eigen::VectorXd& alpha) const {
  CheckInputs(x, alpha);
  receptance_->SetFrequency(omega, options_.harmonics);
  ContactForces(x, alpha, AftDerivatives{true, false});
  CondensedJacobianData data;
  data.harmonics = options_.harmonics;
  data.num_relative = num_relative();
  data.w = w_;
  data.sy = sy_;
  data.row_t = row_t_;
  data.row_n = row_n_;
  data.blocks.resize(num_contacts());
  for (int c = 0; c < num_contacts(); ++c) EffectiveBlocks(c, &data.blocks[c]);
  data.receptance = receptance_;
  data.omega = omega;
  return MakeCondensedJacobian(std::move(data));
}

void CondensedSystem::Evaluate(const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& alpha,
                               const HbmRequest& request, HbmEvaluation* out) const {
  CheckInputs(x, alpha);
  receptance_->SetFrequency(omega, options_.harmonics);
  const int nr = num_relative(), nc = num_contacts();
  const int nh = 2 * options_.harmonics + 1, nx = num_unknowns();
  const Eigen::VectorXd ft =
      ContactForces(x, alpha, AftDerivatives{request.jacobian, request.alpha_jacobian});
  out->residual.resize(nx);
  if (request.jacobian) out->jacobian.setZero(nx, nx);
  if (request.alpha_jacobian) out->alpha_jacobian.setZero(nx, nc);
  if (request.omega_derivative) out->omega_derivative.resize(nx);
  for (int h = 0; h <= options_.harmonics; ++h) {
    const std::vector<int> js = Coefficients(h);
    const int m = static_cast<int>(js.size());
    // G_h itself only for the Jacobians (the modal receptance forms it on first use at an ω).
    const Eigen::MatrixXd* g_h =
        request.jacobian || request.alpha_jacobian ? &receptance_->G(h) : nullptr;
    const Eigen::MatrixXd& pr = receptance_->DofPRows(h);  // response rows of P_h
    // x̃_h = Z̃_h⁻¹ (f_h − B_hᵀ F̃_h): only its relative part and the response are needed here,
    // both from per-ω quantities (the full x̃_h only for ∂/∂ω).
    const Eigen::VectorXd fs = Stack(h, ft);
    Eigen::VectorXd bx;
    receptance_->GTimes(h, fs, false, &bx);
    bx = receptance_->LoadRelative(h) - bx;
    Eigen::VectorXd y(m);  // response coefficients
    for (int jj = 0; jj < m; ++jj) {
      y[jj] = receptance_->LoadResponseAtDof(h)[jj] - pr.row(jj).dot(fs);
    }
    Eigen::VectorXd bd, dy;  // B ∂x̃_h/∂ω and the response's ∂x̃_h/∂ω
    if (request.omega_derivative) receptance_->OmegaDerivative(h, fs, &bd, &dy);
    for (int jj = 0; jj < m; ++jj) {
      const int j = js[jj];
      for (int i = 0; i < nr; ++i) {
        out->residual[Idx(j, i)] = w_[i] * (x[Idx(j, i)] - bx[jj * nr + i]);
      }
      out->residual[Idx(j, nr)] = sy_ * (x[Idx(j, nr)] - y[jj]);
      if (request.omega_derivative) {
        for (int i = 0; i < nr; ++i) out->omega_derivative[Idx(j, i)] = -w_[i] * bd[jj * nr + i];
        out->omega_derivative[Idx(j, nr)] = -sy_ * dy[jj];
      }
    }
    if (request.jacobian) {
      const Eigen::MatrixXd gdf = TimesForceJacobian(h, *g_h);
      const Eigen::MatrixXd pdf = TimesForceJacobian(h, pr);
      for (int jj = 0; jj < m; ++jj) {
        const int j = js[jj];
        for (int l = 0; l < nh; ++l) {
          out->jacobian.block(Idx(j, 0), Idx(l, 0), nr, nr).noalias() =
              w_.asDiagonal() * gdf.block(jj * nr, l * nr, nr, nr);
          out->jacobian.block(Idx(j, nr), Idx(l, 0), 1, nr) = sy_ * pdf.block(jj, l * nr, 1, nr);
        }
        for (int i = 0; i < nr; ++i) out->jacobian(Idx(j, i), Idx(j, i)) += w_[i];
        out->jacobian(Idx(j, nr), Idx(j, nr)) = sy_;
      }
    }
    if (request.alpha_jacobian) {
      for (int c = 0; c < nc; ++c) {
        for (int jj = 0; jj < m; ++jj) {
          const double dt = blocks_[c].dt_dalpha[js[jj]];
          if (dt == 0.0) continue;
          for (int kk = 0; kk < m; ++kk) {
            for (int i = 0; i < nr; ++i) {
              out->alpha_jacobian(Idx(js[kk], i), c) +=
                  w_[i] * (*g_h)(kk * nr + i, jj * nr + row_t_[c]) * dt;
            }
            out->alpha_jacobian(Idx(js[kk], nr), c) += sy_ * pr(kk, jj * nr + row_t_[c]) * dt;
          }
        }
      }
    }
  }
}

double CondensedSystem::ResidualScale() const { return full_->ResidualScale(); }

Eigen::VectorXd CondensedSystem::StickLinearSolution(double omega) const {
  // x̃_h = Z̃_h⁻¹ f_h through the receptance (K + K_stick); the preloaded normal springs push A
  // and B apart: −Bᵀ p with p the preloads on the normal rows.
  receptance_->SetFrequency(omega, options_.harmonics);
  const int n = model_.num_dofs(), nr = num_relative();
  Eigen::VectorXd preload = Eigen::VectorXd::Zero(nr);
  for (int c = 0; c < num_contacts(); ++c) preload[row_n_[c]] += model_.contacts[c].normal_preload;
  Eigen::VectorXd full(n * (2 * options_.harmonics + 1));
  for (int h = 0; h <= options_.harmonics; ++h) {
    Eigen::VectorXd f = Excitation(h);
    if (h == 0) f -= b_.transpose() * preload;
    const Eigen::VectorXd xt = receptance_->Solve(h, f);
    const std::vector<int> js = Coefficients(h);
    for (size_t jj = 0; jj < js.size(); ++jj) {
      full.segment(js[jj] * n, n) = xt.segment(static_cast<int>(jj) * n, n);
    }
  }
  return Condense(full);
}

double CondensedSystem::Amplitude(const Eigen::VectorXd& x) const {
  const int nr = num_relative();
  return std::hypot(x[Idx(1, nr)], x[Idx(2, nr)]);
}

Eigen::VectorXd CondensedSystem::AmplitudeSquaredGradient(const Eigen::VectorXd& x) const {
  const int nr = num_relative();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(num_unknowns());
  g[Idx(1, nr)] = 2.0 * x[Idx(1, nr)];
  g[Idx(2, nr)] = 2.0 * x[Idx(2, nr)];
  return g;
}

Eigen::VectorXd CondensedSystem::Recover(const Eigen::VectorXd& x, double omega,
                                         const Eigen::VectorXd& alpha) const {
  CheckInputs(x, alpha);
  receptance_->SetFrequency(omega, options_.harmonics);
  const int n = model_.num_dofs();
  const Eigen::VectorXd ft = ContactForces(x, alpha, AftDerivatives{});
  Eigen::VectorXd full(n * (2 * options_.harmonics + 1));
  for (int h = 0; h <= options_.harmonics; ++h) {
    const std::vector<int> js = Coefficients(h);
    const Eigen::VectorXd xt = receptance_->LoadResponse(h) - receptance_->TimesP(h, Stack(h, ft));
    for (size_t jj = 0; jj < js.size(); ++jj) {
      full.segment(js[jj] * n, n) = xt.segment(static_cast<int>(jj) * n, n);
    }
  }
  return full;
}

Eigen::VectorXd CondensedSystem::Condense(const Eigen::VectorXd& x_full) const {
  const int n = model_.num_dofs(), nr = num_relative(), nh = 2 * options_.harmonics + 1;
  if (x_full.size() != n * nh) {
    throw std::invalid_argument("CondensedSystem::Condense: expected " + std::to_string(n * nh) +
                                " full coefficients, got " + std::to_string(x_full.size()));
  }
  Eigen::VectorXd x(num_unknowns());
  for (int j = 0; j < nh; ++j) {
    x.segment(Idx(j, 0), nr) = b_ * x_full.segment(j * n, n);
    x[Idx(j, nr)] = x_full[j * n + model_.response_dof];
  }
  for (int h = 1; h <= options_.harmonics && next_.size() > 0; ++h) {
    // The cyclic rows read the next sector's harmonic h delayed (HarmonicReceptance::Relative).
    Eigen::VectorXd block(2 * n);
    block << x_full.segment((2 * h - 1) * n, n), x_full.segment(2 * h * n, n);
    const Eigen::VectorXd r = receptance_->Relative(h, block);
    x.segment(Idx(2 * h - 1, 0), nr) = r.head(nr);
    x.segment(Idx(2 * h, 0), nr) = r.tail(nr);
  }
  return x;
}

std::vector<ContactHistory> CondensedSystem::ContactHistories(const Eigen::VectorXd& x,
                                                              double omega,
                                                              const Eigen::VectorXd& alpha) const {
  return full_->ContactHistories(Recover(x, omega, alpha), omega, alpha);
}

std::vector<ContactRegime> CondensedSystem::ContactRegimes(const Eigen::VectorXd& x,
                                                           double /*omega*/,
                                                           const Eigen::VectorXd& alpha) const {
  CheckInputs(x, alpha);
  ContactForces(x, alpha, AftDerivatives{});
  std::vector<ContactRegime> out;
  for (const ContactForceBlocks& b : blocks_) out.push_back(ClassifyRegime(b.law.states));
  return out;
}

CycleEnergy CondensedSystem::Energies(const Eigen::VectorXd& x, double omega,
                                      const Eigen::VectorXd& alpha) const {
  return full_->Energies(Recover(x, omega, alpha), omega, alpha);
}

double CondensedSystem::LossFactor(const Eigen::VectorXd& x, double omega,
                                   const Eigen::VectorXd& alpha, const HbmEvaluation& e,
                                   Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_alpha) const {
  (void)e;  // η is evaluated on the recovered full solution
  const Eigen::VectorXd xf = Recover(x, omega, alpha);
  HbmEvaluation ef;
  HbmRequest req;
  req.jacobian = req.alpha_jacobian = grad_x != nullptr;
  full_->Evaluate(xf, omega, alpha, req, &ef);
  Eigen::VectorXd gxf, gaf;
  const double eta =
      full_->LossFactor(xf, omega, alpha, ef, grad_x ? &gxf : nullptr, grad_x ? &gaf : nullptr);
  if (grad_x == nullptr) return eta;
  // Chain rule through x̃(r, α) = Z̃⁻¹(f − Bᵀ F̃(r, α)): ∂x̃_h = −P_h ∂F̃_h.
  ContactForces(x, alpha, AftDerivatives{true, true});  // refresh the derivative blocks at x
  const int n = model_.num_dofs(), nr = num_relative(), nc = num_contacts();
  const int nh = 2 * options_.harmonics + 1;
  grad_x->setZero(num_unknowns());
  *grad_alpha = gaf;
  for (int h = 0; h <= options_.harmonics; ++h) {
    const std::vector<int> js = Coefficients(h);
    const int m = static_cast<int>(js.size());
    Eigen::VectorXd gh(m * n);
    for (int jj = 0; jj < m; ++jj) gh.segment(jj * n, n) = gxf.segment(js[jj] * n, n);
    const Eigen::RowVectorXd v = -receptance_->TransposeTimesP(h, gh).transpose();
    const Eigen::MatrixXd vdf = TimesForceJacobian(h, v);
    for (int l = 0; l < nh; ++l) {
      for (int i = 0; i < nr; ++i) (*grad_x)[Idx(l, i)] += vdf(0, l * nr + i);
    }
    for (int c = 0; c < nc; ++c) {
      for (int jj = 0; jj < m; ++jj)
        (*grad_alpha)[c] += v[jj * nr + row_t_[c]] * blocks_[c].dt_dalpha[js[jj]];
    }
  }
  return eta;
}

}  // namespace fricrom
