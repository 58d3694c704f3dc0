#include "material/hinge_curve.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "common/error.h"
#include "material/monotone_curve.h"

namespace flatmorph {
namespace {

// Faster than any FFF printer extrudes: a range beyond it was written in mm/min.
constexpr double kMaxPlausibleTpuSpeed = 1000;
// A fold of more than 2 rad per mm (r < 0.5 mm) is no 0.8 mm thick strip: a unit mistake.
constexpr double kMaxCurvature = 2;
constexpr int kHingeCurveSamples = 400;
// Slack at the ends of the range (mm/s), for speeds read back from text.
constexpr double kSpeedSlack = 1e-9;

std::span<const double> coefficients(const HingeCurve& c, bool pla_on_bed) {
  return pla_on_bed ? c.case_a_coefficients : c.case_b_coefficients;
}

std::string case_problem(const HingeCurve& c, bool pla_on_bed) {
  const std::span<const double> k = coefficients(c, pla_on_bed);
  const std::string name = hinge_case_name(pla_on_bed);
  if (k.empty() || k.size() > kMaxCurveCoefficients) {
    return fmt::format("{} has {} coefficients; give 1 to {}", name, k.size(),
                       kMaxCurveCoefficients);
  }
  for (double x : k) {
    if (!std::isfinite(x))
      return fmt::format("{} has a coefficient that is no finite number", name);
  }
  double previous = 0;
  int sign = 0;
  for (int i = 0; i <= kHingeCurveSamples; ++i) {
    const double v = c.min_speed + (c.max_speed - c.min_speed) * i / kHingeCurveSamples;
    const double kappa = polynomial_value(k, v);
    if (!(kappa > 0 && kappa <= kMaxCurvature)) {
      return fmt::format(
          "{} gives a curvature of {:g} /mm at {:g} mm/s; a hinge bends to a curvature in (0, "
          "{:g}] /mm (1 / radius in mm)",
          name, kappa, v, kMaxCurvature);
    }
    if (i > 0) {
      const int s = kappa > previous ? 1 : (kappa < previous ? -1 : 0);
      if (s == 0 || (sign != 0 && s != sign)) {
        return fmt::format(
            "{}'s curvature is not strictly monotone on [{:g}, {:g}] mm/s (it turns near {:g} "
            "mm/s), so a fold would have several speeds",
            name, c.min_speed, c.max_speed, v);
      }
      sign = s;
    }
    previous = kappa;
  }
  return "";
}

}  // namespace

std::string hinge_case_name(bool pla_on_bed) {
  return pla_on_bed ? "case A (PLA on the bed)" : "case B (TPU on the bed)";
}

std::string hinge_stack_problem(const HingeStack& s) {
  if (!(s.layer_height > 0 && s.layer_height <= 1)) {
    return fmt::format("its layer height is {:g} mm; give (0, 1] mm", s.layer_height);
  }
  if (s.pla_layers < 1 || s.pla_layers > 20 || s.tpu_layers < 1 || s.tpu_layers > 20) {
    return fmt::format("it has {} PLA and {} TPU layers; give 1 to 20 of each", s.pla_layers,
                       s.tpu_layers);
  }
  if (!(s.tpu_speed > 0 && s.tpu_speed <= kMaxPlausibleTpuSpeed)) {
    return fmt::format("its TPU speed is {:g} mm/s; give (0, {:g}] mm/s (not mm/min)", s.tpu_speed,
                       kMaxPlausibleTpuSpeed);
  }
  if (!(s.overlap >= 0 && s.overlap <= 10)) {
    return fmt::format("its overlap into the faces is {:g} mm; give 0 to 10 mm", s.overlap);
  }
  return "";
}

std::string hinge_curve_problem(const HingeCurve& c) {
  if (!(c.min_speed > 0) || !(c.max_speed > c.min_speed) || !std::isfinite(c.max_speed)) {
    return fmt::format("its speed range [{:g}, {:g}] mm/s is not an interval of positive speeds",
                       c.min_speed, c.max_speed);
  }
  if (c.max_speed > kMaxPlausibleTpuSpeed) {
    return fmt::format(
        "its speed range ends at {:g} mm/s, faster than any printer extrudes; give the speeds in "
        "mm/s (a G-code feed rate in mm/min is 60 times larger)",
        c.max_speed);
  }
  for (bool pla_on_bed : {true, false}) {
    if (std::string problem = case_problem(c, pla_on_bed); !problem.empty()) return problem;
  }
  if (std::string problem = hinge_stack_problem(c.stack); !problem.empty()) {
    return "its actuator stack is unusable: " + problem;
  }
  if (!(c.nozzle_temperature >= 0 && c.nozzle_temperature <= 350)) {
    return fmt::format("its nozzle temperature is {:g} C; give 0 (not recorded) to 350 C",
                       c.nozzle_temperature);
  }
  return "";
}

double hinge_curvature(const HingeCurve& c, double speed, bool pla_on_bed) {
  if (!(speed >= c.min_speed - kSpeedSlack && speed <= c.max_speed + kSpeedSlack)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("an actuator printed at {:g} mm/s ({:g} mm/min) lies outside the {} hinge "
                    "curve's speeds, {:g} to {:g} mm/s ({:g} to {:g} mm/min): choose a speed in "
                    "that range{}",
                    speed, 60 * speed, c.calibrated ? "calibrated" : "default", c.min_speed,
                    c.max_speed, 60 * c.min_speed, 60 * c.max_speed,
                    c.calibrated ? ", or calibrate a wider one ('flatmorph calibrate print "
                                   "--hinge-sheet --hinge-speeds ...')"
                                 : ", or calibrate the hinges ('flatmorph calibrate print "
                                   "--hinge-sheet')"));
  }
  return polynomial_value(coefficients(c, pla_on_bed), std::clamp(speed, c.min_speed, c.max_speed));
}

double hinge_speed_for_curvature(const HingeCurve& c, double curvature, bool pla_on_bed) {
  const std::span<const double> k = coefficients(c, pla_on_bed);
  double lo = c.min_speed, hi = c.max_speed;
  const double at_lo = polynomial_value(k, lo), at_hi = polynomial_value(k, hi);
  const double least = std::min(at_lo, at_hi), most = std::max(at_lo, at_hi);
  const double slack = 1e-12;
  if (!(curvature >= least - slack && curvature <= most + slack)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("a hinge curvature of {:.4g} /mm (radius {:.3g} mm) is outside what a {} "
                    "actuator reaches with the {} hinge curve: {:.4g} to {:.4g} /mm (radius "
                    "{:.3g} to {:.3g} mm) for speeds of {:g} to {:g} mm/s; change the "
                    "actuator's width (W = fold angle / curvature) to bring it into that range",
                    curvature, 1 / curvature, hinge_case_name(pla_on_bed),
                    c.calibrated ? "calibrated" : "default", least, most, 1 / most, 1 / least,
                    c.min_speed, c.max_speed));
  }
  // 100 halvings reach the resolution of a double.
  const bool increasing = at_hi > at_lo;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if ((polynomial_value(k, mid) < curvature) == increasing) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace flatmorph
