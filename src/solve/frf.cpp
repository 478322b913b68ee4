#include "fricrom/frf.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "fricrom/units.h"

namespace fricrom {
namespace {

// The balance's own classification: the condensed one's from its relative displacements, without
// recovering every DOF (7 % of an FE trace's time went to that recovery).
std::vector<ContactRegime> Regimes(const HarmonicBalance& system, const Eigen::VectorXd& x,
                                   double omega, const Eigen::VectorXd& alpha) {
  return system.ContactRegimes(x, omega, alpha);
}

// The balance's matrix-free ∂R/∂x at (x, ω, α) with the evaluation `req` asks for there (∂R/∂ω,
// ∂R/∂α): a path's Linearize. nullptr, and nothing evaluated, where the balance has no operator.
std::unique_ptr<JacobianOperator> LinearizeWith(const HarmonicBalance& system,
                                                const Eigen::VectorXd& x, double omega,
                                                const Eigen::VectorXd& alpha, const HbmRequest& req,
                                                HbmEvaluation* e) {
  std::unique_ptr<JacobianOperator> op = system.Linearize(x, omega, alpha);
  if (op) system.Evaluate(x, omega, alpha, req, e);
  return op;
}

ContinuationOptions MakeContinuationOptions(const HarmonicBalance& system,
                                            const FrfOptions& options, double f0, double f1,
                                            const Eigen::VectorXd& x0) {
  ContinuationOptions c;
  c.lambda_start = RadPerS(f0);
  c.lambda_end = RadPerS(f1);
  c.lambda_scale = std::abs(c.lambda_end - c.lambda_start);
  c.x_scale = std::max(x0.norm(), 1e-300);
  (void)system;
  c.initial_step = options.initial_step;
  c.min_step = options.min_step;
  c.max_step = options.max_step;
  c.max_points = options.max_points;
  c.corrector = options.newton;
  return c;
}
}  // namespace

bool FrfOptions::IsValid(std::string* error) const {
  if (!(min_step > 0.0 && initial_step >= min_step && max_step >= initial_step)) {
    *error = "FrfOptions: steps must satisfy 0 < min_step <= initial_step <= max_step";
    return false;
  }
  if (max_points < 1 || fallback_max_points < 1) {
    *error = "FrfOptions.max_points and fallback_max_points must be >= 1";
    return false;
  }
  if (stall_points < 1 || !(crawl_step >= 0.0) || max_jumps < 0 || !(turn_back_limit > 0.0)) {
    *error = "FrfOptions: stall_points >= 1, crawl_step >= 0, max_jumps >= 0, turn_back_limit > 0";
    return false;
  }
  if (max_corrector_iterations < 0 || max_corrector_backtracks < -1) {
    *error = "FrfOptions: max_corrector_iterations >= 0, max_corrector_backtracks >= -1";
    return false;
  }
  if (frequency_fallbacks < 0 || frequency_fallbacks > 7) {
    *error = "FrfOptions.frequency_fallbacks must lie in [0, 7]";
    return false;
  }
  return newton.IsValid(error);
}

HbmAtFrequency::HbmAtFrequency(const HarmonicBalance& system, double omega,
                               const Eigen::VectorXd& alpha)
    : system_(system), omega_(omega), alpha_(alpha) {}
int HbmAtFrequency::size() const { return system_.num_unknowns(); }
void HbmAtFrequency::Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r,
                              Eigen::MatrixXd* j) const {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = j != nullptr;
  system_.Evaluate(x, omega_, alpha_, req, &e);
  *r = std::move(e.residual);
  if (j) *j = std::move(e.jacobian);
}
double HbmAtFrequency::ResidualScale() const { return system_.ResidualScale(); }
std::unique_ptr<JacobianOperator> HbmAtFrequency::Linearize(const Eigen::VectorXd& x) const {
  return system_.Linearize(x, omega_, alpha_);
}

