// Angle constants and the one angle wrap: radians everywhere, degrees only where a file or a
// message speaks them.
#pragma once

#include <cmath>
#include <numbers>

namespace flatmorph {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kDegree = std::numbers::pi / 180;            // rad per degree
constexpr double kDegreesPerRadian = 180 / std::numbers::pi;  // degrees per rad

// x (rad) wrapped to [-pi, pi).
inline double wrap_angle(double x) { return x - kTwoPi * std::floor((x + kPi) / kTwoPi); }

}  // namespace flatmorph
