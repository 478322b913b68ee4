// Units: SI throughout; frequencies enter and leave the library in Hz, the core works in rad/s.
// The one place the conversion constant lives.
#pragma once

#include <numbers>

namespace fricrom {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

// f [Hz] -> ω [rad/s] and back.
constexpr double RadPerS(double hz) { return kTwoPi * hz; }
constexpr double Hz(double rad_per_s) { return rad_per_s / kTwoPi; }

}  // namespace fricrom