HbmFrequencyFamily::HbmFrequencyFamily(const HarmonicBalance& system, const Eigen::VectorXd& alpha)
    : system_(system), alpha_(alpha) {}
int HbmFrequencyFamily::size() const { return system_.num_unknowns(); }
void HbmFrequencyFamily::Evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd* r,
                                  Eigen::MatrixXd* j, Eigen::VectorXd* dr_domega) const {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = j != nullptr;
  req.omega_derivative = dr_domega != nullptr;
  system_.Evaluate(x, omega, alpha_, req, &e);
  *r = std::move(e.residual);
  if (j) *j = std::move(e.jacobian);
  if (dr_domega) *dr_domega = std::move(e.omega_derivative);
}
double HbmFrequencyFamily::ResidualScale() const { return system_.ResidualScale(); }
std::unique_ptr<JacobianOperator> HbmFrequencyFamily::Linearize(const Eigen::VectorXd& x,
                                                                double omega,
                                                                Eigen::VectorXd* dr_domega) const {
  HbmRequest req;
  req.omega_derivative = true;
  HbmEvaluation e;
  std::unique_ptr<JacobianOperator> op = LinearizeWith(system_, x, omega, alpha_, req, &e);
  if (op) *dr_domega = std::move(e.omega_derivative);
  return op;
}

HbmAlphaPath::HbmAlphaPath(const HarmonicBalance& system, double omega,
                           const Eigen::VectorXd& alpha0, const Eigen::VectorXd& alpha1)
    : system_(system), omega_(omega), alpha0_(alpha0), alpha1_(alpha1) {}
int HbmAlphaPath::size() const { return system_.num_unknowns(); }
void HbmAlphaPath::Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* r,
                            Eigen::MatrixXd* j, Eigen::VectorXd* dr_dlambda) const {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = j != nullptr;
  req.alpha_jacobian = dr_dlambda != nullptr;
  system_.Evaluate(x, omega_, AlphaAt(lambda), req, &e);
  *r = std::move(e.residual);
  if (j) *j = std::move(e.jacobian);
  if (dr_dlambda) *dr_dlambda = e.alpha_jacobian * (alpha1_ - alpha0_);
}
std::unique_ptr<JacobianOperator> HbmAlphaPath::Linearize(const Eigen::VectorXd& x, double lambda,
                                                          Eigen::VectorXd* dr_dlambda) const {
  HbmRequest req;
  req.alpha_jacobian = true;
  HbmEvaluation e;
  std::unique_ptr<JacobianOperator> op =
      LinearizeWith(system_, x, omega_, AlphaAt(lambda), req, &e);
  if (op) *dr_dlambda = e.alpha_jacobian * (alpha1_ - alpha0_);
  return op;
}
double HbmAlphaPath::ResidualScale() const { return system_.ResidualScale(); }
// Continuation may overshoot λ ∈ [0, 1] slightly; α is clamped to its admissible box.
Eigen::VectorXd HbmAlphaPath::AlphaAt(double lambda) const {
  return (alpha0_ + lambda * (alpha1_ - alpha0_)).cwiseMax(-1.0).cwiseMin(1.0);
}

namespace {

// Follows `path` from x0 to its λ end and polishes the end by Newton on `at`: true with *x the
// solution; *evaluations counts both. The tail of every homotopy and continuation fallback here.
// With `polish_short_end` a path that ran out of points is polished from its last point too.
bool ContinueAndPolish(const ParametricSystem& path, const ContinuationOptions& c,
                       const Eigen::VectorXd& x0, const SquareSystem& at,
                       const NewtonOptions& newton, Eigen::VectorXd* x, int* evaluations,
                       bool polish_short_end = false) {
  Eigen::VectorXd x_end;
  const ContinuationSummary cs = Continue(path, c, x0, [&](const ContinuationPoint& cp) {
    x_end = cp.x;
    return true;
  });
  *evaluations += cs.evaluations;
  const bool short_end = polish_short_end && cs.status == ContinuationStatus::kMaxPoints;
  if (cs.status != ContinuationStatus::kReachedEnd && !short_end) return false;
  *x = x_end;
  const NewtonSummary ns = SolveNewton(at, newton, x);
  *evaluations += ns.iterations;
  return ns.IsSolutionUsable();
}

}  // namespace

