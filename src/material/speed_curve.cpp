#include "material/speed_curve.h"

#include <fmt/core.h>

#include <cmath>

namespace flatmorph {
namespace {

// Faster than any FFF printer extrudes: a range beyond it was written in mm/min (Thermorph's
// 1500-9000 mm/min are 25-150 mm/s).
constexpr double kMaxPlausibleSpeed = 1000;

MonotoneCurve view(const SpeedCurve& c) {
  return {c.lambda1_coefficients, c.min_print_speed, c.max_print_speed};
}

}  // namespace

std::string speed_curve_problem(const SpeedCurve& c) {
  if (c.max_print_speed > kMaxPlausibleSpeed) {
    return fmt::format(
        "its range ends at {:g} mm/s, faster than any printer extrudes; give the "
        "speeds in mm/s (a G-code feed rate in mm/min is 60 times larger)",
        c.max_print_speed);
  }
  if (std::string problem = monotone_curve_problem(view(c), kSpeedCurveParameter);
      !problem.empty()) {
    return problem;
  }
  if (!(c.layer_height >= 0 && c.layer_height <= 1) ||
      !(c.nozzle_temperature >= 0 && c.nozzle_temperature <= 350)) {
    return fmt::format(
        "it was printed at {:g} mm layers and {:g} C; give a layer height of 0 to "
        "1 mm and a temperature of 0 to 350 C (0: not recorded)",
        c.layer_height, c.nozzle_temperature);
  }
  return "";
}

double lambda1_at_print_speed(const SpeedCurve& curve, double v) {
  return monotone_curve_value(view(curve), v, kSpeedCurveParameter);
}

double print_speed_for_lambda1(const SpeedCurve& curve, double lambda1) {
  return monotone_curve_inverse(view(curve), lambda1, kSpeedCurveParameter);
}

}  // namespace flatmorph
