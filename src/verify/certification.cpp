#include "fricrom/certification.h"

namespace fricrom {

std::vector<std::string> CertificationGaps(const CertificationEvidence& e) {
  std::vector<std::string> gaps;
  const int solved = e.samples - e.samples_failed;
  const int steady = e.time_runs - e.time_runs_unsteady;
  if (solved <= 0 && steady <= 0) gaps.emplace_back("nothing was checked");
  if (e.samples_failed > 0) {
    gaps.push_back(std::to_string(e.samples_failed) + " of " + std::to_string(e.samples) +
                   " alpha samples did not converge");
  }
  if (e.samples_outside > 0) {
    gaps.push_back(std::to_string(e.samples_outside) + " alpha samples outside the bounds");
  }
  if (e.time_runs_unsteady > 0) {
    gaps.push_back(std::to_string(e.time_runs_unsteady) + " of " + std::to_string(e.time_runs) +
                   " time integrations reached no steady state");
  }
  if (e.time_runs_outside > 0) {
    gaps.push_back(std::to_string(e.time_runs_outside) + " time integrations outside the bounds");
  }
  if (e.time_states_beyond > 0) {
    gaps.push_back(std::to_string(e.time_states_beyond) +
                   " time integrations end at a harmonic-balance solution beyond the bounds (the "
                   "bounds are local optima there)");
  }
  if (e.bounds_beaten > 0) {
    gaps.push_back("the bound run was beaten: " + std::to_string(e.bounds_beaten) +
                   " of its bounds lay inside a solution found by the checks");
  }
  return gaps;
}

}  // namespace fricrom
