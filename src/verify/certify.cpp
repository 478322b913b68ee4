// Certify and its stages (certification.h).
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "fricrom/certification.h"
#include "fricrom/frf.h"
#include "fricrom/solve.h"
#include "fricrom/units.h"

namespace fricrom {
namespace {

// Relative tolerance of "inside" for fixed-α solutions (solver tolerances are ~1e-10).
constexpr double kInsideTolerance = 1e-6;
// Harmonic truncation (H) separates a time-domain amplitude from the HBM's by up to ~1e-2 next
// to the resonance: a time-domain amplitude is judged with this margin.
constexpr double kTimeDomainMargin = 0.02;

bool Outside(double y, double lo, double hi) {
  return y < lo * (1 - kInsideTolerance) || y > hi * (1 + kInsideTolerance);
}

SampleTally Tally(const std::vector<double>& y, size_t from, size_t to, double lo, double hi) {
  SampleTally t;
  t.samples = static_cast<int>(to - from);
  for (size_t i = from; i < to; ++i) {
    const double v = y[i];
    if (std::isnan(v)) {
      ++t.failed;
      continue;
    }
    t.min = std::isnan(t.min) ? v : std::min(t.min, v);
    t.max = std::isnan(t.max) ? v : std::max(t.max, v);
    ++(Outside(v, lo, hi) ? t.outside : t.inside);
  }
  return t;
}

// The run from the refined solution's own state: where the solution holds and the run lies
// within the truncation margin of it, the run has settled on it.
void ContinueFromSolution(const Model& model, const HarmonicBalance& system, double freq_hz,
                          const Eigen::VectorXd& alpha, TimeIntegrationOptions to,
                          double run_amplitude, RefinedState* s) {
  to.freq_hz = freq_hz;
  to.min_periods = 1;
  to.max_periods = 3 * to.window_periods;
  const TimeIntegrationResult c = IntegrateFromPeriodicState(
      model, PeriodicStartOf(model, system, s->x, RadPerS(freq_hz), alpha), to);
  const auto near = [&](double v) {
    return std::abs(v - s->amplitude) <= kTimeDomainMargin * s->amplitude;
  };
  s->continued = true;
  s->continued_status = ToString(c.status);
  s->continued_amplitude = c.amplitude;
  s->continued_periods = c.periods;
  s->continued_relative_change = c.relative_change;
  s->solution_holds = c.IsSteady() && near(c.amplitude);
  s->run_settled_on_it = s->solution_holds && near(run_amplitude);
}

}  // namespace

bool CertifyOptions::IsValid(std::string* error) const {
  if (samples < 0 || time_runs < 0) {
    *error = "CertifyOptions: samples and time_runs must be >= 0";
    return false;
  }
  return true;
}

CertificationPlan PlanCertification(int num_alpha, const std::vector<AlphaLevel>& levels,
                                    const CertifyOptions& options) {
  CertificationPlan plan;
  plan.samples = StructuredAlphaPatterns(levels);
  plan.structured = static_cast<int>(plan.samples.size());
  const int nc = num_alpha;
  std::mt19937 rng(20241);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < options.samples; ++i) {
    Eigen::VectorXd a(nc);
    for (int k = 0; k < nc; ++k) {
      a[k] = (nc < 20 && i < (1 << nc)) ? (((i >> k) & 1) ? 1.0 : -1.0) : u(rng);
    }
    plan.samples.push_back(a);
  }
  for (int i = 0; i < options.time_runs; ++i) {
    Eigen::VectorXd a(nc);
    for (int k = 0; k < nc; ++k) {
      a[k] = i == 0 ? 0.0 : (i <= 2 ? ((k % 2 == 0) == (i == 1) ? 1.0 : -1.0) : u(rng));
    }
    plan.time_runs.push_back(a);
  }
  return plan;
}

double SolveSampleAmplitude(const HarmonicBalance& system, const Eigen::VectorXd& alpha,
                            double freq_hz) {
  const FrfPoint p = SolveAtFrequency(system, alpha, freq_hz, Eigen::VectorXd(), FrfOptions{});
  return p.status == SolverStatus::kConverged ? p.amplitude : std::nan("");
}

