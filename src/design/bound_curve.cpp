// Bound curves over frequency: the bounds point by point with warm-started α seeds, and the
// resonance of the maximum-response bound.
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fricrom/design.h"

namespace fricrom {

std::vector<double> EvenFrequencies(double lo_hz, double hi_hz, int points) {
  if (points < 2 || !(lo_hz > 0.0) || !(hi_hz > lo_hz) || !std::isfinite(hi_hz)) {
    throw std::invalid_argument("EvenFrequencies: need 0 < lo < hi (finite) and points >= 2");
  }
  std::vector<double> f(points);
  for (int i = 0; i < points; ++i) f[i] = lo_hz + (hi_hz - lo_hz) * i / (points - 1);
  return f;
}

BoundCurve ComputeBoundCurve(const HarmonicBalance& system, const std::vector<double>& freqs_hz,
                             const BoundCurveOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  for (double f : freqs_hz) {
    if (!(f > 0.0) || !std::isfinite(f)) {
      throw std::invalid_argument("ComputeBoundCurve: frequencies must be positive and finite");
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  BoundCurve curve;
  const int total = static_cast<int>(freqs_hz.size());
  for (int i = 0; i < total; ++i) {
    BoundsOptions bo = options.bounds;
    // The previous point's optima are usually the closest starts (the optimal α moves little
    // between neighbouring frequencies).
    if (options.warm_start && i > 0) {
      const BoundsResult& prev = curve.points.back();
      if (bo.alpha_seeds.empty()) bo.alpha_seeds = DefaultAlphaSeeds(system.num_alpha());
      if (prev.min.IsUsable()) bo.alpha_seeds.push_back(prev.min.alpha);
      if (prev.max.IsUsable()) bo.alpha_seeds.push_back(prev.max.alpha);
    }
    if (options.progress) {
      std::ostringstream label;
      label << freqs_hz[i] << " Hz: ";
      const auto outer = options.progress;
      const std::string prefix = label.str();
      bo.progress = [outer, prefix](const std::string& stage, int done, int n) {
        outer(prefix + stage, done, n);
      };
    }
    curve.points.push_back(ComputeBounds(system, freqs_hz[i], bo));
    const BoundsResult& b = curve.points.back();
    if (b.max.IsUsable() &&
        (curve.peak < 0 || b.max.amplitude > curve.points[curve.peak].max.amplitude)) {
      curve.peak = i;
    }
    if (options.progress) options.progress("frequencies", i + 1, total);
  }
  curve.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return curve;
}

std::string BoundCurve::BriefReport() const {
  std::ostringstream os;
  int usable = 0;
  for (const BoundsResult& b : points) usable += b.IsUsable();
  os << "bound curve: " << points.size() << " frequencies, " << usable << " with both bounds";
  if (HasPeak()) {
    const BoundsResult& p = points[peak];
    os << "; peak of y_max at " << p.freq_hz << " Hz: y_min " << p.min.amplitude << " m, y_max "
       << p.max.amplitude << " m, R " << p.robustness();
  } else {
    os << "; no maximum-response bound converged";
  }
  os << "; " << wall_s << " s";
  return os.str();
}

}  // namespace fricrom