ResidualHomotopy::ResidualHomotopy(const HarmonicBalance& system, double omega,
                                   const Eigen::VectorXd& alpha, const Eigen::VectorXd& x0)
    : system_(system), omega_(omega), alpha_(alpha) {
  HbmEvaluation e;
  system_.Evaluate(x0, omega_, alpha_, HbmRequest{false, false, false}, &e);
  r0_ = std::move(e.residual);
}
int ResidualHomotopy::size() const { return system_.num_unknowns(); }
void ResidualHomotopy::Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* r,
                                Eigen::MatrixXd* j, Eigen::VectorXd* dr_dlambda) const {
  HbmEvaluation e;
  HbmRequest req;
  req.jacobian = j != nullptr;
  system_.Evaluate(x, omega_, alpha_, req, &e);
  *r = std::move(e.residual) - (1.0 - lambda) * r0_;
  if (j) *j = std::move(e.jacobian);
  if (dr_dlambda) *dr_dlambda = r0_;
}
double ResidualHomotopy::ResidualScale() const { return system_.ResidualScale(); }
std::unique_ptr<JacobianOperator> ResidualHomotopy::Linearize(const Eigen::VectorXd& x,
                                                              double /*lambda*/,
                                                              Eigen::VectorXd* dr_dlambda) const {
  std::unique_ptr<JacobianOperator> op = system_.Linearize(x, omega_, alpha_);
  if (op) *dr_dlambda = r0_;
  return op;
}

bool SolveFromNearbyPoint(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                          const Eigen::VectorXd& x0, const FrfOptions& options, Eigen::VectorXd* x,
                          int* evaluations) {
  if (!x0.allFinite()) return false;
  const ResidualHomotopy path(system, omega, alpha, x0);
  ContinuationOptions c;
  c.x_scale = std::max(x0.norm(), 1e-300);
  c.initial_step = 0.1;
  c.max_step = 0.5;
  c.min_step = 1e-8;
  c.max_points = options.fallback_max_points;
  c.corrector = options.newton;
  return ContinueAndPolish(path, c, x0, HbmAtFrequency(system, omega, alpha), options.newton, x,
                           evaluations);
}

namespace {

// Follows the branch at fixed α from (f_from, x_from) to f_to by continuation in frequency and
// polishes the end by Newton; true with *x the solution at f_to.
bool ContinueInFrequency(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double f_from,
                         const Eigen::VectorXd& x_from, double f_to, const FrfOptions& options,
                         Eigen::VectorXd* x, int* iterations) {
  HbmFrequencyFamily family(system, alpha);
  ContinuationOptions copt = MakeContinuationOptions(system, options, f_from, f_to, x_from);
  copt.max_points = std::min(copt.max_points, options.fallback_max_points);
  // A path that crossed a resonance may run out of points a fraction of a hertz short of f_to
  // (FE cascade at 1100 Hz: 40 points from 1.05 f end 0.5 Hz short), where Newton at f_to from
  // its last point is one solve against the next path's 40 points.
  return ContinueAndPolish(family, copt, x_from, HbmAtFrequency(system, RadPerS(f_to), alpha),
                           options.newton, x, iterations, true);
}

// The α homotopy's options from x0 at α = 0 (ContinueInAlpha, ContinueTowardsAlpha).
ContinuationOptions AlphaPathOptions(const Eigen::VectorXd& x0, const FrfOptions& options) {
  ContinuationOptions c;
  c.lambda_start = 0.0;
  c.lambda_end = 1.0;
  c.x_scale = std::max(x0.norm(), 1e-300);
  c.initial_step = 0.05;
  c.max_step = 0.2;
  c.min_step = 1e-8;
  c.max_points = options.fallback_max_points;
  c.corrector = options.newton;
  return c;
}

// Homotopy in α: the solution at α = 0 (x0) continued along α(λ) = λ·α_target, λ: 0 → 1.
bool ContinueInAlpha(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                     const Eigen::VectorXd& x0, const FrfOptions& options, Eigen::VectorXd* x,
                     int* iterations) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(alpha.size());
  HbmAlphaPath path(system, omega, zero, alpha);
  return ContinueAndPolish(path, AlphaPathOptions(x0, options), x0,
                           HbmAtFrequency(system, omega, alpha), options.newton, x, iterations);
}

