// Reduced-space bound runs: projected gradient over α with Newton (or chord) solves of R = 0
// and the adjoint reduced gradient.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bound_runs.h"
#include "box_lbfgs.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "gauss_newton_target.h"
#include "linear/dense_lapack.h"
#include "linear/gmres.h"
#include "solve/newton_preconditioned.h"

namespace fricrom::bounds_detail {
namespace {

// Adjoint solves by GMRES: relative residual and products before a new LU is preferred.
constexpr double kAdjointTolerance = 1e-10;
constexpr int kAdjointProducts = 16;

// Chord iterations x ← x − J₀⁻¹ R(x) with the factorised transpose J₀ᵀ of the last accepted
// point. Where no contact changes state between the two α the balance is linear in x (stick) or
// nearly so, and one or two steps converge without a new factorisation. On success x solves
// R = 0 to Newton's tolerance; on failure x is the iterate with the smallest residual (the start
// if no step reduced it), *r_best its R: a warm start for Newton (the first chord step is
// Newton's first step up to the Jacobian's change with α).
bool ChordSolve(const SquareSystem& at, const dense::Lu& lu_transposed, const NewtonOptions& o,
                Eigen::VectorXd* x, Eigen::VectorXd* r_best) {
  constexpr int kChordSteps = 4;
  const double scale = at.ResidualScale();
  Eigen::VectorXd r, x_trial, r_trial;
  at.Evaluate(*x, &r, nullptr);
  double norm = r.norm() / scale;
  for (int k = 0; k < kChordSteps && norm > o.residual_tolerance && std::isfinite(norm); ++k) {
    x_trial = *x - lu_transposed.Solve(r, true);
    at.Evaluate(x_trial, &r_trial, nullptr);
    const double trial = r_trial.norm() / scale;
    if (!(trial < norm)) break;  // no progress: Newton takes over from the best iterate
    x->swap(x_trial);
    r.swap(r_trial);
    const bool slow = !(trial < 0.25 * norm);  // too slow a contraction: Newton takes over
    norm = trial;
    if (slow) break;
  }
  *r_best = std::move(r);
  return norm <= o.residual_tolerance;
}

// The adjoint system (∂R/∂x)ᵀ λ = rhs by GMRES preconditioned with `lu` (a factorised (∂R/∂x)ᵀ),
// on the matrix-free Jacobian `op` if there is one, else on the dense `jacobian`. A `guess`
// (the adjoint of the run's last iterate, empty if none) that leaves a smaller residual than 0
// is corrected instead: GMRES solves for the correction to the same absolute tolerance.
bool AdjointByGmres(const JacobianOperator* op, const Eigen::MatrixXd& jacobian,
                    const dense::Lu& lu, const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess,
                    Eigen::VectorXd* lambda) {
  const dense::LinearMap apply = [op, &jacobian](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
    if (op != nullptr) {
      op->Apply(v, true, out);
    } else {
      *out = jacobian.transpose() * v;
    }
  };
  const double rhs_norm = rhs.norm();
  if (guess.size() == rhs.size() && rhs_norm > 0.0) {
    Eigen::VectorXd r0;
    apply(guess, &r0);
    r0 = rhs - r0;
    const double r0_norm = r0.norm();
    if (r0_norm <= kAdjointTolerance * rhs_norm) {
      *lambda = guess;
      return true;
    }
    if (r0_norm < 0.5 * rhs_norm) {
      Eigen::VectorXd e;
      const bool ok =
          dense::PreconditionedGmres(apply, lu, false, r0, kAdjointTolerance * rhs_norm / r0_norm,
                                     kAdjointProducts - 1, &e)
              .converged;
      *lambda = guess + e;
      return ok;
    }
  }
  if (op != nullptr) {
    return dense::PreconditionedGmres(apply, lu, false, rhs, kAdjointTolerance, kAdjointProducts,
                                      lambda)
        .converged;
  }
  return dense::PreconditionedGmres(jacobian, true, lu, false, rhs, kAdjointTolerance,
                                    kAdjointProducts, lambda)
      .converged;
}

// φ and the reduced gradient at a solution (x, a) by one adjoint solve (∂R/∂x)ᵀ λ = ∂φ/∂x.
// Large systems (`krylov_ok`) first try GMRES preconditioned with `previous`, the factorised
// (∂R/∂x)ᵀ of an earlier point (nearby points differ in a few contacts' blocks); else a new LU.
// *lu receives the factorisation used.
bool ValueAndGradient(const RunSetup& s, bool krylov_ok, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& a, const std::shared_ptr<const dense::Lu>& previous,
                      const Eigen::VectorXd& lambda_guess, double* phi, Eigen::VectorXd* g,
                      std::shared_ptr<const dense::Lu>* lu, Eigen::VectorXd* lambda) {
  // The amplitude objective needs no ∂R/∂x of its own: with an earlier LU to precondition,
  // the adjoint GMRES runs on the matrix-free Jacobian and the dense one is formed only
  // if it misses (the loss factor's gradient reads the dense Jacobian).
  const bool krylov = krylov_ok && previous;
  const std::unique_ptr<JacobianOperator> op = krylov && s.objective != BoundsOptions::kLossFactor
                                                   ? s.system->Linearize(x, s.omega, a)
                                                   : nullptr;
  HbmEvaluation e;
  HbmRequest req;
  req.alpha_jacobian = true;
  req.jacobian = op == nullptr;
  s.system->Evaluate(x, s.omega, a, req, &e);
  Eigen::VectorXd gx, ga;
  *phi = Objective(s, x, a, e, &gx, &ga);
  bool solved = false;
  if (op) {
    solved = AdjointByGmres(op.get(), e.jacobian, *previous, gx, lambda_guess, lambda);
    if (!solved) {
      req.alpha_jacobian = false;
      req.jacobian = true;
      HbmEvaluation ej;
      s.system->Evaluate(x, s.omega, a, req, &ej);
      e.jacobian = std::move(ej.jacobian);
    }
  } else if (krylov) {
    solved = AdjointByGmres(nullptr, e.jacobian, *previous, gx, lambda_guess, lambda);
  }
  if (solved) {
    *lu = previous;
  } else {
    // A new factorisation: single precision on large systems (it serves mostly as the next
    // preconditioner), with GMRES restoring double accuracy; double if that misses.
    auto fresh = std::make_shared<dense::Lu>();
    fresh->ComputeTransposed(e.jacobian,
                             krylov_ok ? dense::LuPrecision::kSingle : dense::LuPrecision::kDouble);
    if (!fresh->exact()) {
      solved = dense::PreconditionedGmres(e.jacobian, true, *fresh, false, gx, kAdjointTolerance,
                                          kAdjointProducts, lambda)
                   .converged;
      if (!solved) fresh->ComputeTransposed(e.jacobian);
    }
    if (!(fresh->rcond() > 1e-14)) return false;
    if (!solved) *lambda = fresh->Solve(gx);
    *lu = std::move(fresh);
  }
  *g = ga - e.alpha_jacobian.transpose() * *lambda;
  return g->allFinite();
}

// ∂q/∂α at the solution (x, α) of q(α) = a0·b1(α) − b0·a1(α), (a0, b0) the response phasor at
// x: the response's sensitivity across its phasor, which with the gradient of φ = |y|² (along
// it) spans the 2×nα Jacobian ∂y/∂α a Gauss-Newton step needs. `lu` is the factorised
// (∂R/∂x)ᵀ of this point (`exact_here`) or of a nearby one, which preconditions GMRES on the
// matrix-free Jacobian (a new LU if that misses).
bool QuadratureGradient(const RunSetup& s, const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                        const dense::Lu& lu, bool exact_here, Eigen::VectorXd* jq) {
  const HarmonicBalance& sys = *s.system;
  const auto [ic, is] = sys.ResponseCoefficients();
  Eigen::VectorXd qx = Eigen::VectorXd::Zero(sys.num_unknowns()), lambda;
  qx[ic] = -x[is];
  qx[is] = x[ic];
  HbmRequest req;
  req.alpha_jacobian = true;
  HbmEvaluation e;
  if (exact_here && lu.exact()) {
    sys.Evaluate(x, s.omega, a, req, &e);
    lambda = lu.Solve(qx);
  } else {
    const std::unique_ptr<JacobianOperator> op = sys.Linearize(x, s.omega, a);
    req.jacobian = op == nullptr;
    sys.Evaluate(x, s.omega, a, req, &e);
    if (!AdjointByGmres(op.get(), e.jacobian, lu, qx, Eigen::VectorXd(), &lambda)) {
      if (op) {
        HbmRequest jreq;
        jreq.jacobian = true;
        HbmEvaluation ej;
        sys.Evaluate(x, s.omega, a, jreq, &ej);
        e.jacobian = std::move(ej.jacobian);
      }
      dense::Lu fresh;
      fresh.ComputeTransposed(e.jacobian);
      if (!(fresh.rcond() > 1e-14)) return false;
      lambda = fresh.Solve(qx);
    }
  }
  *jq = -(e.alpha_jacobian.transpose() * lambda);
  return jq->allFinite();
}

// Whether a run at objective phi (after gains.size() iterations with these decreases) is
// dominated by `incumbent` (RunSetup): judged after kJudgeAfter iterations, against kGainMargin
// times the best decrease per iteration over the last kJudgeAfter (the rate it crawls at now,
// not that of a first jump), over the iterations left.
bool Dominated(double incumbent, double phi, const std::vector<double>& gains, int left) {
  constexpr std::ptrdiff_t kJudgeAfter = 10;
  constexpr double kGainMargin = 10.0;
  if (!std::isfinite(incumbent) || std::ssize(gains) < kJudgeAfter) return false;
  const double recent = *std::max_element(gains.end() - kJudgeAfter, gains.end());
  return phi - incumbent > kGainMargin * recent * left;
}

// One reduced-space run (RunReduced): projected gradient over the α box with Barzilai-Borwein
// steps (maximum runs: limited-memory BFGS directions, RunSetup::bfgs_memory) and a
// (nonmonotone) Armijo backtracking; x(α) by chord steps or Newton warm-started at the
// last iterate, so that every iterate satisfies R = 0; the reduced gradient
// g = ∂φ/∂α − (∂R/∂α)ᵀ(∂R/∂x)⁻ᵀ∂φ/∂x by one adjoint solve.
class ReducedRun {
 public:
  ReducedRun(const RunSetup& s, int seed, int max_iterations, double tolerance)
      : s_(s),
        sys_(*s.system),
        max_iterations_(max_iterations),
        tolerance_(tolerance),
        // Chord steps and reused factorisations pay off where an LU is dear; small (lumped)
        // systems keep plain Newton and a new LU per point.
        chord_(sys_.num_unknowns() >= dense::kLapackMinSize),
        gauss_newton_(s.gauss_newton && s.objective == BoundsOptions::kAmplitude && s.sign > 0.0),
        memory_(std::max(s.line_search_memory, 1)),
        bfgs_(s.bfgs_memory) {
    out_.seed = seed;
    // A line-search solve that stalls is ended early: its trial step is halved anyway. On the
    // FE cascade (1082.65 and 1103.06 Hz) 1 of 2375 line-search solves that converged had
    // crawled 8 steps at < 1 %, while failed ones spent 35-51 % of their iterations past that
    // point.
    newton_.stall_window = 8;
  }

