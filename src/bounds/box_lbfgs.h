// A limited-memory BFGS direction on the box [−1, 1]ⁿ for the reduced-space maximum runs
// (BoundsOptions::maximum_bfgs_memory): the two-loop recursion of Nocedal (1980) restricted to
// the free variables, those the gradient does not hold at a bound.
#pragma once

#include <Eigen/Core>
#include <deque>

namespace fricrom::bounds_detail {

class BoxLbfgs {
 public:
  explicit BoxLbfgs(int memory) : memory_(memory) {}

  // Records an accepted step s = α₊ − α with its gradient change y = g₊ − g. A pair without
  // positive curvature (s·y ≤ 10⁻¹² |s||y|, a kink of the response between the two points) is
  // not kept: it would make the direction ascend.
  void Push(const Eigen::VectorXd& s, const Eigen::VectorXd& y);
  void Clear() {
    s_.clear();
    y_.clear();
  }
  int pairs() const { return static_cast<int>(s_.size()); }

  // The direction −H g at α for the minimisation of a function with gradient g over the box:
  // zero where α sits at a bound and −g points out of the box, the inverse-Hessian estimate of
  // the stored pairs (each restricted to the free variables, skipped where that restriction
  // lost its curvature) on the others, scaled initially by s·y/y·y of the newest pair used.
  // With no pair usable −fallback_step · g on the free variables (the caller's Barzilai-Borwein
  // step), and −fallback_step · g if the estimate does not descend.
  Eigen::VectorXd Direction(const Eigen::VectorXd& alpha, const Eigen::VectorXd& g,
                            double fallback_step) const;

 private:
  int memory_;
  std::deque<Eigen::VectorXd> s_, y_;  // oldest first
};

}  // namespace fricrom::bounds_detail
