// The alternating frequency/time (AFT) evaluation of one contact: harmonic coefficients of its
// relative displacements (u tangential, v normal) -> time samples (direct sums for 2H+1 ≤ 15,
// FFTW beyond) -> the contact law
// (contact.h) -> harmonic coefficients of T and N, with the exact coefficient-level derivatives.
// One implementation for the full (HbmSystem) and the condensed (CondensedSystem) balance.
// Coefficients follow hbm.h: [c0, a1, b1, ..., aH, bH].
#pragma once

#include <Eigen/Dense>
#include <memory>

#include "fricrom/contact_law.h"
#include "fricrom/harmonic_balance.h"

namespace fricrom {

struct ContactForceBlocks {
  Eigen::VectorXd t, n;                 // T̂, N̂ (2H+1 each) [N]
  Eigen::MatrixXd dt_du, dt_dv, dn_dv;  // ∂T̂/∂û, ∂T̂/∂v̂, ∂N̂/∂v̂ ((2H+1)², with derivatives)
  Eigen::VectorXd dt_dalpha;  // ∂T̂/∂α (with derivatives)
  Eigen::VectorXd u, v;       // relative displacement samples over the period [m]
  ContactLawResult law;       // T, N, states at the samples
  // Evaluate took the closed form of a contact stuck over the whole period (AddDerivatives
  // then needs no new pass over the samples).
  bool stuck_form = false;
};

// Which coefficient-level derivatives Evaluate computes (each costs N·(2H+1) per product).
struct AftDerivatives {
  bool displacement = false;  // dt_du, dt_dv, dn_dv
  bool alpha = false;         // dt_dalpha
  bool any() const { return displacement || alpha; }
};

// Owns the transforms (FFTW plans) and scratch of one harmonic/sample setting; Evaluate is not
// re-entrant (one object per thread).
class AftContactForces {
 public:
  explicit AftContactForces(const HbmOptions& options);  // throws std::invalid_argument
  ~AftContactForces();
  AftContactForces(const AftContactForces&) = delete;
  AftContactForces& operator=(const AftContactForces&) = delete;

  int num_coefficients() const;
  int num_samples() const;
  // uh, vh: 2H+1 coefficients each; |α| ≤ 1.
  void Evaluate(const ContactLawParams& params, const Eigen::VectorXd& uh,
                const Eigen::VectorXd& vh, double alpha, AftDerivatives derivatives,
                ContactForceBlocks* out) const;
  // The derivatives of an Evaluate without them that left `out` at these uh, vh, α: the same
  // blocks as Evaluate with `derivatives` would give, bit for bit; for a contact stuck over
  // the period in closed form, without another pass over the samples.
  void AddDerivatives(const ContactLawParams& params, const Eigen::VectorXd& uh,
                      const Eigen::VectorXd& vh, double alpha, AftDerivatives derivatives,
                      ContactForceBlocks* out) const;

 private:
  struct Plans;
  std::unique_ptr<Plans> plans_;
};

}  // namespace fricrom