  BoundSolution Run(const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                    const StartGradient* start);

 private:
  struct Trial {
    Eigen::VectorXd x, a, g, lambda;
    double phi = 0.0;
    std::shared_ptr<const dense::Lu> lu;
    std::vector<ContactRegime> regimes;  // empty unless the chord steps computed them
    bool newton_failed = false;          // some trial of the line search failed in Newton
    double step = 0.0;                   // the step of the last trial
  };

  // φ and g at (x, a); the adjoint GMRES starts from the current iterate's λ.
  bool Gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double* phi, Eigen::VectorXd* g,
                const std::shared_ptr<const dense::Lu>& previous,
                std::shared_ptr<const dense::Lu>* lu, Eigen::VectorXd* lambda) const {
    return ValueAndGradient(s_, chord_, x, a, previous, lambda_, phi, g, lu, lambda);
  }
  bool SolveTrial(Trial* t);
  double TrialObjective(const Eigen::VectorXd& x, const Eigen::VectorXd& a) const;
  bool CompleteTrial(Trial* t) const;
  bool TryGaussNewton(Trial* t);
  bool LineSearch(double reference, Trial* t);
  bool BfgsLineSearch(double reference, Trial* t);
  bool BackToBest();
  bool Stalled();
  void EndOnBest();
  BoundSolution Finish(BoundStatus status, const std::string& message);