// Newton at (ω, α) from `starts` in order; true with *x the solution.
bool NewtonFromStarts(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                      const std::vector<Eigen::VectorXd>& starts, const FrfOptions& options,
                      Eigen::VectorXd* x, int* iterations, NewtonSummary* last) {
  const HbmAtFrequency at(system, omega, alpha);
  for (const Eigen::VectorXd& s : starts) {
    *x = s;
    *last = SolveNewton(at, options.newton, x);
    *iterations += last->iterations;
    if (last->IsSolutionUsable()) return true;
  }
  return false;
}

}  // namespace

bool ContinueTowardsAlpha(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                          const FrfOptions& options, double* lambda, Eigen::VectorXd* x,
                          int* evaluations) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(alpha.size());
  Eigen::VectorXd x0 = system.StickLinearSolution(omega);
  const NewtonSummary s0 = SolveNewton(HbmAtFrequency(system, omega, zero), options.newton, &x0);
  *evaluations += s0.iterations;
  if (!s0.IsSolutionUsable()) return false;
  const HbmAlphaPath path(system, omega, zero, alpha);
  double reached = 0.0;
  Eigen::VectorXd x_end;
  const ContinuationSummary cs =
      Continue(path, AlphaPathOptions(x0, options), x0, [&](const ContinuationPoint& cp) {
        if (cp.lambda > reached && cp.lambda <= 1.0) {
          reached = cp.lambda;
          x_end = cp.x;
        }
        return true;
      });
  *evaluations += cs.evaluations;
  if (cs.status == ContinuationStatus::kReachedEnd) reached = 1.0;
  if (!(reached > 0.0) || x_end.size() == 0) return false;
  *x = x_end;
  const NewtonSummary ns =
      SolveNewton(HbmAtFrequency(system, omega, reached * alpha), options.newton, x);
  *evaluations += ns.iterations;
  if (!ns.IsSolutionUsable()) return false;
  *lambda = reached;
  return true;
}

