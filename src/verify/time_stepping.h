// Pieces both time integrators share (time_integration.h): the contacts' incremental law state,
// the static state for prescribed α, the loads and the end-of-run summary. Internal header.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "fricrom/contact_law.h"
#include "fricrom/model.h"
#include "fricrom/time_integration.h"

namespace fricrom::time_stepping {

// One contact's geometry (ground entries dropped) and its incremental law state.
struct ContactTerm {
  std::vector<int> dof_a, dof_b;  // DOF indices
  std::vector<double> n_a, t_a;   // normal/tangent components on the side-A DOFs
  std::vector<double> n_b, t_b;
  double kn = 0.0, kt = 0.0, mu = 0.0, n0 = 0.0;
  // Law state: tangential force and tangential displacement of the previous step.
  double t_prev = 0.0, u_prev = 0.0;

  ContactLawParams Params() const { return ContactLawParams{kn, kt, mu, n0}; }
  void Relative(const Eigen::VectorXd& q, double* u, double* v) const;
  // Adds the generalised contact force (+F on A, −F on B in the K q + F_C convention, i.e. the
  // force N n + T t acting on B) to fc.
  void Scatter(double normal, double tangential, Eigen::VectorXd* fc) const;
  // The contact law advanced by one sample: the same step as the AFT's (AdvanceContact).
  ContactState Advance(double u, double v, double* normal, double* tangential);
};

std::vector<ContactTerm> BuildContacts(const Model& model);

// Static equilibrium K q + F_C(q) = F0 with T = α μ N on every closed contact, by an active set on
// the open/closed status. Returns false (with a message) if singular or if the active set cycles.
bool SolveStatic(const Model& model, const std::vector<ContactTerm>& terms,
                 const Eigen::VectorXd& alpha, const Eigen::VectorXd& f0, Eigen::VectorXd* q,
                 std::string* message);

// Seats every contact at the static state q: T = α μ N where closed, 0 where open.
void SeatContacts(const Eigen::VectorXd& q, const Eigen::VectorXd& contact_alpha,
                  std::vector<ContactTerm>* terms);

// The loads as F w(t): column 0 the static load, then cos and sin of each harmonic load.
struct LoadBasis {
  Eigen::MatrixXd vectors;     // n × (1 + 2 loads) [N]
  std::vector<int> harmonics;  // per harmonic load
  Eigen::VectorXd Weights(long long step, int steps_per_period, double ramp) const;
};
LoadBasis BuildLoadBasis(const Model& model);

double FirstHarmonicAmplitude(const Eigen::VectorXd& samples, const Eigen::VectorXd& cos_table,
                              const Eigen::VectorXd& sin_table);
// Half-cosine ramp 0 → 1 over [0, t_ramp]: continuous with a continuous first derivative.
double Ramp(double t, double t_ramp);
// Infinitely smooth ramp 0 → 1 over [0, t_ramp] (ψ(s)/(ψ(s) + ψ(1 − s)), ψ(x) = exp(−1/x)): its
// spectrum decays faster than any power, so it leaves almost nothing in free modes detuned from
// the excitation (the half-cosine's leftover falls only as 1/(Δω t_ramp)², and lightly damped
// modes keep it for thousands of periods).
double SmoothRamp(double t, double t_ramp);

// Steady-state bookkeeping of the block test (TimeIntegrationOptions::block_periods), called once
// per period: returns true when the run may stop (settled); sets result->status/relative_change.
class SteadyTest {
 public:
  explicit SteadyTest(const TimeIntegrationOptions& options) : options_(options) {}
  bool Settled(int periods_done, double amplitude, TimeIntegrationResult* result);

 private:
  const TimeIntegrationOptions& options_;
  double prev_block_amplitude_ = -1.0;
};

// Fills amplitude, the last period's records, regimes, equivalent α and the message.
void FinishResult(const Model& model, const Eigen::MatrixXd& disp, const Eigen::MatrixXd& tang,
                  const Eigen::MatrixXd& norm, const std::vector<std::vector<ContactState>>& states,
                  double amplitude, const TimeIntegrationOptions& options,
                  TimeIntegrationResult* result);

}  // namespace fricrom::time_stepping
