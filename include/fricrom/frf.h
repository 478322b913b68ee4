// Frequency responses of a harmonic-balance problem at fixed α: solves at given frequencies
// (warm-started) or traces the branch by pseudo-arclength continuation over a frequency range.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fricrom/harmonic_balance.h"
#include "fricrom/solve.h"

namespace fricrom {

struct FrfOptions {
  NewtonOptions newton;
  double initial_step = 0.02;  // arclength steps, in units of the scaled (x, f) space
  double min_step = 1e-7;
  double max_step = 0.05;
  int max_points = 5000;
  // SolveAtFrequency: when plain Newton from the starts fails, try the α homotopy and the
  // frequency continuations (robust, but costly where they fail too).
  bool use_fallbacks = true;
  // Points each fallback path may take (the α homotopy, each frequency continuation): a path
  // stalled at a kink or crossing resonances is given up early instead of running for minutes.
  // A frequency continuation that runs out of points still ends in Newton at f from its last
  // point (next to a resonance it stops a few hertz short, where Newton converges).
  int fallback_max_points = 2000;
  // Frequency continuations SolveAtFrequency tries, nearest first (0.95 f, 1.05 f, 0.9 f, 1.1 f,
  // 0.8 f, 1.25 f, 0.5 f): fewer for callers that solve many points and can lose a few.
  int frequency_fallbacks = 7;
  // TraceFrf: a trace stalls where its arclength step falls below min_step, or where it crawls —
  // stall_points consecutive steps shorter than crawl_step × max_step (scaled arclength, x
  // against the largest solution so far): the kinks of many contacts switching state, each a
  // corner the step control must shrink for. (A fold is no crawl: its steps keep their length.)
  // It then jumps: Newton at a frequency a little ahead (0.25 % of the range, doubled up to 8 %)
  // from the furthest point, and traces on from there; at most max_jumps times.
  // TraceFrf measures its arclength against the solution's current size
  // (ContinuationOptions::adapt_x_scale).
  bool adapt_x_scale = true;
  int stall_points = 100;
  double crawl_step = 0.05;
  int max_jumps = 20;  // 0: the plain continuation (no crawl guard, no jump)
  // A branch that comes back by more than this fraction of the range below the furthest
  // frequency it reached is looping over traced ground: TraceFrf jumps ahead as from a stall.
  double turn_back_limit = 0.2;
  // TraceFrf's corrector and predictor (ContinuationOptions): the secant predictor and a short
  // corrector budget: where contacts switch state a corrector that has not converged in a few
  // iterations rarely does, and a shorter step is cheaper than its damped iterations.
  bool secant_predictor = true;
  int max_corrector_iterations = 10;
  int max_corrector_backtracks = 5;
  bool IsValid(std::string* error) const;
};

struct FrfPoint {
  double freq_hz = 0.0;
  Eigen::VectorXd x;  // harmonic coefficients (see hbm.h)
  SolverStatus status = SolverStatus::kMaxIterations;
  std::string message;
  int iterations = 0;
  // First-harmonic amplitude of the response DOF [m]; NaN unless the point converged.
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  std::vector<ContactRegime> regimes;
  bool turning_point_before = false;
  // TraceFrf: this point starts a new trace after a jump over a stall; the branch between it and
  // the point before is not traced (a fold or a switch of branch may hide there).
  bool jump_before = false;
};

// Progress: (points done, points total or −1 when unknown).
using FrfProgress = std::function<void(int, int)>;

// One step of SolveAtFrequencies: the point at f_hz warm-started from the converged point
// (f_from_hz, x_from), with options' fallbacks if Newton fails, and last a continuation in
// frequency from that point.
FrfPoint SolveNextFrequency(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                            double f_from_hz, const Eigen::VectorXd& x_from, double f_hz,
                            const FrfOptions& options);

// Solves R(x; 2πf, α) = 0 at each frequency in order, each start warm from the last converged
// point, falling back to the full-stick linear solution and then to a continuation from the last
// converged point. A point that still fails keeps its status; its x is the last iterate.
std::vector<FrfPoint> SolveAtFrequencies(const HarmonicBalance& system,
                                         const Eigen::VectorXd& alpha,
                                         const std::vector<double>& freqs_hz,
                                         const FrfOptions& options,
                                         const FrfProgress& progress = {});

// Solves R(x; ω, α) = 0 at one frequency with the same globalisation as sweeps and bounds.
// Starts: `x_start` (if non-empty), the full-stick linear solution; then a homotopy in α (the
// solution at α = 0 continued along α(λ) = λ·α_target, λ: 0 → 1: the residual has kinks in full
// stick and at |α| = 1, where plain Newton from a linear guess fails on a sizeable share of α);
// then continuation in frequency from nearby frequencies (0.95 f, 1.05 f, ... 0.5 f) (a cold start
// at resonance fails where the branch followed from off-resonance succeeds). The point reports its
// status; a failed point keeps the last Newton iterate in x and has a NaN amplitude.
FrfPoint SolveAtFrequency(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                          double freq_hz, const Eigen::VectorXd& x_start,
                          const FrfOptions& options);

struct FrfTrace {
  std::vector<FrfPoint> points;
  // Over all segments; reached_end only when the last one reached f_end.
  ContinuationSummary summary;
  // The stalls jumped over: (frequency of the last traced point, frequency landed on) [Hz].
  std::vector<std::pair<double, double>> jumps;
};

// Traces the branch from f_start to f_end by continuation (passing turning points); where it
// stalls, jumps ahead and traces on (FrfOptions::stall_points), each jump recorded.
FrfTrace TraceFrf(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double f_start_hz,
                  double f_end_hz, const FrfOptions& options, const FrfProgress& progress = {});

// Solves R(x; ω, α) = 0 from x0, a solution of a nearby problem (the lower-harmonic solution
// embedded at H, the solution at a neighbouring frequency), where Newton from x0 fails: the
// residual homotopy R(x) − (1 − λ) R(x0) = 0, which x0 solves at λ = 0, is continued to λ = 1
// (at most options.fallback_max_points points) and the end polished by Newton. True with *x the
// solution; *evaluations counts the residual evaluations.
bool SolveFromNearbyPoint(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                          const Eigen::VectorXd& x0, const FrfOptions& options, Eigen::VectorXd* x,
                          int* evaluations);

// The α homotopy α(λ) = λ·alpha at ω followed from α = 0 (Newton from the stick solution there)
// as far as it goes in options.fallback_max_points points. Where it stops short of λ = 1 (a kink
// of the contact laws it cannot pass, or the points run out) its last point still solves the
// balance at λ·alpha: a start for an optimisation over α, which needs a solution near its seed,
// not at it. True with *lambda the λ reached (0 < λ ≤ 1) and *x the solution at λ·alpha,
// polished by Newton; false when no point beyond α = 0 converged.
bool ContinueTowardsAlpha(const HarmonicBalance& system, const Eigen::VectorXd& alpha, double omega,
                          const FrfOptions& options, double* lambda, Eigen::VectorXd* x,
                          int* evaluations);

// Adapters that expose a harmonic-balance problem at fixed α to the generic solvers (λ = ω in
// rad/s).
class HbmAtFrequency : public SquareSystem {
 public:
  HbmAtFrequency(const HarmonicBalance& system, double omega, const Eigen::VectorXd& alpha);
  int size() const override;
  void Evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* r, Eigen::MatrixXd* j) const override;
  double ResidualScale() const override;
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x) const override;

 private:
  const HarmonicBalance& system_;
  double omega_;
  Eigen::VectorXd alpha_;
};

