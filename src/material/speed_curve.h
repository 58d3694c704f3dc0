// How the shrink ratio along the path depends on the print speed, for the methods that vary the
// speed to vary the shrinkage (Thermorph "Controllability", Fig. 6: faster printing pulls
// the filament harder, stores more stretch, and the layer shrinks more when heated): a polynomial
// lambda1(v) of degree at most 4, monotone on the range of speeds it was calibrated on, and its
// inverse (wanted lambda1 -> print speed). Outside that range neither is defined: both refuse with
// a UserError. Speeds in mm/s everywhere (G-code feed rates are mm/min: convert where they are
// read or written); lambda1 = length after heating / printed length.
#pragma once

#include <string>
#include <vector>

#include "material/monotone_curve.h"

namespace flatmorph {

// How messages of the shared curve code (monotone_curve.h) name the print speed.
inline constexpr CurveParameter kSpeedCurveParameter = {
    "print speed", "mm/s", "speed curve", "calibrate print --speed-ramp", "--print-speeds"};

struct SpeedCurve {
  // lambda1(v) = sum_i lambda1_coefficients[i] * v^i, v in mm/s (1 to 5 coefficients).
  std::vector<double> lambda1_coefficients;
  double min_print_speed = 0;  // mm/s, the calibrated range
  double max_print_speed = 0;  // mm/s
  // How the samples were printed (0: not recorded): the curve holds for about that layer height.
  double layer_height = 0;        // mm
  double nozzle_temperature = 0;  // degrees C
};

// Empty when `curve` is usable (1 to 5 finite coefficients, 0 < min < max <= 1000 mm/s, lambda1
// in (0, 2] and strictly monotone on [min, max], a layer height and temperature of 0 or more);
// otherwise the first problem, as a sentence.
std::string speed_curve_problem(const SpeedCurve& curve);

// lambda1 at print speed `v` (mm/s). Throws UserError(kInfeasible) when v lies outside the
// calibrated range.
double lambda1_at_print_speed(const SpeedCurve& curve, double v);

// The print speed (mm/s) at which the material shrinks to `lambda1` along the path: the inverse of
// lambda1_at_print_speed, by bisection on the calibrated range (Thermorph chooses the speed of an
// actuator for the fold it wants). Throws UserError(kInfeasible) naming the reachable range when
// `lambda1` is outside it.
double print_speed_for_lambda1(const SpeedCurve& curve, double lambda1);

}  // namespace flatmorph