FrfPoint SolveAtFrequency(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                          double freq_hz, const Eigen::VectorXd& x_start,
                          const FrfOptions& options) {
  if (!(freq_hz > 0.0) || !std::isfinite(freq_hz)) {
    throw std::invalid_argument("SolveAtFrequency: frequency must be positive, got " +
                                std::to_string(freq_hz));
  }
  const double omega = RadPerS(freq_hz);
  FrfPoint p;
  p.freq_hz = freq_hz;
  std::vector<Eigen::VectorXd> starts;
  if (x_start.size() > 0) {
    starts.push_back(x_start);
  } else if (const HarmonicBalance* first = system.FirstHarmonicBalance()) {
    // Harmonic continuation (harmonic_balance.h): the H = 1 solution as the cold start.
    const FrfPoint p1 = SolveAtFrequency(*first, alpha, freq_hz, Eigen::VectorXd(), options);
    p.iterations += p1.iterations;
    if (p1.status == SolverStatus::kConverged)
      starts.push_back(system.EmbedLowerHarmonics(p1.x, 1));
  }
  starts.push_back(system.StickLinearSolution(omega));
  NewtonSummary ns;
  bool ok = NewtonFromStarts(system, alpha, omega, starts, options, &p.x, &p.iterations, &ns);
  const Eigen::VectorXd x_fail = p.x;  // the last plain-Newton iterate, reported on failure
  Eigen::VectorXd x;
  // 1) Homotopy in α from α = 0, whose solution plain Newton usually finds.
  const bool has_alpha = alpha.size() > 0 && alpha.cwiseAbs().maxCoeff() > 0.0;
  Eigen::VectorXd x_alpha0;
  if (!ok && has_alpha && options.use_fallbacks) {
    NewtonSummary s0;
    if (NewtonFromStarts(system, Eigen::VectorXd::Zero(alpha.size()), omega, {starts.back()},
                         options, &x_alpha0, &p.iterations, &s0)) {
      ok = ContinueInAlpha(system, alpha, omega, x_alpha0, options, &x, &p.iterations);
    }
  }
  // 2) Continuation in frequency from a nearby frequency where Newton from the stick solution
  //    converges: the route that makes the sweep succeed where a cold start at resonance fails.
  //    Nearest first, so that the branch followed crosses as few resonances as possible.
  int tried = 0;
  for (double ratio : {0.95, 1.05, 0.9, 1.1, 0.8, 1.25, 0.5}) {
    if (ok || !options.use_fallbacks || tried++ >= options.frequency_fallbacks) break;
    const double f0 = freq_hz * ratio;
    Eigen::VectorXd x0;
    NewtonSummary s0;
    if (!NewtonFromStarts(system, alpha, RadPerS(f0), {system.StickLinearSolution(RadPerS(f0))},
                          options, &x0, &p.iterations, &s0)) {
      continue;
    }
    ok = ContinueInFrequency(system, alpha, f0, x0, freq_hz, options, &x, &p.iterations);
  }
  if (ok && !ns.IsSolutionUsable()) {
    p.x = x;
    ns = SolveNewton(HbmAtFrequency(system, omega, alpha), options.newton, &p.x);
    p.iterations += ns.iterations;
  }
  if (!ns.IsSolutionUsable()) p.x = x_fail;
  p.status = ns.status;
  p.message = ns.message;
  // A point that did not converge has no amplitude: NaN, never a number from a failed iterate.
  p.amplitude = ns.IsSolutionUsable() ? system.Amplitude(p.x) : std::nan("");
  if (ns.IsSolutionUsable()) p.regimes = Regimes(system, p.x, omega, alpha);
  return p;
}

FrfPoint SolveNextFrequency(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                            double f_from_hz, const Eigen::VectorXd& x_from, double f_hz,
                            const FrfOptions& options) {
  FrfPoint p = SolveAtFrequency(system, alpha, f_hz, x_from, options);
  if (p.status == SolverStatus::kConverged) return p;
  // Last resort: continuation in frequency from the converged point.
  HbmFrequencyFamily family(system, alpha);
  const ContinuationOptions copt =
      MakeContinuationOptions(system, options, f_from_hz, f_hz, x_from);
  Eigen::VectorXd x_end;
  const ContinuationSummary cs = Continue(family, copt, x_from, [&](const ContinuationPoint& cp) {
    x_end = cp.x;
    return true;
  });
  if (cs.status == ContinuationStatus::kReachedEnd) {
    FrfPoint q = SolveAtFrequency(system, alpha, f_hz, x_end, options);
    if (q.status == SolverStatus::kConverged) return q;
  }
  return p;
}