// R(x; ω, α) − (1 − λ) R(x0; ω, α): the residual homotopy of SolveFromNearbyPoint.
class ResidualHomotopy : public ParametricSystem {
 public:
  ResidualHomotopy(const HarmonicBalance& system, double omega, const Eigen::VectorXd& alpha,
                   const Eigen::VectorXd& x0);
  int size() const override;
  void Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* r, Eigen::MatrixXd* j,
                Eigen::VectorXd* dr_dlambda) const override;
  double ResidualScale() const override;
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double lambda,
                                              Eigen::VectorXd* dr_dlambda) const override;

 private:
  const HarmonicBalance& system_;
  double omega_;
  Eigen::VectorXd alpha_, r0_;
};

// R(x; ω, α0 + λ(α1 − α0)) at fixed ω: the path of the α homotopy.
class HbmAlphaPath : public ParametricSystem {
 public:
  HbmAlphaPath(const HarmonicBalance& system, double omega, const Eigen::VectorXd& alpha0,
               const Eigen::VectorXd& alpha1);
  int size() const override;
  void Evaluate(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd* r, Eigen::MatrixXd* j,
                Eigen::VectorXd* dr_dlambda) const override;
  double ResidualScale() const override;
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double lambda,
                                              Eigen::VectorXd* dr_dlambda) const override;

 private:
  Eigen::VectorXd AlphaAt(double lambda) const;
  const HarmonicBalance& system_;
  double omega_;
  Eigen::VectorXd alpha0_, alpha1_;
};

class HbmFrequencyFamily : public ParametricSystem {
 public:
  HbmFrequencyFamily(const HarmonicBalance& system, const Eigen::VectorXd& alpha);
  int size() const override;
  void Evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd* r, Eigen::MatrixXd* j,
                Eigen::VectorXd* dr_domega) const override;
  double ResidualScale() const override;
  std::unique_ptr<JacobianOperator> Linearize(const Eigen::VectorXd& x, double omega,
                                              Eigen::VectorXd* dr_domega) const override;

 private:
  const HarmonicBalance& system_;
  Eigen::VectorXd alpha_;
};

}  // namespace fricrom
