// Bounds over the stable solutions among candidates (stability.h, BoundsOverStableSolutions).
#include <random>
#include <stdexcept>
#include <vector>

#include "fricrom/frf.h"
#include "fricrom/stability.h"
#include "fricrom/units.h"

namespace fricrom {

namespace {

// The α of the candidates beyond the bounds' own: the box's two uniform corners, then uniform
// random α from a fixed stream (the same candidates on every run).
std::vector<Eigen::VectorXd> SampleAlphas(int num_alpha, int samples) {
  std::vector<Eigen::VectorXd> out;
  std::mt19937 rng(20261206u);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int k = 0; k < samples; ++k) {
    if (k < 2) {
      out.push_back(Eigen::VectorXd::Constant(num_alpha, k == 0 ? 1.0 : -1.0));
      continue;
    }
    Eigen::VectorXd a(num_alpha);
    for (Eigen::Index i = 0; i < a.size(); ++i) a[i] = unit(rng);
    out.push_back(a);
  }
  return out;
}

}  // namespace

StableBounds BoundsOverStableSolutions(SolutionStability* stability, const HarmonicBalance& system,
                                       const BoundsResult& b, int samples,
                                       const HillOptions& options) {
  if (samples < 0) throw std::invalid_argument("BoundsOverStableSolutions: samples must be >= 0");
  StableBounds out;
  const double omega = RadPerS(b.freq_hz);
  // A stable candidate widens the stable bounds; `exact` marks a bound's own solution.
  const auto consider = [&](BoundSolution s, bool own_min, bool own_max) {
    try {
      const HillResult r = stability->At(s.x, omega, s.alpha, options);
      ++out.candidates;
      out.approximate += r.approximate();
      if (!r.stable) return;
      ++out.stable;
      s.stability = {true, true, r.max_real, r.message};
      if (!(out.min.amplitude <= s.amplitude)) {
        out.min = s;
        out.exact_min = own_min;
      }
      if (!(out.max.amplitude >= s.amplitude)) {
        out.max = s;
        out.exact_max = own_max;
      }
    } catch (const std::domain_error&) {
      ++out.failed;
    }
  };
  // The bounds' own solutions first: one that is stable is the stable bound, unless a sample lies
  // beyond the bounds (the search missed it; counted in beyond_bounds).
  if (b.min.IsUsable()) consider(b.min, true, false);
  if (b.max.IsUsable()) consider(b.max, false, true);
  const BoundSolution& from = b.max.IsUsable() ? b.max : b.min;
  if (!from.IsUsable()) return out;
  FrfOptions quick;
  quick.use_fallbacks = false;  // a sample that plain Newton misses is skipped, not chased
  for (const Eigen::VectorXd& alpha : SampleAlphas(system.num_alpha(), samples)) {
    const FrfPoint p = SolveAtFrequency(system, alpha, b.freq_hz, from.x, quick);
    if (p.status != SolverStatus::kConverged || !std::isfinite(p.amplitude)) {
      ++out.failed;
      continue;
    }
    // Stable or not, a sample beyond the bounds is one the search missed.
    out.beyond_bounds += (b.max.IsUsable() && p.amplitude > b.max.amplitude) ||
                         (b.min.IsUsable() && p.amplitude < b.min.amplitude);
    BoundSolution s;
    s.x = p.x;
    s.alpha = alpha;
    s.amplitude = p.amplitude;
    s.status = BoundStatus::kConverged;
    s.message = "alpha sample";
    consider(s, false, false);
  }
  return out;
}

}  // namespace fricrom
