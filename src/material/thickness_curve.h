// How the shrink ratio along the path depends on the layer height, for the methods that vary the
// layer thickness to vary the shrinkage (SCF 2020 §6 and Fig. 2, Geodesy §3): a polynomial
// lambda1(h) of degree at most 4, monotone on the range of layer heights it was calibrated on, and
// its inverse (wanted shrinkage -> layer height). Outside that range neither is defined: both
// refuse with a UserError. Layer heights in mm; lambda1 = length after heating / printed length;
// shrinkage = 1 - lambda1 (0.42 for the paper's PLA).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "material/monotone_curve.h"

namespace flatmorph {

// How messages of the shared curve code (monotone_curve.h) name the layer height.
inline constexpr CurveParameter kThicknessCurveParameter = {
    "layer height", "mm", "thickness curve", "calibrate print --thickness-ramp", "--layer-heights"};

struct ThicknessCurve {
  // lambda1(h) = sum_i lambda1_coefficients[i] * h^i, h in mm (1 to 5 coefficients).
  std::vector<double> lambda1_coefficients;
  double min_layer_height = 0;    // mm, the calibrated range
  double max_layer_height = 0;    // mm
  int layers = 6;                 // layers of the calibration samples (SCF 2020 prints 6)
  double nozzle_temperature = 0;  // degrees C the samples were printed at (0: not recorded)
};

// Empty when `curve` is usable (1 to 5 finite coefficients, 0 < min < max, lambda1 in (0, 2] and
// strictly monotone on [min, max]); otherwise the first problem, as a sentence.
std::string thickness_curve_problem(const ThicknessCurve& curve);

// lambda1 at layer height `h` (mm). Throws UserError(kInfeasible) when h lies outside the
// calibrated range.
double lambda1_at_layer_height(const ThicknessCurve& curve, double h);

// The layer height (mm) at which the material shrinks to `lambda1` along the path: the inverse of
// lambda1_at_layer_height, by bisection on the calibrated range (the curve is monotone there).
// Throws UserError(kInfeasible) naming the reachable range when `lambda1` is outside it.
double layer_height_for_lambda1(const ThicknessCurve& curve, double lambda1);

// The same for a wanted shrinkage s = 1 - lambda1 (a fraction: 0.3 for 30 %).
double layer_height_for_shrinkage(const ThicknessCurve& curve, double shrinkage);

// The least and the greatest shrinkage (fractions) the curve gives on its calibrated range: those
// at its two ends, the curve being monotone (the thickest layer shrinks least). The range a design
// method may ask of the material (SCF 2020 §8 "Flattening quality": edges outside it are invalid).
std::pair<double, double> reachable_shrinkage(const ThicknessCurve& curve);

// A wanted shrinkage σ (a fraction) as a thickness-controlled print makes it: σ clamped to the
// reachable range and flagged when outside it, never refused (a design method reports such paths
// as invalid, SCF 2020 §8, Table 1 "Inv.", and prints the nearest shrink), and the layer height
// that shrinks by the clamped σ. The one σ → layer height conversion, shared by the layer stack
// the simulation reads (thickness_controlled_layer_stack) and the paths the printer prints
// (continuous_paths), so that both describe one plate. A NaN σ throws UserError(kInfeasible);
// callers refuse a σ that is not finite first, naming where it comes from.
struct PrintedShrinkage {
  double shrinkage = 0;     // σ printed: the wanted one, within the reachable range
  double layer_height = 0;  // mm, within the calibrated range
  // 0 where σ was reachable, -1 where it was below the least shrink the curve gives (raised to
  // it; σ < 0 asks the path to grow), +1 where above the greatest (lowered to it).
  int clamped = 0;
};
PrintedShrinkage printed_shrinkage(const ThicknessCurve& curve, double shrinkage);

}  // namespace flatmorph
