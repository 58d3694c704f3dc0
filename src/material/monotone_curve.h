// The piece the calibrated curves share: the shrink ratio lambda1 (length after heating / printed
// length, along the path) as a polynomial of one printing parameter x, strictly monotone on the
// range [min_x, max_x] it was calibrated on, so that a wanted lambda1 has exactly one x. The
// thickness curve (thickness_curve.h: x = layer height in mm, SCF 2020 §6) and the speed curve
// (speed_curve.h: x = print speed in mm/s, Thermorph Fig. 6) are this with their own fields, units
// and messages. Evaluation, the usability check, the inverse (bisection) and the least-squares fit
// live here once; a CurveParameter names x in the user's messages.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

// How messages name x: "layer height {x} mm is outside the calibrated range ... of the material's
// thickness curve: ... calibrate a wider range ('flatmorph calibrate print --thickness-ramp')".
struct CurveParameter {
  std::string_view quantity;       // "layer height", "print speed" (plural: + "s")
  std::string_view unit;           // "mm", "mm/s"
  std::string_view curve;          // "thickness curve", "speed curve"
  std::string_view ramp_command;   // "calibrate print --thickness-ramp"
  std::string_view values_option;  // "--layer-heights": the option listing the ramp's x values
};

// A view of a curve's data: lambda1(x) = sum_i coefficients[i] x^i on [min_x, max_x].
struct MonotoneCurve {
  std::span<const double> coefficients;
  double min_x = 0;
  double max_x = 0;
};

// Most coefficients a curve may have (degree 4, as SCF 2020 Fig. 2 fits).
constexpr int kMaxCurveCoefficients = 5;

// sum_i coefficients[i] x^i (Horner), anywhere: no range check.
double polynomial_value(std::span<const double> coefficients, double x);

// Empty when `curve` is usable (1 to kMaxCurveCoefficients finite coefficients, 0 < min_x < max_x
// finite, lambda1 in (0, 2] and strictly monotone on [min_x, max_x]); otherwise the first problem,
// as a sentence naming x as `parameter` says.
std::string monotone_curve_problem(const MonotoneCurve& curve, const CurveParameter& parameter);

// lambda1 at x. Throws UserError(kInfeasible) when x lies outside [min_x, max_x] (a slack of 1e-9
// for values read back from text).
double monotone_curve_value(const MonotoneCurve& curve, double x, const CurveParameter& parameter);

// The x in [min_x, max_x] at which the curve is `lambda1`, by bisection (deterministic, and the
// answer stays in the range). Throws UserError(kInfeasible) naming the reachable lambda1 range when
// `lambda1` is outside it. The curve must be usable (monotone_curve_problem empty).
double monotone_curve_inverse(const MonotoneCurve& curve, double lambda1,
                              const CurveParameter& parameter);

// The least-squares polynomial through the samples (x[i], lambda1[i]) of the highest degree <=
// min(max_degree, 4, distinct x values - 1) that is usable on [min x, max x]: its coefficients in
// powers of x (the fit itself is computed in the scaled variable (x - mid) / half-range, which
// keeps it well conditioned, then expanded). Throws UserError(kFormat) with fewer than two
// distinct x values or when no degree gives a usable curve; std::invalid_argument for x and
// lambda1 of different sizes.
std::vector<double> fit_monotone_curve(std::span<const double> x, std::span<const double> lambda1,
                                       int max_degree, const CurveParameter& parameter);

}  // namespace flatmorph