std::vector<FrfPoint> SolveAtFrequencies(const HarmonicBalance& system,
                                         const Eigen::VectorXd& alpha,
                                         const std::vector<double>& freqs_hz,
                                         const FrfOptions& options, const FrfProgress& progress) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  std::vector<FrfPoint> points;
  bool have_last = false;
  Eigen::VectorXd last_x;
  double last_f = 0.0;
  int done = 0;
  for (double f : freqs_hz) {
    if (!(f > 0.0) || !std::isfinite(f)) {
      throw std::invalid_argument("SolveAtFrequencies: frequencies must be positive, got " +
                                  std::to_string(f));
    }
    FrfPoint p = have_last ? SolveNextFrequency(system, alpha, last_f, last_x, f, options)
                           : SolveAtFrequency(system, alpha, f, Eigen::VectorXd(), options);
    if (p.status == SolverStatus::kConverged) {
      have_last = true;
      last_x = p.x;
      last_f = f;
    }
    points.push_back(std::move(p));
    if (progress) progress(++done, static_cast<int>(freqs_hz.size()));
  }
  return points;
}

namespace {

// One continuation segment of TraceFrf from x0 at f0 towards f1, its points appended; stopped
// early where it crawls (FrfOptions::stall_points).
ContinuationSummary TraceSegment(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                                 double f0, double f1, const Eigen::VectorXd& x0,
                                 const FrfOptions& options, int max_points, bool crawl_guard,
                                 const FrfProgress& progress, FrfTrace* trace, std::string* stall) {
  HbmFrequencyFamily family(system, alpha);
  ContinuationOptions copt = MakeContinuationOptions(system, options, f0, f1, x0);
  copt.max_points = max_points;
  copt.adapt_x_scale = options.adapt_x_scale;
  copt.secant_predictor = options.secant_predictor;
  copt.max_corrector_iterations = options.max_corrector_iterations;
  copt.max_corrector_backtracks = options.max_corrector_backtracks;
  const double dir = f1 > f0 ? 1.0 : -1.0, range = std::abs(f1 - f0);
  const double back = 1e-3 * range;  // how far out of the range a trace may turn back
  const double turn_back = options.turn_back_limit * range;
  double furthest = f0;
  double x_size = x0.norm();
  int short_steps = 0;
  stall->clear();
  const size_t first = trace->points.size();
  return Continue(family, copt, x0, [&](const ContinuationPoint& cp) {
    FrfPoint p;
    p.freq_hz = Hz(cp.lambda);
    p.x = cp.x;
    p.status = SolverStatus::kConverged;
    p.iterations = cp.corrector_iterations;
    p.amplitude = system.Amplitude(cp.x);
    p.regimes = Regimes(system, cp.x, cp.lambda, alpha);
    p.turning_point_before = cp.turning_point_before;
    p.jump_before = trace->points.size() == first && first > 0;
    trace->points.push_back(std::move(p));
    if (progress) progress(static_cast<int>(trace->points.size()), -1);
    if (!crawl_guard) return true;
    const auto at = [&cp] { return " at " + std::to_string(Hz(cp.lambda)) + " Hz"; };
    if (dir * (Hz(cp.lambda) - f0) < -back) {
      *stall = "the branch turned back out of the range" + at();  // nothing to trace there
      return false;
    }
    if (dir * (Hz(cp.lambda) - furthest) > 0.0) furthest = Hz(cp.lambda);
    if (dir * (furthest - Hz(cp.lambda)) > turn_back) {
      // A loop back over traced ground: the range ahead is what is left.
      *stall = "the branch turned back from " + std::to_string(furthest) + " Hz" + at();
      return false;
    }
    const FrfPoint& now = trace->points.back();
    if (trace->points.size() > first + 1) {
      const FrfPoint& before = trace->points[trace->points.size() - 2];
      x_size = std::max(x_size, now.x.norm());
      const double df = (now.freq_hz - before.freq_hz) / range;
      const double dx = (now.x - before.x).norm() / std::max(x_size, 1e-300);
      const bool is_short = std::sqrt(df * df + dx * dx) < options.crawl_step * options.max_step;
      short_steps = is_short ? short_steps + 1 : 0;
      if (short_steps >= options.stall_points) {
        *stall =
            "crawling: " + std::to_string(options.stall_points) + " short steps in a row" + at();
        return false;
      }
    }
    return true;
  });
}

void Accumulate(const ContinuationSummary& s, ContinuationSummary* total) {
  total->points += s.points;
  total->turning_points += s.turning_points;
  total->rejected_steps += s.rejected_steps;
  total->evaluations += s.evaluations;
  total->status = s.status;
  total->message = s.message;
}

}  // namespace

