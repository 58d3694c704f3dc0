#include "gcode/estimate.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace flatmorph {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The largest speed (mm/s) at which the head may pass from direction `u` to direction `w` (unit
// vectors), before the nominal speeds of the two moves are taken into account.
double junction_speed(const Eigen::Vector3d& u, const Eigen::Vector3d& w, double acceleration,
                      const MotionLimits& limits) {
  if (limits.cornering == CorneringModel::kJerk) {
    const double change = (w - u).cwiseAbs().maxCoeff();
    return change < 1e-12 ? kInfinity : limits.jerk / change;
  }
  // grbl / Marlin 2: the speed of a circle of deviation `junction_deviation` tangent to both moves.
  const double cos_theta = -u.dot(w);
  if (cos_theta > 1 - 1e-9) return 0;           // full reversal
  if (cos_theta < -1 + 1e-9) return kInfinity;  // straight on
  const double sin_half = std::sqrt(0.5 * (1 - cos_theta));
  return std::sqrt(acceleration * limits.junction_deviation * sin_half / (1 - sin_half));
}

}  // namespace

MotionLimits motion_limits(const PrinterProfile& printer) {
  MotionLimits limits;
  limits.print_acceleration = printer.print_acceleration;
  limits.travel_acceleration = printer.travel_acceleration;
  limits.cornering = printer.cornering;
  limits.junction_deviation = printer.junction_deviation;
  limits.jerk = printer.jerk;
  return limits;
}

double trapezoid_time(double length, double v0, double v, double v1, double a) {
  if (length <= 0) return 0;
  const double accelerate = (v * v - v0 * v0) / (2 * a);
  const double decelerate = (v * v - v1 * v1) / (2 * a);
  if (accelerate + decelerate <= length) {
    return (v - v0) / a + (v - v1) / a + (length - accelerate - decelerate) / v;
  }
  // No cruise: the peak speed where the acceleration and deceleration ramps meet.
  const double peak = std::sqrt(std::max(0.0, a * length + (v0 * v0 + v1 * v1) / 2));
  return (peak - v0) / a + (peak - v1) / a;
}

double estimate_time(std::span<const Motion> motions, const MotionLimits& limits) {
  const size_t n = motions.size();
  // Per move: length, unit direction (zero for filament-only moves), nominal speed, acceleration.
  std::vector<double> length(n), speed(n), accel(n);
  std::vector<Eigen::Vector3d> dir(n);
  for (size_t i = 0; i < n; ++i) {
    const Motion& m = motions[i];
    const double d = m.delta.norm();
    const bool moves = d > 1e-12;
    length[i] = moves ? d : std::abs(m.e);
    dir[i] = moves ? Eigen::Vector3d(m.delta / d) : Eigen::Vector3d::Zero();
    speed[i] = std::max(m.speed, 1e-6);
    accel[i] = moves && m.e > 0 ? limits.print_acceleration : limits.travel_acceleration;
  }
  // entry[i]: the speed at the start of move i; entry[n] = 0 (rest at the end).
  std::vector<double> entry(n + 1, 0.0);
  for (size_t i = 1; i < n; ++i) {
    const bool both_move = dir[i - 1].squaredNorm() > 0 && dir[i].squaredNorm() > 0;
    entry[i] = both_move ? std::min({speed[i - 1], speed[i],
                                     junction_speed(dir[i - 1], dir[i], accel[i], limits)})
                         : 0.0;
  }
  // Backward pass: every move must be able to slow down to the next entry speed...
  for (size_t i = n; i-- > 0;) {
    entry[i] =
        std::min(entry[i], std::sqrt(entry[i + 1] * entry[i + 1] + 2 * accel[i] * length[i]));
  }
  // ...and forward pass: and to speed up from its own entry speed.
  for (size_t i = 0; i < n; ++i) {
    entry[i + 1] =
        std::min(entry[i + 1], std::sqrt(entry[i] * entry[i] + 2 * accel[i] * length[i]));
  }
  double total = 0;
  for (size_t i = 0; i < n; ++i) {
    total += trapezoid_time(length[i], entry[i], std::max({speed[i], entry[i], entry[i + 1]}),
                            entry[i + 1], accel[i]);
  }
  return total;
}

std::string format_duration(double seconds) {
  long s = std::lround(std::max(0.0, seconds));
  const long days = s / 86400;
  const long hours = (s / 3600) % 24;
  const long minutes = (s / 60) % 60;
  s %= 60;
  if (days > 0) return fmt::format("{}d {}h {}m {}s", days, hours, minutes, s);
  if (hours > 0) return fmt::format("{}h {}m {}s", hours, minutes, s);
  if (minutes > 0) return fmt::format("{}m {}s", minutes, s);
  return fmt::format("{}s", s);
}

}  // namespace flatmorph
