// Reduced-space bound runs: projected gradient over α with Newton (or chord) solves of R = 0
// and the adjoint reduced gradient.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bound_runs.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
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
// R = 0 to Newton's tolerance; on failure x is left as the best iterate (a warm start).
// *r_start receives R at the start x, which a Newton solve from there need not evaluate again.
bool ChordSolve(const SquareSystem& at, const dense::Lu& lu_transposed, const NewtonOptions& o,
                Eigen::VectorXd* x, Eigen::VectorXd* r_start) {
  constexpr int kChordSteps = 4;
  const double scale = at.ResidualScale();
  Eigen::VectorXd r, x_trial, r_trial;
  at.Evaluate(*x, &r, nullptr);
  *r_start = r;
  double norm = r.norm() / scale;
  for (int k = 0; k < kChordSteps && std::isfinite(norm); ++k) {
    if (norm <= o.residual_tolerance) return true;
    x_trial = *x - lu_transposed.Solve(r, true);
    at.Evaluate(x_trial, &r_trial, nullptr);
    const double trial = r_trial.norm() / scale;
    if (!(trial < 0.25 * norm)) return false;  // too slow a contraction: Newton takes over
    x->swap(x_trial);
    r.swap(r_trial);
    norm = trial;
  }
  return norm <= o.residual_tolerance;
}

// φ and the reduced gradient at a solution (x, a) by one adjoint solve (∂R/∂x)ᵀ λ = ∂φ/∂x.
// Large systems (`krylov_ok`) first try GMRES preconditioned with `previous`, the factorised
// (∂R/∂x)ᵀ of an earlier point (nearby points differ in a few contacts' blocks); else a new LU.
// *lu receives the factorisation used.
bool ValueAndGradient(const RunSetup& s, bool krylov_ok, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& a, const std::shared_ptr<const dense::Lu>& previous,
                      double* phi, Eigen::VectorXd* g, std::shared_ptr<const dense::Lu>* lu) {
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
  Eigen::VectorXd gx, ga, lambda;
  *phi = Objective(s, x, a, e, &gx, &ga);
  bool solved = false;
  if (op) {
    const dense::LinearMap apply = [&op](const Eigen::VectorXd& v, Eigen::VectorXd* out) {
      op->Apply(v, true, out);
    };
    solved = dense::PreconditionedGmres(apply, *previous, false, gx, kAdjointTolerance,
                                        kAdjointProducts, &lambda)
                 .converged;
    if (!solved) {
      req.alpha_jacobian = false;
      req.jacobian = true;
      HbmEvaluation ej;
      s.system->Evaluate(x, s.omega, a, req, &ej);
      e.jacobian = std::move(ej.jacobian);
    }
  } else if (krylov) {
    solved = dense::PreconditionedGmres(e.jacobian, true, *previous, false, gx, kAdjointTolerance,
                                        kAdjointProducts, &lambda)
                 .converged;
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
                                          kAdjointProducts, &lambda)
                   .converged;
      if (!solved) fresh->ComputeTransposed(e.jacobian);
    }
    if (!(fresh->rcond() > 1e-14)) return false;
    if (!solved) lambda = fresh->Solve(gx);
    *lu = std::move(fresh);
  }
  *g = ga - e.alpha_jacobian.transpose() * lambda;
  return g->allFinite();
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

}  // namespace