  const RunSetup& s_;
  const HarmonicBalance& sys_;
  const int max_iterations_;
  const double tolerance_;
  const bool chord_;
  NewtonOptions newton_;
  BoundSolution out_;
  // The current iterate (x_, a_ solve R = 0) with its objective, gradient, adjoint, LU and
  // regimes.
  Eigen::VectorXd x_, a_, g_, lambda_;
  double phi_ = 0.0;
  std::shared_ptr<const dense::Lu> lu_;
  std::vector<ContactRegime> regimes_;
  double step_ = 0.0;
  // A trial α that Newton cannot reach from x costs a failed solve (~10x a converging one on
  // the FE cascade) and halves the step; after a jump of the Barzilai-Borwein step a run spent
  // up to ten such failures per iteration (1098.98 Hz, H = 1: 190 of 217 solves, 8.8 of 9.5 s).
  // After an iteration with a failed solve the next step is capped at the one accepted; the cap
  // doubles with every iteration without one.
  double step_cap_ = std::numeric_limits<double>::infinity();
  int quiet_ = 0;
  // Gauss-Newton steps towards y = 0 (RunSetup::gauss_newton): minimum runs of the amplitude
  // only; after a failed one the next waits gn_backoff_ iterations (2, doubled with every
  // failure up to 64).
  const bool gauss_newton_;
  int gn_wait_ = 0;
  int gn_backoff_ = 2;
  std::vector<double> gains_;         // decrease of the objective per accepted iteration
  std::vector<double> best_history_;  // the best objective after each accepted iteration
  // Nonmonotone line search (BoundsOptions::line_search_memory): the last objectives a step is
  // measured against, and the best iterate, which the run ends on.
  int memory_;
  std::vector<double> recent_;
  // Quasi-Newton directions (RunSetup::bfgs_memory > 0) and the cap on their moves in α (inf
  // norm): after an iteration with a failed solve the accepted move, doubled with every
  // iteration without one (the role step_cap_ plays for the gradient steps).
  BoxLbfgs bfgs_;
  double move_cap_ = std::numeric_limits<double>::infinity();
  struct Iterate {
    Eigen::VectorXd x, a, g, lambda;
    double phi = 0.0;
    std::shared_ptr<const dense::Lu> lu;
  } best_;
};

BoundSolution ReducedRun::Finish(BoundStatus status, const std::string& message) {
  out_.x = x_;
  out_.alpha = a_;
  out_.status = status;
  out_.message = message;
  out_.stationary = status == BoundStatus::kConverged;
  Describe(sys_, s_.omega, &out_);
  if (out_.status == BoundStatus::kConverged && !(out_.residual <= kFeasibility)) {
    out_.status = BoundStatus::kFailed;
    out_.stationary = false;
    out_.message += "; the point violates R = 0";
  }
  return out_;
}

// A stopping test met above the best iterate (only possible with memory > 1): back to the best,
// and on monotonically from there, so that a run's result is its best stationary point.
bool ReducedRun::BackToBest() {
  if (!(phi_ > best_.phi)) return false;
  x_ = best_.x;
  a_ = best_.a;
  g_ = best_.g;
  lambda_ = best_.lambda;
  phi_ = best_.phi;
  lu_ = best_.lu;
  if (chord_) regimes_ = sys_.ContactRegimes(x_, s_.omega, a_);
  memory_ = 1;
  recent_.assign(1, phi_);
  quiet_ = 0;
  step_ = 0.5 / std::max(g_.lpNorm<Eigen::Infinity>(), 1e-300);
  step_cap_ = std::numeric_limits<double>::infinity();
  move_cap_ = std::numeric_limits<double>::infinity();
  bfgs_.Clear();
  return true;
}

// Whether the best objective improved by at most stall_change (relative) over the last
// stall_window accepted iterations (RunSetup::stall_change), after recording the current one.
bool ReducedRun::Stalled() {
  if (s_.stall_window <= 0) return false;
  best_history_.push_back(best_.phi);
  const std::ptrdiff_t n = std::ssize(best_history_);
  if (n <= s_.stall_window) return false;
  const double before = best_history_[n - 1 - s_.stall_window];
  return before - best_.phi <= s_.stall_change * std::abs(best_.phi);
}

void ReducedRun::EndOnBest() {
  if (!(phi_ > best_.phi)) return;
  x_ = best_.x;
  a_ = best_.a;
  phi_ = best_.phi;
}

// x(α_new) for t->a: chord steps with the last factorisation, kept only if every contact is in
// the regime it had at the last accepted point (a chord step can otherwise land on another
// branch, e.g. a lift-off the Newton path would not reach); else Newton. Then φ there; the
// gradient waits for the line search to accept the trial (CompleteTrial).
bool ReducedRun::SolveTrial(Trial* t) {
  const HbmAtFrequency at(sys_, s_.omega, t->a);
  t->x = x_;
  Eigen::VectorXd r_at_x;  // R at t->x (α_new), from the chord attempt
  if (chord_ && ChordSolve(at, *lu_, newton_, &t->x, &r_at_x)) {
    t->regimes = sys_.ContactRegimes(t->x, s_.omega, t->a);
    if (t->regimes == regimes_) {
      t->phi = TrialObjective(t->x, t->a);
      return true;
    }
    // A root where some contact changed its regime may lie on another branch: Newton from x_.
    t->x = x_;
    r_at_x.resize(0);
  }
  if (!SolveNewtonPreconditioned(at, newton_, NewtonPreconditioner{lu_.get(), true}, &t->x, nullptr,
                                 r_at_x.size() > 0 ? &r_at_x : nullptr)
           .IsSolutionUsable()) {
    t->newton_failed = true;
    return false;
  }
  t->regimes.clear();
  t->phi = TrialObjective(t->x, t->a);
  return true;
}

// φ at a solved point. The amplitude's is read off x; the loss factor's needs R at the point.
double ReducedRun::TrialObjective(const Eigen::VectorXd& x, const Eigen::VectorXd& a) const {
  HbmEvaluation e;
  if (s_.objective != BoundsOptions::kAmplitude) sys_.Evaluate(x, s_.omega, a, HbmRequest{}, &e);
  return Objective(s_, x, a, e, nullptr, nullptr);
}

// The gradient (adjoint, LU) of an accepted trial. Only accepted trials need it: on the FE
// cascade's 50-point curve 25-68 % of the solved trials were rejected by the line search, and
// their gradients took ~12 % of the curve.
bool ReducedRun::CompleteTrial(Trial* t) const {
  double phi = 0.0;
  return Gradient(t->x, t->a, &phi, &t->g, lu_, &t->lu, &t->lambda);
}

// A Gauss-Newton trial towards y = 0 (GaussNewtonTarget), kept where it halves φ; true if it
// was. One trial solve, no backtracking: a half step as well cost more than it found (10 points
// 1113-1132 Hz of the FE curve: 174 against 149 s, R <= 0.001 at every point with either).
bool ReducedRun::TryGaussNewton(Trial* t) {
  if (!gauss_newton_ || !(phi_ > 0.0)) return false;
  if (gn_wait_ > 0) {
    --gn_wait_;
    return false;
  }
  Eigen::VectorXd jq, target;
  if (QuadratureGradient(s_, x_, a_, *lu_, !chord_, &jq) &&
      GaussNewtonTarget(a_, g_, phi_, jq, &target)) {
    t->a = target;
    if (SolveTrial(t) && t->phi <= 0.5 * phi_ && CompleteTrial(t)) {
      t->newton_failed = false;
      t->step = step_;
      gn_backoff_ = 2;
      return true;
    }
  }
  *t = Trial{};  // the line search starts clean (no failed solve of this attempt counts there)
  gn_wait_ = gn_backoff_;
  gn_backoff_ = std::min(2 * gn_backoff_, 64);
  return false;
}

// Backtracking along the projected path α + τd, d the BFGS direction, from τ = 1 (or the move
// cap), each trial measured against `reference`. t->step is the move of the last trial (inf
// norm).
bool ReducedRun::BfgsLineSearch(double reference, Trial* t) {
  const Eigen::VectorXd d = bfgs_.Direction(a_, g_, step_);
  const double d_norm = d.lpNorm<Eigen::Infinity>();
  double tau = d_norm > move_cap_ ? move_cap_ / d_norm : 1.0;
  bool accepted = false;
  for (int bt = 0; bt < 40 && !accepted; ++bt, tau *= 0.5) {
    t->a = (a_ + tau * d).cwiseMax(-1.0).cwiseMin(1.0);
    if ((t->a - a_).lpNorm<Eigen::Infinity>() <= 1e-14) break;
    if (!SolveTrial(t)) continue;
    accepted = t->phi <= reference - 1e-4 * g_.dot(a_ - t->a) && CompleteTrial(t);
    t->step = (t->a - a_).lpNorm<Eigen::Infinity>();
  }
  return accepted;
}

// Backtracking along the projected-gradient path from step_, each trial measured against
// `reference` (the largest recent objective). On return step_ is half the last step tried.
bool ReducedRun::LineSearch(double reference, Trial* t) {
  if (s_.bfgs_memory > 0) return BfgsLineSearch(reference, t);
  bool accepted = false;
  t->step = step_;
  for (int bt = 0; bt < 40 && !accepted; ++bt, step_ *= 0.5) {
    t->a = (a_ - step_ * g_).cwiseMax(-1.0).cwiseMin(1.0);
    if ((t->a - a_).lpNorm<Eigen::Infinity>() <= 1e-14) break;
    if (!SolveTrial(t)) continue;
    accepted = t->phi <= reference - 1e-4 * g_.dot(a_ - t->a) && CompleteTrial(t);
    t->step = step_;
  }
  return accepted;
}

BoundSolution ReducedRun::Run(const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                              const StartGradient* start) {
  x_ = x0;
  a_ = a0;
  if (chord_) regimes_ = sys_.ContactRegimes(x_, s_.omega, a_);
  if (start != nullptr && start->lu) {
    // The KKT check's gradient of +φ: this run's objective is sign·φ, so are g and λ.
    phi_ = TrialObjective(x_, a_);
    g_ = s_.sign * start->g;
    lambda_ = s_.sign * start->lambda;
    lu_ = start->lu;
  } else if (!Gradient(x_, a_, &phi_, &g_, nullptr, &lu_, &lambda_)) {
    return Finish(BoundStatus::kFailed, "singular Jacobian at the start");
  }
  step_ = 0.5 / std::max(g_.lpNorm<Eigen::Infinity>(), 1e-300);  // first move ≤ 0.5 in α
  recent_.assign(1, phi_);
  best_ = Iterate{x_, a_, g_, lambda_, phi_, lu_};
  for (int it = 0; it < max_iterations_; ++it) {
    out_.iterations = it;
    // First-order conditions on the box: the projected gradient step vanishes.
    const Eigen::VectorXd pg = (a_ - g_).cwiseMax(-1.0).cwiseMin(1.0) - a_;
    if (pg.lpNorm<Eigen::Infinity>() <= tolerance_) {
      if (BackToBest()) continue;
      return Finish(BoundStatus::kConverged, "reduced space: projected gradient vanishes (KKT)");
    }
    Trial t;
    if (!TryGaussNewton(&t) && !LineSearch(*std::max_element(recent_.begin(), recent_.end()), &t)) {
      if (BackToBest()) continue;
      return Finish(BoundStatus::kConverged,
                    "reduced space: no descent along the projected gradient (nonsmooth "
                    "stationary point)");
    }
    const Eigen::VectorXd ds = t.a - a_, dg = t.g - g_;
    const double change = std::abs(phi_ - t.phi);
    gains_.push_back(phi_ - t.phi);
    if (Dominated(s_.incumbent, std::min(t.phi, best_.phi), gains_, max_iterations_ - it - 1)) {
      x_ = t.x;
      a_ = t.a;
      phi_ = t.phi;
      EndOnBest();
      out_.iterations = it + 1;
      return Finish(
          BoundStatus::kAbandoned,
          "reduced space: abandoned after " + std::to_string(it + 1) +
              " iterations, dominated (cannot reach the bound of a KKT start or the one held)");
    }
    x_ = std::move(t.x);
    a_ = std::move(t.a);
    g_ = std::move(t.g);
    lambda_ = std::move(t.lambda);
    phi_ = t.phi;
    lu_ = std::move(t.lu);
    if (phi_ < best_.phi) best_ = Iterate{x_, a_, g_, lambda_, phi_, lu_};
    if (phi_ <= s_.stop_below) {
      out_.iterations = it + 1;
      BoundSolution negligible =
          Finish(BoundStatus::kConverged, "reduced space: stopped at a negligible response");
      negligible.stationary = false;
      return negligible;
    }
    if (Stalled()) {
      EndOnBest();
      out_.iterations = it + 1;
      std::ostringstream message;
      message << "reduced space: best objective stalled (relative improvement <= "
              << s_.stall_change << " in " << s_.stall_window << " iterations)";
      return Finish(BoundStatus::kConverged, message.str());
    }
    recent_.push_back(phi_);
    if (std::ssize(recent_) > memory_) recent_.erase(recent_.begin());
    if (chord_) regimes_ = t.regimes.empty() ? sys_.ContactRegimes(x_, s_.omega, a_) : t.regimes;
    quiet_ = change <= s_.stationary_change * std::max(std::abs(phi_), 1.0) ? quiet_ + 1 : 0;
    if (quiet_ >= 3) {
      if (BackToBest()) continue;
      std::ostringstream message;
      message << "reduced space: objective stationary (relative change <= " << s_.stationary_change
              << " in 3 iterations)";
      return Finish(BoundStatus::kConverged, message.str());
    }
    const double sy = ds.dot(dg);
    step_ =
        sy > 0.0 ? std::clamp(ds.squaredNorm() / sy, 1e-8, 1e8) : 4.0 * step_;  // Barzilai-Borwein
    if (s_.bfgs_memory > 0) {
      bfgs_.Push(ds, dg);
      move_cap_ = t.newton_failed ? ds.lpNorm<Eigen::Infinity>() : 2.0 * move_cap_;
    } else {
      step_cap_ = t.newton_failed ? t.step : 2.0 * step_cap_;
      step_ = std::min(step_, step_cap_);
    }
  }
  EndOnBest();
  return Finish(BoundStatus::kMaxIterations, "reduced space: iteration limit");
}

}  // namespace

BoundSolution RunReduced(const RunSetup& s, const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                         int seed, int max_iterations, double tolerance,
                         const StartGradient* start) {
  return ReducedRun(s, seed, max_iterations, tolerance).Run(x0, a0, start);
}

}  // namespace fricrom::bounds_detail
