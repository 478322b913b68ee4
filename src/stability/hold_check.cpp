// The time-integration check of a harmonic-balance solution (stability.h): integrate from its own
// state and see whether the motion stays on it.
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>
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
  // A lightly damped stable solution can still be shedding the free vibration its start excites
  // when the run ends (not settled): it holds if the motion is still within the margin of it.
  const bool ran = t.status == TimeIntegrationResult::Status::kSteadyState ||
                   t.status == TimeIntegrationResult::Status::kNotSettled;
  r.settled = t.IsSteady();
  r.holds = ran && near;
  std::ostringstream os;
  os << std::setprecision(4);
  if (!ran) {
    os << "the run from the solution failed: " << t.message;
  } else if (r.holds) {
    os << "the run from the solution stays within " << 100 * options.margin << " % of it over "
       << t.periods << " periods" << (r.settled ? "" : " (not yet settled)");
  } else {
    os << "the run from the solution left it: amplitude " << t.amplitude << " m against "
       << r.solution_amplitude << " m after " << t.periods << " periods";
  }
  r.message = os.str();
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace fricrom