TimeRunEvidence RunTimeEvidence(const Model& model, const HarmonicBalance& system,
                                const Eigen::VectorXd& initial_alpha, double freq_hz,
                                const TimeIntegrationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  TimeIntegrationOptions to = options;
  to.freq_hz = freq_hz;
  to.min_periods = std::min(to.min_periods, to.max_periods);
  const TimeIntegrationResult r = IntegrateToSteadyState(model, initial_alpha, to);
  TimeRunEvidence e;
  e.initial_alpha = initial_alpha;
  e.status = r.status;
  e.message = r.message;
  e.scheme = r.scheme;
  e.amplitude = r.amplitude;
  e.periods = r.periods;
  e.modes_integrated = r.modes_integrated;
  e.relative_change = r.relative_change;
  e.free_vibration = r.free_vibration;
  e.equivalent_alpha = r.equivalent_alpha;
  e.regimes = r.regimes;
  // Newton from the last period's harmonics at its equivalent α: where it converges, the
  // time-domain state is a member of the HBM's α-family. Not where α is grouped (no α per
  // contact to refine at).
  e.refinable = std::isfinite(r.amplitude) && model.alpha_group.empty() &&
                r.last_period_displacements.cols() > 0;
  if (e.refinable) {
    RefinedState& s = e.refined;
    Eigen::VectorXd x = system.FromDofCoefficients(LastPeriodCoefficients(r, system.harmonics()));
    const NewtonSummary ns = SolveNewton(
        HbmAtFrequency(system, RadPerS(freq_hz), r.equivalent_alpha), NewtonOptions{}, &x);
    s.converged = ns.IsSolutionUsable();
    s.iterations = ns.iterations;
    if (s.converged) {
      s.amplitude = system.Amplitude(x);
      s.x = x;
      if (!r.IsSteady()) {
        ContinueFromSolution(model, system, freq_hz, r.equivalent_alpha, to, r.amplitude, &s);
      }
    }
  }
  e.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

Certificate JudgeCertification(const HarmonicBalance& system, double freq_hz,
                               const BoundsOptions& options, const CertificationPlan& plan,
                               BoundsResult bounds, const std::vector<double>& sample_y,
                               std::vector<TimeRunEvidence> time_runs) {
  if (sample_y.size() != plan.samples.size()) {
    throw std::invalid_argument("JudgeCertification: one amplitude per plan sample expected");
  }
  Certificate c;
  c.freq_hz = freq_hz;
  c.y_min_optimised = bounds.min.amplitude;
  c.y_max_optimised = bounds.max.amplitude;
  const double lo0 = c.y_min_optimised, hi0 = c.y_max_optimised;
  // Solutions beyond the bound run's bounds: the optimisation restarts from them (their x keeps
  // the branch of periodic solutions they were found on).
  std::vector<KnownSolution> beyond;
  for (size_t i = 0; i < sample_y.size(); ++i) {
    if (std::isnan(sample_y[i]) || !Outside(sample_y[i], lo0, hi0)) continue;
    const FrfPoint p =
        SolveAtFrequency(system, plan.samples[i], freq_hz, Eigen::VectorXd(), FrfOptions{});
    if (p.status == SolverStatus::kConverged) beyond.push_back({p.x, plan.samples[i]});
  }
  for (const TimeRunEvidence& r : time_runs) {
    if (r.refined.converged && Outside(r.refined.amplitude, lo0, hi0)) {
      beyond.push_back({r.refined.x, r.equivalent_alpha});
    }
  }
  c.restarts = static_cast<int>(beyond.size());
  if (!beyond.empty()) c.bounds_moved = ImproveBounds(system, freq_hz, options, beyond, &bounds);
  const double lo = bounds.min.amplitude, hi = bounds.max.amplitude;
  c.y_min_relative_excess = std::isfinite(lo0) && lo < lo0 ? (lo0 - lo) / lo0 : 0.0;
  c.y_max_relative_excess = std::isfinite(hi0) && hi > hi0 ? (hi - hi0) / hi0 : 0.0;
  const size_t ns = sample_y.size(), st = static_cast<size_t>(plan.structured);
  c.sampling = Tally(sample_y, 0, ns, lo, hi);
  c.structured = Tally(sample_y, 0, st, lo, hi);
  c.uniform = Tally(sample_y, st, ns, lo, hi);
  for (TimeRunEvidence& r : time_runs) {
    const double y = r.amplitude;
    r.inside = y >= lo * (1 - kTimeDomainMargin) && y <= hi * (1 + kTimeDomainMargin);
    r.steady =
        r.status == TimeIntegrationResult::Status::kSteadyState || r.refined.run_settled_on_it;
    r.beyond = r.refined.converged && Outside(r.refined.amplitude, lo, hi);
    c.time_outside += r.steady && !r.inside;
    c.time_unsteady += !r.steady;
    c.time_beyond += r.beyond;
  }
  CertificationEvidence evidence{
      c.sampling.samples, c.sampling.failed, c.sampling.outside, static_cast<int>(time_runs.size()),
      c.time_unsteady,    c.time_outside,    c.time_beyond};
  evidence.bounds_beaten = c.bounds_moved;
  c.gaps = CertificationGaps(evidence);
  c.certified = c.gaps.empty() && bounds.IsUsable();
  if (!bounds.IsUsable()) c.gaps.emplace_back("the bounds did not converge");
  c.bounds = std::move(bounds);
  c.time_runs = std::move(time_runs);
  return c;
}

Certificate Certify(const Model& model, const HarmonicBalance& system, double freq_hz,
                    const BoundsOptions& options, const LevelSearchOptions& levels,
                    const CertifyOptions& certify) {
  std::string error;
  if (!certify.IsValid(&error)) throw std::invalid_argument(error);
  const CertificationPlan plan = PlanCertification(system.num_alpha(), levels.levels, certify);
  BoundsResult bounds = ComputeLevelBounds(system, freq_hz, options, levels);
  std::vector<double> y;
  for (const Eigen::VectorXd& a : plan.samples)
    y.push_back(SolveSampleAmplitude(system, a, freq_hz));
  std::vector<TimeRunEvidence> runs;
  for (const Eigen::VectorXd& a : plan.time_runs) {
    runs.push_back(RunTimeEvidence(model, system, a, freq_hz, certify.time));
  }
  return JudgeCertification(system, freq_hz, options, plan, std::move(bounds), y, std::move(runs));
}

std::string Certificate::BriefReport() const {
  std::ostringstream s;
  s << "Certification at " << freq_hz << " Hz: [" << bounds.min.amplitude << ", "
    << bounds.max.amplitude << "] m; " << sampling.samples - sampling.failed << "/"
    << sampling.samples << " samples solved (" << structured.samples << " structured), "
    << sampling.outside << " outside; " << time_runs.size() - time_unsteady << "/"
    << time_runs.size() << " time integrations steady";
  if (bounds_moved > 0) s << "; the bound run was beaten (" << bounds_moved << " bounds)";
  s << (certified ? "; CERTIFIED" : "; NOT CERTIFIED");
  for (const std::string& g : gaps) s << " [" << g << "]";
  return s.str();
}

}  // namespace fricrom
