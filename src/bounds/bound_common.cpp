// Shared pieces of the bound runs (bound_runs.h): objective, KKT test at the start, description
// of a returned point, start solutions.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "bound_runs.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "fricrom/units.h"
#include "linear/dense_lapack.h"
#include "linear/gmres.h"

namespace fricrom::bounds_detail {
namespace {

double ResidualNorm(const HarmonicBalance& sys, const Eigen::VectorXd& x, double omega,
                    const Eigen::VectorXd& alpha) {
  HbmEvaluation e;
  sys.Evaluate(x, omega, alpha, HbmRequest{}, &e);
  return e.residual.norm() / sys.ResidualScale();
}

}  // namespace

// The run's objective sign·φ(x, α)/objective_scale (φ = a1² + b1² of the response DOF, or η) and,
// when grad_x is given, its gradient in the unscaled variables. `e` must hold R at (x, α) for the
// loss factor, and the Jacobians as well for its gradient.
double Objective(const RunSetup& s, const Eigen::VectorXd& x, const Eigen::VectorXd& alpha,
                 const HbmEvaluation& e, Eigen::VectorXd* grad_x, Eigen::VectorXd* grad_alpha) {
  const HarmonicBalance& sys = *s.system;
  const double factor = s.sign / s.objective_scale;
  if (s.objective == BoundsOptions::kAmplitude) {
    if (grad_x != nullptr) {
      *grad_x = factor * sys.AmplitudeSquaredGradient(x);
      grad_alpha->setZero(sys.num_alpha());
    }
    const double y = sys.Amplitude(x);
    return factor * y * y;
  }
  const double eta = sys.LossFactor(x, s.omega, alpha, e, grad_x, grad_alpha);
  if (grad_x != nullptr) {
    *grad_x *= factor;
    *grad_alpha *= factor;
  }
  return factor * eta;
}

// Whether the (feasible) start already satisfies the first-order optimality conditions: the
// reduced gradient g = ∂φ/∂α − (∂R/∂α)ᵀ (∂R/∂x)⁻ᵀ ∂φ/∂x vanishes (to `tolerance`) in every free
// α direction and points out of the box at an active bound. This is typical on the plateaus of
// the response over α (contacts that slip or whose first-period force saturates forget α), where
// the interior-point method would only spend its iterations driving the barrier to zero.
// The two directions differ only in the sign of φ: one adjoint solve serves both.
std::array<bool, 2> StartIsKktPoint(const RunSetup& s, const Eigen::VectorXd& x0,
                                    const Eigen::VectorXd& alpha0, double tolerance,
                                    const std::array<double, 2>& signs, StartGradient* gradient) {
  RunSetup plus = s;
  plus.sign = 1.0;
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = req.alpha_jacobian = true;
  s.system->Evaluate(x0, s.omega, alpha0, req, &e);
  Eigen::VectorXd gx, ga, lambda;
  Objective(plus, x0, alpha0, e, &gx, &ga);
  // Large systems: a single-precision LU and GMRES to double accuracy (half the cost).
  const bool large = e.jacobian.rows() >= dense::kLapackMinSize;
  auto lu = std::make_shared<dense::Lu>();
  lu->ComputeTransposed(e.jacobian,
                        large ? dense::LuPrecision::kSingle : dense::LuPrecision::kDouble);
  bool solved = false;
  if (!lu->exact() && lu->rcond() > 1e-6) {
    solved =
        dense::PreconditionedGmres(e.jacobian, true, *lu, false, gx, 1e-12, 20, &lambda).converged;
  }
  if (!solved) {
    if (!lu->exact()) lu->ComputeTransposed(e.jacobian);
    if (!(lu->rcond() > 1e-12)) return {false, false};
    lambda = lu->Solve(gx);
  }
  Eigen::VectorXd g_plus = ga - e.alpha_jacobian.transpose() * lambda;
  if (!g_plus.allFinite()) return {false, false};
  std::array<bool, 2> kkt{};
  for (int d = 0; d < 2; ++d) {
    kkt[d] = true;
    for (int c = 0; c < g_plus.size() && kkt[d]; ++c) {
      const double g = signs[d] * g_plus[c];
      const bool at_upper = alpha0[c] >= 1.0, at_lower = alpha0[c] <= -1.0;
      // Minimising: at the upper bound the gradient may be negative, at the lower one positive.
      kkt[d] = at_upper ? g <= tolerance : (at_lower ? g >= -tolerance : std::abs(g) <= tolerance);
    }
  }
  if (gradient != nullptr) {
    gradient->g = std::move(g_plus);
    gradient->lambda = std::move(lambda);
    gradient->lu = std::move(lu);
  }
  return kkt;
}

std::vector<ContactRegime> Regimes(const HarmonicBalance& sys, const Eigen::VectorXd& x,
                                   double omega, const Eigen::VectorXd& alpha) {
  std::vector<ContactRegime> out;
  for (const ContactHistory& h : sys.ContactHistories(x, omega, alpha)) out.push_back(h.regime);
  return out;
}

// Fills the derived fields of a solution (x, α set).
void Describe(const HarmonicBalance& sys, double omega, BoundSolution* s) {
  s->amplitude = sys.Amplitude(s->x);
  s->residual = ResidualNorm(sys, s->x, omega, s->alpha);
  s->loss_factor = sys.Energies(s->x, omega, s->alpha).loss_factor();
  s->regimes = Regimes(sys, s->x, omega, s->alpha);
}

void MarkUnfinishedAsBound(BoundSolution* s) {
  s->status = BoundStatus::kConverged;
  s->stationary = false;
  s->message += "; its last iterate (R = 0) goes beyond every converged run";
}

bool UsableUnfinished(const HarmonicBalance& sys, double omega, const BoundSolution& failed,
                      BoundSolution* out) {
  if (failed.status != BoundStatus::kMaxIterations || failed.x.size() != sys.num_unknowns() ||
      failed.alpha.size() != sys.num_alpha() || !failed.x.allFinite()) {
    return false;
  }
  *out = failed;
  Describe(sys, omega, out);  // the amplitude of a failed bound was set to NaN
  if (!(out->residual <= kFeasibility) || !std::isfinite(out->amplitude)) return false;
  MarkUnfinishedAsBound(out);
  return true;
}

// Points a seed's fallback path may take. A seed is one start among several: the path that
// works at 1103 Hz on the FE cascade (frequency continuation from 1.05 f) takes ~23 points;
// stalled ones ran to 2000, minutes per seed. Same bounds there with 40, 100 and 2000.
constexpr int kSeedFallbackPoints = 40;

// Points of the α homotopy for a start that may fall short of its α. At 1098.98 Hz on the FE
// cascade (H = 3, the ladder's minimum) 40 points reach λ = 0.23 and the run from there a
// minimum 21 % above the one the continuations in frequency lead to after 370 s; 200 points
// reach λ = 1 (884 evaluations, ~16 s) and the same minimum to 14 digits.
constexpr int kAlphaPathPoints = 200;

// A converged harmonic-balance solution at α to start from, cheapest route first: plain Newton
// from the cold start (SolveAtFrequency without its fallback paths), then from the other seeds'
// starts, then (with alpha_start) the α homotopy from 0 as far as it goes, then SolveAtFrequency
// with its fallbacks (α homotopy, frequency continuations), then a ramp up to f. Near a resonance
// of the FE cascade the fallbacks cost minutes per seed (1103 Hz: 98 % of a bound), where Newton
// from an earlier seed's solution takes a few steps. A known solution comes before all of them:
// near a resonance several periodic solutions coexist at one α, and the cold start would leave the
// one that was found (e.g. by a time integration).
bool StartSolution(const HarmonicBalance& sys, double freq_hz, const Eigen::VectorXd& alpha,
                   const std::vector<Eigen::VectorXd>& other_starts, Eigen::VectorXd* x,
                   const Eigen::VectorXd& known, Eigen::VectorXd* alpha_start) {
  if (alpha_start != nullptr) *alpha_start = alpha;
  FrfOptions frf;
  frf.use_fallbacks = false;
  if (known.size() == sys.num_unknowns()) {
    *x = known;
    if (SolveNewton(HbmAtFrequency(sys, RadPerS(freq_hz), alpha), frf.newton, x)
            .IsSolutionUsable()) {
      return true;
    }
  }
  FrfPoint p = SolveAtFrequency(sys, alpha, freq_hz, Eigen::VectorXd(), frf);
  if (p.status == SolverStatus::kConverged) {
    *x = p.x;
    return true;
  }
  const HbmAtFrequency at(sys, RadPerS(freq_hz), alpha);
  for (auto it = other_starts.rbegin(); it != other_starts.rend(); ++it) {
    *x = *it;
    if (SolveNewton(at, frf.newton, x).IsSolutionUsable()) return true;
  }
  frf.use_fallbacks = true;
  frf.fallback_max_points = kSeedFallbackPoints;
  if (alpha_start != nullptr) {
    // The α homotopy from 0 as far as it goes (KnownSolution::start_short_of_alpha): the run
    // needs a solution near α, and the continuations in frequency below cost minutes next to a
    // resonance (FE cascade, the ladder's start at 1098.98 Hz, H = 3: 4 of them, 240 s).
    double lambda = 0.0;
    int evaluations = 0;
    FrfOptions path = frf;
    path.fallback_max_points = kAlphaPathPoints;
    if (ContinueTowardsAlpha(sys, alpha, RadPerS(freq_hz), path, &lambda, x, &evaluations)) {
      *alpha_start = lambda * alpha;
      return true;
    }
  }
  p = SolveAtFrequency(sys, alpha, freq_hz, Eigen::VectorXd(), frf);
  if (p.status == SolverStatus::kConverged) {
    *x = p.x;
    return true;
  }
  // The ramp: ten frequencies up to f warm-started one from the other, then f from the last
  // converged one by Newton and the short continuation in frequency. f's own fallbacks are not run
  // again: the same α homotopy and continuations as just above, the same failure (FE cascade at
  // 1100 Hz: 45-110 s per seed, half the bound's time).
  std::vector<double> ramp;
  for (int k = 10; k >= 1; --k) ramp.push_back(freq_hz * (1.0 - 0.005 * k));
  const std::vector<FrfPoint> pts = SolveAtFrequencies(sys, alpha, ramp, frf);
  const auto last = std::find_if(pts.rbegin(), pts.rend(), [](const FrfPoint& q) {
    return q.status == SolverStatus::kConverged;
  });
  if (last == pts.rend()) return false;  // f from nothing: the cold routes above, failed
  frf.use_fallbacks = false;
  const FrfPoint end = SolveNextFrequency(sys, alpha, last->freq_hz, last->x, freq_hz, frf);
  if (end.status != SolverStatus::kConverged) return false;
  *x = end.x;
  return true;
}

}  // namespace fricrom::bounds_detail
