// Example 3: friction contacts on reduced FE models — the response bounds of the coarse FE
// cascade (3 blade sectors, 2 wedge dampers, 108 node pairs).
//
//   build/examples/ex3_fe_cascade_bounds [meshes/cascade3/coarse.toml] [freq_hz]
//
// The steps from exported FE matrices to robustness: read an assembly case (each body's
// CalculiX matrices reduced by Craig-Bampton onto its contact, load and response nodes on first
// use, then cached), pair the contact faces node to node, condense the harmonic balance onto the
// contact DOFs, bound the response over the per-pair α, and check the bounds against α sampled
// pair by pair. Also run by ctest (Examples.FeCascadeBounds): exit status 0 only if every check
// below holds. Units SI.
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fricrom/balance.h"
#include "fricrom/bounds.h"
#include "fricrom/case_file.h"
#include "fricrom/frf.h"
#include "fricrom/linear.h"

namespace {

// How many contacts are in each state, e.g. "stick-slip 40, full-stick 68".
std::string StateCounts(const std::vector<fricrom::ContactRegime>& regimes) {
  std::map<std::string, int> n;
  for (fricrom::ContactRegime r : regimes) ++n[fricrom::ToString(r)];
  std::string s;
  for (const auto& [name, count] : n)
    s += (s.empty() ? "" : ", ") + name + " " + std::to_string(count);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "meshes/cascade3/coarse.toml";
  const double freq = argc > 2 ? std::stod(argv[2]) : 1000.0;
  try {
    // 1. The assembly: reduced bodies and interfaces paired by coordinates (docs/case-files.md).
    const fricrom::Case c = fricrom::LoadCase(path);
    std::printf(
        "1. %s: %d reduced DOFs, %zu interfaces, %d node pairs, %zu contact laws, %d alpha\n",
        c.name.c_str(), c.model.num_dofs(), c.interface_names.size(), c.model.num_contact_pairs(),
        c.model.contacts.size(), c.model.num_alpha());

    // 2. The harmonic balance condensed onto the contact DOFs, with the modal receptance.
    const std::unique_ptr<fricrom::HarmonicBalance> balance = fricrom::MakeBalance(
        c.model,
        fricrom::HbmOptions{c.analysis.harmonics, c.analysis.samples_per_period,
                            c.analysis.receptance},
        c.analysis.balance);
    std::printf("2. %s balance, H = %d: %d unknowns\n",
                fricrom::ToString(c.analysis.balance).c_str(), c.analysis.harmonics,
                balance->num_unknowns());

    // 3. The linear limits at the frequency: dampers absent (free; blade 2 is not excited, so
    //    its response is zero) and fully stuck.
    const double free_amp = fricrom::LinearResponseAmplitude(
        c.model, fricrom::LinearSystemKind::kFree, {freq}, c.analysis.receptance)[0];
    const double stick_amp = fricrom::LinearResponseAmplitude(
        c.model, fricrom::LinearSystemKind::kStick, {freq}, c.analysis.receptance)[0];
    std::printf("3. linear response at %.1f Hz: free %.4e m, full stick %.4e m\n", freq, free_amp,
                stick_amp);

    // 4. The bounds over α per node pair, searched at H = 1 and refined at the case's H (the
    //    case's harmonic ladder); the default seeds plus the sample check.
    fricrom::BoundsOptions options;
    options.search_harmonics = c.analysis.search_harmonics;
    const fricrom::BoundsResult b = fricrom::ComputeBounds(*balance, freq, options);
    std::printf("4. y_min %.4e m, y_max %.4e m, R = %.4f (%s, %.2f s)\n", b.min.amplitude,
                b.max.amplitude, b.robustness(), b.IsUsable() ? "converged" : "FAILED", b.wall_s);
    if (!b.IsUsable()) {
      std::fprintf(stderr, "%s\n", b.BriefReport().c_str());
      return 1;
    }
    std::printf("   contacts at the minimum: %s\n", StateCounts(b.min.regimes).c_str());
    std::printf("   contacts at the maximum: %s\n", StateCounts(b.max.regimes).c_str());
    const double lo = b.min.amplitude, hi = b.max.amplitude;
    bool ok = c.model.num_contact_pairs() == 108 && b.robustness() > 0.0 && b.robustness() <= 1.0;

    // 5. Independent route: α drawn per pair, each solved on its own, must lie inside the bounds.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int samples = 40;
    int solved = 0, outside = 0;
    for (int s = 0; s < samples; ++s) {
      Eigen::VectorXd alpha(balance->num_alpha());
      for (Eigen::Index k = 0; k < alpha.size(); ++k) alpha[k] = u(rng);
      const fricrom::FrfPoint p =
          fricrom::SolveAtFrequency(*balance, alpha, freq, Eigen::VectorXd(), {});
      if (p.status != fricrom::SolverStatus::kConverged) continue;
      ++solved;
      if (p.amplitude < lo * (1 - 1e-9) || p.amplitude > hi * (1 + 1e-9)) ++outside;
    }
    std::printf("5. %d random alpha: %d solved, %d outside the bounds\n", samples, solved, outside);
    ok = ok && solved >= samples * 95 / 100 && outside == 0;
    std::printf("%s\n", ok ? "all checks passed" : "CHECK FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {  // bad case file, FE file, unknown node set, ...
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
