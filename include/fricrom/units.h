// Units: SI throughout; frequencies enter and leave the library in Hz, the core works in rad/s.
// The one place the conversion constant lives.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fricrom {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

// f [Hz] -> ω [rad/s] and back.
constexpr double RadPerS(double hz) { return kTwoPi * hz; }
constexpr double Hz(double rad_per_s) { return rad_per_s / kTwoPi; }

// Eigenvalue λ = ω² of K φ = λ M φ [rad²/s²] <-> frequency [Hz]; round-off negatives read as 0 Hz.
inline double HzFromEigenvalue(double lambda) { return Hz(std::sqrt(std::max(lambda, 0.0))); }
constexpr double EigenvalueFromHz(double hz) { return RadPerS(hz) * RadPerS(hz); }

}  // namespace fricrom
