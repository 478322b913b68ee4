// Certification of response bounds at one frequency (fricrom verify): the bounds against routes
// that do not share the optimiser — fixed-α solves at structured and uniform α, and time
// integrations from several static states, each state refined by Newton into a harmonic-balance
// solution. A certificate needs evidence: at least one check, no sample that failed to solve,
// nothing outside the bounds, every time integration at a steady state, and a bound run that no
// check beat.
//
// The stages, each usable on its own so that a caller can hand the units of work to threads,
// MPI ranks or a journal:
//   PlanCertification   every α drawn before anything is solved (unit k is the same computation
//                       anywhere);
//   the units           ComputeLevelBounds, SolveSampleAmplitude per sample, RunTimeEvidence per
//                       time integration;
//   JudgeCertification  the bound optimisation restarted from any solution beyond the bounds
//                       (ImproveBounds), then every check judged against the result.
// Certify runs them all in order on one thread.
#pragma once

#include <Eigen/Dense>
#include <limits>
#include <string>
#include <vector>

#include "fricrom/alpha_levels.h"
#include "fricrom/bound_search.h"
#include "fricrom/bounds.h"
#include "fricrom/harmonic_balance.h"
#include "fricrom/model.h"
#include "fricrom/time_integration.h"

namespace fricrom {

struct CertificationEvidence {
  int samples = 0;             // α samples attempted
  int samples_failed = 0;      // ... whose harmonic-balance solve did not converge
  int samples_outside = 0;     // ... converged outside [y_min, y_max]
  int time_runs = 0;           // time integrations attempted
  int time_runs_unsteady = 0;  // ... that reached no steady state
  int time_runs_outside = 0;   // ... whose steady state lies outside the bounds
  // Time integrations whose final state, refined by Newton into a harmonic-balance solution at
  // its equivalent α, lies beyond the bounds: proof that a bound is a local optimum only.
  int time_states_beyond = 0;
  // Bounds (0-2) of the bound run that a sample or a time state went beyond: the run is reported
  // as beaten, never certified, even where the improved bounds then hold everything.
  int bounds_beaten = 0;
};

// Why the evidence does not certify the bounds; empty: certified.
std::vector<std::string> CertificationGaps(const CertificationEvidence& e);

struct CertifyOptions {
  // Uniform α samples after the structured ones (StructuredAlphaPatterns of the levels); with
  // fewer than 20 α the box's corners come first.
  int samples = 200;
  // Time integrations: from α = 0, the two alternating corners, then random α.
  int time_runs = 4;
  TimeIntegrationOptions time;  // freq_hz is set by the certification
  bool IsValid(std::string* error) const;
};

struct CertificationPlan {
  std::vector<Eigen::VectorXd> samples;    // structured α first, then uniform
  int structured = 0;                      // how many of `samples` are structured
  std::vector<Eigen::VectorXd> time_runs;  // each run's initial α
};
// Deterministic (fixed seeds): the same plan on any machine, thread or rank.
CertificationPlan PlanCertification(int num_alpha, const std::vector<AlphaLevel>& levels,
                                    const CertifyOptions& options);

// The amplitude of a fixed-α solve at the sample (SolveAtFrequency's routes); NaN where it fails.
double SolveSampleAmplitude(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                            double freq_hz);

// The harmonic-balance solution a time integration's final state refines into, and, where the
// run had not settled, the run from that solution's own state (IntegrateFromPeriodicState).
struct RefinedState {
  bool converged = false;
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;
  Eigen::VectorXd x;  // the solution (empty unless converged)
  bool continued = false;
  std::string continued_status;
  double continued_amplitude = std::numeric_limits<double>::quiet_NaN();
  int continued_periods = 0;
  double continued_relative_change = std::numeric_limits<double>::quiet_NaN();
  bool solution_holds = false;     // steady, at its own amplitude within the truncation margin
  bool run_settled_on_it = false;  // ... and the run within that margin of it
};

struct TimeRunEvidence {
  Eigen::VectorXd initial_alpha;
  TimeIntegrationResult::Status status = TimeIntegrationResult::Status::kNotSettled;
  std::string message, scheme;
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  int periods = 0, modes_integrated = 0;
  double relative_change = std::numeric_limits<double>::quiet_NaN();
  double free_vibration = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd equivalent_alpha;  // T/μN per contact at the start of the last period
  std::vector<ContactRegime> regimes;
  double wall_s = 0.0;
  bool refinable = false;  // a refinement was attempted (α per contact, a period integrated)
  RefinedState refined;
  // Set by JudgeCertification.
  bool steady = false;  // settled by itself, or on a solution that holds
  bool inside = false;  // time-domain amplitude within the bounds (truncation margin)
  bool beyond = false;  // refined solution beyond the bounds
};

// One time integration from the static state of `initial_alpha`, its final state refined into a
// harmonic-balance solution of `system` (a balance of `model`), continued from that solution
// where the run had not settled.
TimeRunEvidence RunTimeEvidence(const Model& model, const HarmonicBalance& system,
                                const Eigen::VectorXd& initial_alpha, double freq_hz,
                                const TimeIntegrationOptions& options);

struct SampleTally {
  int samples = 0, failed = 0, inside = 0, outside = 0;
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

struct Certificate {
  double freq_hz = 0.0;
  BoundsResult bounds;  // after the restarts from solutions beyond the bound run's
  double y_min_optimised = std::numeric_limits<double>::quiet_NaN();  // the bound run's own
  double y_max_optimised = std::numeric_limits<double>::quiet_NaN();
  int restarts = 0;                    // solutions beyond the bound run's bounds
  int bounds_moved = 0;                // bounds (0-2) the restarts moved: the run was beaten
  double y_min_relative_excess = 0.0;  // how far (relative) each was beaten
  double y_max_relative_excess = 0.0;
  SampleTally sampling, structured, uniform;
  std::vector<TimeRunEvidence> time_runs;
  int time_outside = 0, time_unsteady = 0, time_beyond = 0;
  bool certified = false;
  std::vector<std::string> gaps;  // why not certified
  std::string BriefReport() const;
};

// Judges the evidence: restarts the bound optimisation from every sample and refined time state
// beyond `bounds` (the samples solved again by the same deterministic solve), then tallies every
// check against the result. sample_y: one amplitude per plan sample, NaN where it failed.
Certificate JudgeCertification(const HarmonicBalance& system, double freq_hz,
                               const BoundsOptions& options, const CertificationPlan& plan,
                               BoundsResult bounds, const std::vector<double>& sample_y,
                               std::vector<TimeRunEvidence> time_runs);

// Everything in order on the calling thread: ComputeLevelBounds, the samples, the time runs and
// the judgement. Throws std::invalid_argument on invalid options or a non-positive frequency.
Certificate Certify(const Model& model, const HarmonicBalance& system, double freq_hz,
                    const BoundsOptions& options, const LevelSearchOptions& levels,
                    const CertifyOptions& certify);

}  // namespace fricrom
