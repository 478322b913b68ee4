// The Gauss-Newton step of the reduced-space minimum runs (RunSetup::gauss_newton).
#pragma once

#include <Eigen/Core>

namespace fricrom::bounds_detail {

// The Gauss-Newton target for y(α) → 0 on the box: the least-norm δ with g·δ = −2φ (g = ∇φ, so
// that the linearised |y|² vanishes along the phasor) and jq·δ = 0 (nor does it turn), entries
// that would leave [−1, 1] fixed at the bound they cross and the rest solved again. Where the
// two rows are nearly parallel (the α cannot turn the phasor) the second is dropped. False if
// no step remains.
bool GaussNewtonTarget(const Eigen::VectorXd& a, const Eigen::VectorXd& g, double phi,
                       const Eigen::VectorXd& jq, Eigen::VectorXd* target);

}  // namespace fricrom::bounds_detail
