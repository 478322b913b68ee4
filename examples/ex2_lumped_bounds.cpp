// Example 2: response bounds, robustness and the most robust design of the paper's lumped
// 3-blade / 2-damper system (Zara et al. 2024, §4).
//
//   build/examples/ex2_lumped_bounds [meshes/lumped3/baseline.toml] [freq_hz]
//
// The steps of a robust-design study through the library: read a case, build its harmonic
// balance, solve it at one α, bound the response over every admissible α, check the bounds
// against an independent route (random α solved one by one), and find the asymmetry γ of the
// damper preloads that makes the response most robust. Also run by ctest
// (Examples.LumpedBounds): exit status 0 only if every check below holds. Units SI.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/design.h"
#include "fricrom/frf.h"
#include "fricrom/linear.h"

namespace {

std::unique_ptr<fricrom::HarmonicBalance> BalanceOf(const fricrom::Case& c) {
  const fricrom::HbmOptions hbm{c.analysis.harmonics, c.analysis.samples_per_period,
                                c.analysis.receptance};
  return fricrom::MakeBalance(c.model, hbm, c.analysis.balance);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "meshes/lumped3/baseline.toml";
  const double freq = argc > 2 ? std::stod(argv[2]) : 266.0;
  try {
    // 1. The case: bodies, springs, wedge contacts and loads, all as data (docs/case-files.md).
    const fricrom::Case c = fricrom::LoadCase(path);
    const std::unique_ptr<fricrom::HarmonicBalance> balance = BalanceOf(c);
    std::printf("1. %s: %d DOFs, %zu contacts, H = %d\n", c.name.c_str(), c.model.num_dofs(),
                c.model.contacts.size(), c.analysis.harmonics);

    // 2. The linear limits: contacts free (no damper) and fully stuck.
    const double free_amp =
        fricrom::LinearResponseAmplitude(c.model, fricrom::LinearSystemKind::kFree, {freq})[0];
    const double stick_amp =
        fricrom::LinearResponseAmplitude(c.model, fricrom::LinearSystemKind::kStick, {freq})[0];
    std::printf("2. linear response at %.1f Hz: free %.4e m, full stick %.4e m\n", freq, free_amp,
                stick_amp);

    // 3. One member of the family: the nonlinear response at α = 0 (no initial tangential force).
    const Eigen::VectorXd alpha0 = Eigen::VectorXd::Zero(balance->num_alpha());
    const fricrom::FrfPoint at0 =
        fricrom::SolveAtFrequency(*balance, alpha0, freq, Eigen::VectorXd(), fricrom::FrfOptions{});
    if (at0.status != fricrom::SolverStatus::kConverged) {
      std::fprintf(stderr, "alpha = 0: %s\n", at0.message.c_str());
      return 1;
    }
    std::printf("3. response at alpha = 0: %.4e m (%d Newton iterations)\n", at0.amplitude,
                at0.iterations);

    // 4. The bounds over every α in [-1, 1]^n: minimum and maximum response, R = y_min / y_max.
    fricrom::BoundsOptions options;
    options.search_harmonics = c.analysis.search_harmonics;
    std::string why;
    if (!options.IsValid(&why)) {
      std::fprintf(stderr, "options: %s\n", why.c_str());
      return 2;
    }
    const fricrom::BoundsResult b = fricrom::ComputeBounds(*balance, freq, options);
    std::printf("4. %s\n", b.BriefReport().c_str());
    if (!b.IsUsable()) return 1;
    const double lo = b.min.amplitude, hi = b.max.amplitude;
    bool ok =
        lo <= at0.amplitude && at0.amplitude <= hi && b.robustness() > 0.0 && b.robustness() <= 1.0;

    // 5. Independent route: random α solved one by one must all lie inside the bounds.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int solved = 0, outside = 0;
    const int samples = 200;
    for (int s = 0; s < samples; ++s) {
      Eigen::VectorXd alpha(balance->num_alpha());
      for (Eigen::Index k = 0; k < alpha.size(); ++k) alpha[k] = u(rng);
      const fricrom::FrfPoint p =
          fricrom::SolveAtFrequency(*balance, alpha, freq, Eigen::VectorXd(), {});
      if (p.status != fricrom::SolverStatus::kConverged) continue;
      ++solved;
      if (p.amplitude < lo * (1 - 1e-9) || p.amplitude > hi * (1 + 1e-9)) ++outside;
    }
    std::printf("5. %d random alpha: %d solved, %d outside [%.4e, %.4e] m\n", samples, solved,
                outside, lo, hi);
    ok = ok && solved >= samples * 95 / 100 && outside == 0;

    // 6. The most robust design: the nested optimisation over γ (damper preloads (1 -/+ γ)),
    //    a scan then golden-section refinement, each value's R from its own bounds.
    fricrom::NoaOptions noa;
    noa.lower = 0.0;
    noa.upper = 0.43;
    noa.objective = fricrom::NoaOptions::kOneMinusR;
    noa.inner.reference_freq_hz = freq;
    noa.inner.bounds = options;
    const fricrom::NoaResult best = fricrom::RunNoa(
        [&](double gamma) {
          return BalanceOf(fricrom::LoadCase(path, {{"gamma", gamma}}));
        },
        noa);
    std::printf("6. %s\n", best.BriefReport().c_str());
    double best_seen = 0.0;
    for (const fricrom::RobustnessPoint& p : best.history) {
      if (std::isfinite(p.robustness)) best_seen = std::max(best_seen, p.robustness);
    }
    ok = ok && best.converged && best.robustness >= best_seen;
    std::printf("%s\n", ok ? "all checks passed" : "CHECK FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {  // bad case file, unknown parameter, ...
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
