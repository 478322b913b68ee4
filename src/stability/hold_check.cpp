// The time-integration check of a harmonic-balance solution (stability.h): integrate from its own
// state and see whether the motion stays on it.
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "fricrom/stability.h"
#include "fricrom/time_integration.h"
#include "fricrom/units.h"

namespace fricrom {

bool HoldOptions::IsValid(std::string* error) const {
  if (window_periods < 1 || windows < 2 || !(margin > 0.0) || !(modal_cutoff_factor >= 1.0)) {
    *error =
        "HoldOptions: window_periods >= 1, windows >= 2, margin > 0 and modal_cutoff_factor >= 1";
    return false;
  }
  return true;
}

HoldResult HoldsUnderTimeIntegration(const Model& model, const HarmonicBalance& system,
                                     const Eigen::VectorXd& x, double omega,
                                     const Eigen::VectorXd& alpha, const HoldOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument(error);
  const auto t0 = std::chrono::steady_clock::now();
  TimeIntegrationOptions to;
  to.scheme = TimeIntegrationOptions::Scheme::kImplicitModal;
  to.freq_hz = Hz(omega);
  to.window_periods = options.window_periods;
  to.min_periods = 1;
  to.max_periods = options.windows * options.window_periods;
  to.modal_cutoff_factor = options.modal_cutoff_factor;
  const TimeIntegrationResult t =
      IntegrateFromPeriodicState(model, PeriodicStartOf(model, system, x, omega, alpha), to);
  HoldResult r;
  r.solution_amplitude = system.Amplitude(x);
  r.status = ToString(t.status);
  r.amplitude = t.amplitude;
  r.periods = t.periods;
  const bool near =
      std::abs(t.amplitude - r.solution_amplitude) <= options.margin * r.solution_amplitude;
  r.holds = t.IsSteady() && near;
  r.message = r.holds         ? "the run from the solution stays on it"
              : !t.IsSteady() ? "the run from the solution did not settle: " + t.message
                              : "the run from the solution settled elsewhere (amplitude " +
                                    std::to_string(t.amplitude) + " m against " +
                                    std::to_string(r.solution_amplitude) + " m)";
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace fricrom
