// Thermorph's actuator as printed layers (CHI 2018, "Material mechanism" and Fig. 5; notes §5, §8),
// and the hinge curve it gives before any calibration: the stack goes through the same laminate
// the simulator uses (laminate.h), so the default curve a design folds its hinges with and the
// layer-stack simulation of a hinge cannot disagree. Lengths in mm, speeds in mm/s, angles in rad.
//
// The actuator: `pla_layers` active PLA layers (tool 0) with their lines across the hinge, each
// shrinking along its lines by the λ1 its print speed gives, and `tpu_layers` TPU layers (tool 1)
// that do not shrink (HingeStack). Case A prints the PLA on the bed and the TPU on top; case B the
// TPU first. Within the PLA, λ1 grows linearly from the bed side up, by the size of the PLA
// material's Δλ1 (Thermorph, Fig. 5 text: each PLA layer keeps more stress at its bottom, and the
// layer on the cool bed more than the others), so a case A actuator folds more than a case B one.
#pragma once

#include <utility>

#include "material/hinge_curve.h"
#include "material/material.h"
#include "plate/layer_stack.h"

namespace flatmorph {

// The speeds (mm/s) the default shrink covers when the PLA has no speed curve: the paper's 3000
// to 9000 mm/min (Table 1; notes §5).
inline constexpr double kDefaultActiveMinSpeed = 50;
inline constexpr double kDefaultActiveMaxSpeed = 150;

// The speeds (mm/s) active_lambda1 knows for `pla`: its speed curve's calibrated range, else
// [kDefaultActiveMinSpeed, kDefaultActiveMaxSpeed].
std::pair<double, double> active_speed_range(const Material& pla);

// λ1 (length after heating / printed length, along the lines) of the active PLA printed at `speed`
// (mm/s) in layers of stack.layer_height: printed_lambda1 (material.h) when `pla` has a speed
// curve; else 1 − ε(v) with ε rising linearly from 0.118 at 50 mm/s (Geodesy Fig. 2a's 11.8 % for
// 0.2 mm layers at 3000 mm/min, the same lab's PLA) to 0.25 at 150 mm/s (notes §5, a stated
// guess). Throws UserError(kInfeasible) outside active_speed_range.
double active_lambda1(const Material& pla, const HingeStack& stack, double speed);

// `pla` as the origami print reads it back from its G-code (gcode/deposited_plate.h): λ2 = λ3 = 1
// and the gradient rising from the bed side up (|Δλ1|), as actuator_layer_stack lays them; no
// thickness curve (the hinges print in layers of stack.layer_height: its λ1 there is kept); and
// without a speed curve, active_lambda1's default as one, linear over [kDefaultActiveMinSpeed,
// kDefaultActiveMaxSpeed]. So printed_lambda1 of the result at any speed in active_speed_range is
// active_lambda1 of `pla`, and a G-code judged with it meets the design's own stack.
Material thermorph_pla(const Material& pla, const HingeStack& stack);

// The layers of `num_faces` faces that are all actuator: materials {pla, tpu} (tools 0 and 1),
// the PLA layers along `line_direction` (rad: across the hinge) with mean λ1 `lambda1`, the
// gradient above, and λ2 = λ3 = 1 (Thermorph measures only the shrink along the lines; the
// bilayer of notes §5 keeps its thicknesses), the TPU layers along the hinge with the TPU's own
// ratios. Throws UserError(kOption) for an unusable stack (hinge_stack_problem),
// std::invalid_argument for num_faces < 1 or lambda1 outside (0, 2].
LayerStack actuator_layer_stack(const Material& pla, const Material& tpu, const HingeStack& stack,
                                double lambda1, bool pla_on_bed, double line_direction,
                                int num_faces);

// The fold angle per mm of printed actuator width (1/mm) of that stack held straight along the
// hinge: the laminate's rest forms are doubly curved (the TPU's Poisson expansion and the PLA's
// orthotropic coupling curl the strip along the hinge too, as much as across it), but the faces
// on both sides keep the hinge straight, so the actuator takes the state of least laminate energy
// with no curvature along the hinge (cylindrical bending), b_xx/√a_xx across it (its curvature
// b/a times the arc length per printed mm √a). Signed as b̄ (docs/conventions.md): < 0 when the
// actuator folds toward the bed (case A), > 0 away from it (case B).
double actuator_curvature(const Material& pla, const Material& tpu, const HingeStack& stack,
                          double lambda1, bool pla_on_bed);

// The physically based hinge curve (not calibrated) of actuators printed as `stack` with `pla` and
// `tpu`, on active_speed_range(pla): per case, |actuator_curvature| at active_lambda1(v), as the
// least-squares polynomial of degree 4 through 17 speeds spread over the range (within 1e-4 of
// the laminate everywhere on it: tests/plate/actuator_stack_test.cpp). Throws UserError(kProfile)
// when a case would fold the wrong way (a PLA gradient stronger than the TPU's constraint), naming
// the materials; UserError(kOption) for an unusable stack.
HingeCurve default_hinge_curve(const Material& pla, const Material& tpu, const HingeStack& stack);

}  // namespace flatmorph