// Reduced-space run: projected gradient with Armijo backtracking and Barzilai-Borwein steps over
// the α box; x(α) from Newton warm-started at the last iterate, so every iterate satisfies R = 0,
// and the reduced gradient g = ∂φ/∂α − (∂R/∂α)ᵀ(∂R/∂x)⁻ᵀ∂φ/∂x by one adjoint solve.
BoundSolution RunReduced(const RunSetup& s, const Eigen::VectorXd& x0, const Eigen::VectorXd& a0,
                         int seed, int max_iterations, double tolerance) {
  const HarmonicBalance& sys = *s.system;
  BoundSolution out;
  out.seed = seed;
  // Chord steps and reused factorisations pay off where an LU is dear; small (lumped) systems
  // keep plain Newton and a new LU per point.
  const bool chord = sys.num_unknowns() >= dense::kLapackMinSize;
  auto value_and_gradient =
      [&](const Eigen::VectorXd& x, const Eigen::VectorXd& a, double* phi, Eigen::VectorXd* g,
          const std::shared_ptr<const dense::Lu>& previous, std::shared_ptr<const dense::Lu>* lu) {
        return ValueAndGradient(s, chord, x, a, previous, phi, g, lu);
      };
  Eigen::VectorXd x = x0, a = a0, g;
  double phi = 0.0;
  std::shared_ptr<const dense::Lu> lu, lu_new;
  std::vector<ContactRegime> regimes, regimes_new;
  if (chord) regimes = sys.ContactRegimes(x, s.omega, a);
  auto finish = [&](BoundStatus status, const std::string& message) {
    out.x = x;
    out.alpha = a;
    out.status = status;
    out.message = message;
    out.stationary = status == BoundStatus::kConverged;
    Describe(sys, s.omega, &out);
    if (out.status == BoundStatus::kConverged && !(out.residual <= kFeasibility)) {
      out.status = BoundStatus::kFailed;
      out.stationary = false;
      out.message += "; the point violates R = 0";
    }
    return out;
  };
  if (!value_and_gradient(x, a, &phi, &g, nullptr, &lu)) {
    return finish(BoundStatus::kFailed, "singular Jacobian at the start");
  }
  // A line-search solve that stalls is ended early: its trial step is halved anyway. On the FE
  // cascade (1082.65 and 1103.06 Hz) 1 of 2375 line-search solves that converged had crawled 8
  // steps at < 1 %, while failed ones spent 35-51 % of their iterations past that point.
  NewtonOptions newton;
  newton.stall_window = 8;
  double step = 0.5 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300);  // first move ≤ 0.5 in α
  // A trial α that Newton cannot reach from x costs a failed solve (~10x a converging one on the
  // FE cascade) and halves the step; after a jump of the Barzilai-Borwein step a run spent up to
  // ten such failures per iteration (1098.98 Hz, H = 1: 190 of 217 solves, 8.8 of 9.5 s). After
  // an iteration with a failed solve the next step is capped at the one accepted; the cap
  // doubles with every iteration without one.
  double step_cap = std::numeric_limits<double>::infinity();
  int quiet = 0;
  std::vector<double> gains;  // decrease of the objective per accepted iteration
  // Nonmonotone line search (BoundsOptions::line_search_memory): the last objectives a step is
  // measured against, and the best iterate, which the run ends on.
  int memory = std::max(s.line_search_memory, 1);
  std::vector<double> recent{phi};
  struct Iterate {
    Eigen::VectorXd x, a, g;
    double phi = 0.0;
    std::shared_ptr<const dense::Lu> lu;
  } best{x, a, g, phi, lu};
  // A stopping test met above the best iterate (only possible with memory > 1): back to the
  // best, and on monotonically from there, so that a run's result is its best stationary point.
  auto back_to_best = [&]() {
    if (!(phi > best.phi)) return false;
    x = best.x;
    a = best.a;
    g = best.g;
    phi = best.phi;
    lu = best.lu;
    if (chord) regimes = sys.ContactRegimes(x, s.omega, a);
    memory = 1;
    recent.assign(1, phi);
    quiet = 0;
    step = 0.5 / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300);
    step_cap = std::numeric_limits<double>::infinity();
    return true;
  };
  auto end_on_best = [&]() {
    if (!(phi > best.phi)) return;
    x = best.x;
    a = best.a;
    phi = best.phi;
  };
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it;
    // First-order conditions on the box: the projected gradient step vanishes.
    const Eigen::VectorXd pg = (a - g).cwiseMax(-1.0).cwiseMin(1.0) - a;
    if (pg.lpNorm<Eigen::Infinity>() <= tolerance) {
      if (back_to_best()) continue;
      return finish(BoundStatus::kConverged, "reduced space: projected gradient vanishes (KKT)");
    }
    bool accepted = false, newton_failed = false;
    double accepted_step = step;
    const double reference = *std::max_element(recent.begin(), recent.end());
    Eigen::VectorXd a_new, x_new, g_new;
    double phi_new = 0.0;
    for (int bt = 0; bt < 40 && !accepted; ++bt, step *= 0.5) {
      a_new = (a - step * g).cwiseMax(-1.0).cwiseMin(1.0);
      if ((a_new - a).lpNorm<Eigen::Infinity>() <= 1e-14) break;
      // x(α_new): chord steps with the last factorisation, kept only if every contact is in the
      // regime it had at the last accepted point (a chord step can otherwise land on another
      // branch, e.g. a lift-off the Newton path would not reach); else Newton.
      const HbmAtFrequency at(sys, s.omega, a_new);
      bool solved = false;
      x_new = x;
      Eigen::VectorXd r_at_x;  // R(x, α_new), from the chord attempt
      if (chord && ChordSolve(at, *lu, newton, &x_new, &r_at_x)) {
        regimes_new = sys.ContactRegimes(x_new, s.omega, a_new);
        solved = regimes_new == regimes &&
                 value_and_gradient(x_new, a_new, &phi_new, &g_new, lu, &lu_new);
      }
      if (!solved) {
        x_new = x;
        if (!SolveNewtonPreconditioned(at, newton, NewtonPreconditioner{lu.get(), true}, &x_new,
                                       nullptr, r_at_x.size() > 0 ? &r_at_x : nullptr)
                 .IsSolutionUsable()) {
          newton_failed = true;
          continue;
        }
        if (!value_and_gradient(x_new, a_new, &phi_new, &g_new, lu, &lu_new)) continue;
        regimes_new.clear();
      }
      accepted = phi_new <= reference - 1e-4 * g.dot(a - a_new);
      accepted_step = step;
    }
    if (!accepted) {
      if (back_to_best()) continue;
      return finish(BoundStatus::kConverged,
                    "reduced space: no descent along the projected gradient (nonsmooth "
                    "stationary point)");
    }
    const Eigen::VectorXd ds = a_new - a, dg = g_new - g;
    const double change = std::abs(phi - phi_new);
    gains.push_back(phi - phi_new);
    if (Dominated(s.incumbent, std::min(phi_new, best.phi), gains, max_iterations - it - 1)) {
      x = x_new;
      a = a_new;
      phi = phi_new;
      end_on_best();
      out.iterations = it + 1;
      return finish(BoundStatus::kAbandoned,
                    "reduced space: abandoned after " + std::to_string(it + 1) +
                        " iterations, dominated (cannot reach the bound of a KKT start)");
    }
    x = x_new;
    a = a_new;
    g = g_new;
    phi = phi_new;
    std::swap(lu, lu_new);
    if (phi < best.phi) best = Iterate{x, a, g, phi, lu};
    recent.push_back(phi);
    if (std::ssize(recent) > memory) recent.erase(recent.begin());
    if (chord) regimes = regimes_new.empty() ? sys.ContactRegimes(x, s.omega, a) : regimes_new;
    quiet = change <= tolerance * std::max(std::abs(phi), 1.0) ? quiet + 1 : 0;
    if (quiet >= 3) {
      if (back_to_best()) continue;
      return finish(BoundStatus::kConverged, "reduced space: objective stationary");
    }
    const double sy = ds.dot(dg);
    step =
        sy > 0.0 ? std::clamp(ds.squaredNorm() / sy, 1e-8, 1e8) : 4.0 * step;  // Barzilai-Borwein
    step_cap = newton_failed ? accepted_step : 2.0 * step_cap;
    step = std::min(step, step_cap);
  }
  end_on_best();
  return finish(BoundStatus::kMaxIterations, "reduced space: iteration limit");
}

}  // namespace fricrom::bounds_detail
