// How far a Thermorph actuator bends (CHI 2018, Step 3 and Fig. 5-7; notes §5): under the paper's
// "uniform shrinking material model" a strip printed with its active PLA at speed v bends to a
// constant curvature κ(v), so a strip W wide folds its two faces by θ = κ(v) W and r = 1/κ is the
// radius of Algorithm 1 (W = r|θ|). κ here is the fold angle per mm of PRINTED actuator width
// (what the calibration measures: θ / W), in 1/mm, positive; the stacking case gives the side:
// case A (PLA on the bed, TPU on top) folds the faces toward the bed, case B (TPU on the bed)
// away from it (Fig. 5). Speeds in mm/s (the paper's mm/min / 60), lengths in mm, angles in rad.
//
// A curve is either calibrated (`flatmorph calibrate print --hinge-sheet`, then `calibrate fit`,
// written into the material file under "hinge_curve") or the physically based default
// (plate/actuator_stack.h: default_hinge_curve, from the same laminate the simulator uses).
#pragma once

#include <string>
#include <vector>

#include "material/monotone_curve.h"

namespace flatmorph {

// How the shared curve code (monotone_curve.h: the least-squares fit) names the speed of a hinge
// curve.
inline constexpr CurveParameter kHingeCurveParameter = {
    "print speed", "mm/s", "hinge curve", "calibrate print --hinge-sheet", "--hinge-speeds"};

// What one actuator prints (notes §2, §8): `pla_layers` active PLA layers with their lines across
// the hinge and `tpu_layers` TPU constraint layers, all `layer_height` thick; the active lines
// run `overlap` mm into both faces to bond them [paper, Step 4]; the TPU is printed at
// `tpu_speed`. The toolpath writer, the calibration sheet and the default curve read this one
// struct, so that they describe the same actuator.
struct HingeStack {
  double layer_height = 0.2;  // mm [paper: Fabrication]
  int pla_layers = 3;
  int tpu_layers = 1;
  double tpu_speed = 25;  // mm/s (1500 mm/min, Fig. 6-7 captions)
  double overlap = 1.0;   // mm

  double pla_thickness() const { return pla_layers * layer_height; }  // mm, as printed
  double tpu_thickness() const { return tpu_layers * layer_height; }  // mm
};

// Empty when `stack` is usable (layer height in (0, 1] mm, 1 to 20 layers of each, TPU speed in
// (0, 1000] mm/s, overlap in [0, 10] mm); otherwise the first problem, as a sentence.
std::string hinge_stack_problem(const HingeStack& stack);

struct HingeCurve {
  // κ(v) = Σ_i c_i v^i in 1/mm, v the active PLA's print speed in mm/s (1 to 5 coefficients),
  // strictly monotone and positive on [min_speed, max_speed].
  std::vector<double> case_a_coefficients;  // PLA on the bed
  std::vector<double> case_b_coefficients;  // TPU on the bed
  double min_speed = 0;                     // mm/s
  double max_speed = 0;                     // mm/s
  // Measured on printed strips (calibrate fit), or the default model's (outputs made with it say
  // "uncalibrated default").
  bool calibrated = false;
  // How the strips were printed (or, for the default, the actuator the model describes): the
  // curve holds for actuators printed the same way.
  HingeStack stack;
  double nozzle_temperature = 0;  // degrees C of the PLA; 0: not recorded
};

// Empty when `curve` is usable (each case 1 to 5 finite coefficients, 0 < min_speed < max_speed
// <= 1000 mm/s, κ in (0, 2] /mm and strictly monotone on the range, a usable stack, a temperature
// of 0 to 350 C); otherwise the first problem, as a sentence naming the case.
std::string hinge_curve_problem(const HingeCurve& curve);

// κ (1/mm, > 0) of an actuator whose active PLA is printed at `speed` (mm/s), case A when
// `pla_on_bed`, else case B. Throws UserError(kInfeasible) when the speed lies outside
// [min_speed, max_speed], naming the range.
double hinge_curvature(const HingeCurve& curve, double speed, bool pla_on_bed);

// The speed (mm/s) at which the actuator bends to `curvature` (1/mm): the inverse of
// hinge_curvature, by bisection on the range (Thermorph's "adjust the actuator length while
// keeping the angle", Fig. 11c: W fixed, v solved from κ(v) = |θ| / W). Throws
// UserError(kInfeasible) naming the reachable curvatures (and radii) when `curvature` is outside
// them. The curve must be usable (hinge_curve_problem empty).
double hinge_speed_for_curvature(const HingeCurve& curve, double curvature, bool pla_on_bed);

// "case A (PLA on the bed)" / "case B (TPU on the bed)", for messages.
std::string hinge_case_name(bool pla_on_bed);

}  // namespace flatmorph