FrfTrace TraceFrf(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double f_start_hz,
                  double f_end_hz, const FrfOptions& options, const FrfProgress& progress) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  FrfTrace trace;
  trace.summary.points = 0;
  const double range = std::abs(f_end_hz - f_start_hz), dir = f_end_hz > f_start_hz ? 1.0 : -1.0;
  double f0 = f_start_hz;
  Eigen::VectorXd x0 = system.StickLinearSolution(RadPerS(f_start_hz));
  for (int segment = 0;; ++segment) {
    std::string stall;
    const int left = options.max_points - trace.summary.points;
    const ContinuationSummary s =
        TraceSegment(system, alpha, f0, f_end_hz, x0, options, std::max(left, 1),
                     options.max_jumps > 0, progress, &trace, &stall);
    Accumulate(s, &trace.summary);
    if (!stall.empty()) {
      trace.summary.status = ContinuationStatus::kStepTooSmall;
      trace.summary.message = stall;
    }
    const bool stalled = s.status == ContinuationStatus::kStepTooSmall || !stall.empty();
    if (!stalled || segment >= options.max_jumps || trace.points.empty() ||
        trace.summary.points >= options.max_points) {
      break;
    }
    // Jump: Newton a little ahead of the furthest point traced, from it.
    const FrfPoint* from = &trace.points.back();
    for (const FrfPoint& p : trace.points) {
      if (dir * (p.freq_hz - from->freq_hz) > 0.0) from = &p;
    }
    bool landed = false;
    bool at_end = false;
    // Newton alone first (0.25 % of the range, doubled up to 8 %); where a branch drops off a
    // fold none of those may converge, and the fallbacks' α homotopy and frequency continuations
    // are tried at 1 % and 4 % before the trace gives up.
    const auto try_jump = [&](double step, bool fallbacks) {
      // A jump that would pass the end lands on it, and the trace is complete.
      at_end = dir * (from->freq_hz + dir * step - f_end_hz) >= 0.0;
      const double f = at_end ? f_end_hz : from->freq_hz + dir * step;
      FrfOptions quick = options;
      quick.use_fallbacks = fallbacks;
      quick.frequency_fallbacks = std::min(options.frequency_fallbacks, 2);
      FrfPoint p = SolveAtFrequency(system, alpha, f, from->x, quick);
      if (p.status != SolverStatus::kConverged) return;
      trace.jumps.emplace_back(from->freq_hz, f);
      f0 = f;
      x0 = p.x;
      landed = true;
      if (at_end) {
        p.jump_before = true;
        trace.points.push_back(std::move(p));
        ++trace.summary.points;
        trace.summary.status = ContinuationStatus::kReachedEnd;
        trace.summary.message.clear();
      }
    };
    for (double step = 0.0025 * range; step <= 0.08 * range && !landed; step *= 2.0) {
      try_jump(step, false);
      if (at_end) break;
    }
    for (double step = 0.01 * range; step <= 0.04 * range && !landed && !at_end; step *= 4.0) {
      try_jump(step, true);
    }
    if (landed && at_end) break;
    if (!landed) {
      trace.summary.message += "; no jump past the stall converged";
      break;
    }
  }
  if (!trace.jumps.empty()) {
    std::ostringstream os;
    os << trace.summary.message << (trace.summary.message.empty() ? "" : "; ") << trace.jumps.size()
       << " jump(s) over stalls, the branch untraced between";
    for (const auto& [a, b] : trace.jumps) os << " " << a << "->" << b << " Hz";
    trace.summary.message = os.str();
  }
  return trace;
}

}  // namespace fricrom
