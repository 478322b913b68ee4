// The verdict of a certification of response bounds (fricrom verify): what was checked, and the
// rule that turns it into "certified". A certificate needs evidence: at least one check, no
// sample that failed to solve, nothing outside the bounds, every time integration at a steady
// state.
#pragma once

#include <string>
#include <vector>

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

}  // namespace fricrom
