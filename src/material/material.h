// Filament parameters: how printed layers shrink when heated, how stiff they are, and how to print
// them. Lengths in mm, temperatures in degrees Celsius, moduli in MPa (only their ratio matters for
// the predicted shape).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "material/hinge_curve.h"
#include "material/speed_curve.h"
#include "material/thickness_curve.h"

namespace flatmorph {

struct Material {
  std::string name;
  std::string description;
  // Shrink ratios after heating (Shrink & Morph §4.1): new length / printed length.
  double lambda1 = 0.58;  // along the deposition path
  double lambda2 = 1.08;  // across the path, in the plate's plane
  double lambda3 = 1.52;  // through the thickness
  // Bilayer gradient of lambda1 through the thickness (Shrink & Morph Eq. 15), with z measured from
  // the plate's mid-plane toward the top (away from the bed): lambda1(z) = lambda1 + (z/h) *
  // delta_lambda1. Negative when the top layers shrink more than those on the bed.
  double delta_lambda1 = -0.0226764665509417;
  // Orthotropic stiffness (Eq. 4): Young's moduli along and across the path, Poisson-like ratio.
  double young_modulus_along = 10.0;
  double young_modulus_across = 1.0;
  double poisson_ratio = 0.4;
  // How the material was printed when the ratios above were measured.
  double layer_height = 0.08;       // mm
  double nozzle_temperature = 190;  // degrees C
  double bed_temperature = 55;      // degrees C
  double max_nozzle_temperature = 230;
  double max_bed_temperature = 70;
  double density = 1.24;  // g/cm^3
  // Safe printing range: the G-code check refuses extrusion below the minimum and any target above
  // the maxima (degrees C).
  double min_nozzle_temperature = 180;
  // Speeds the ratios were measured at (mm/s): the shrink depends on them, so they are the G-code
  // writer's default for extruding moves (0 = use the printer's).
  double print_speed = 30;
  double first_layer_speed = 15;
  // Part-cooling fan, percent of full speed, from the second layer on and on the first layer.
  double fan_speed = 100;
  double first_layer_fan_speed = 0;
  // Optional: lambda1 as a function of the layer height, with its calibrated range (key
  // "thickness_curve"; `flatmorph calibrate fit` on a --thickness-ramp print writes it).
  std::optional<ThicknessCurve> thickness_curve;
  // Optional: lambda1 as a function of the print speed (key "speed_curve"; `flatmorph calibrate
  // fit` on a --speed-ramp print writes it). print_speed must lie in its calibrated range: the
  // ratios above were measured at print_speed, and printed_lambda1 scales them from there.
  std::optional<SpeedCurve> speed_curve;
  // Optional, for the PLA of Thermorph's actuators: how far an actuator bends per mm of its width
  // against the speed its active PLA is printed at (key "hinge_curve"; `flatmorph calibrate fit`
  // on a --hinge-sheet print writes it). Without it, designs use the uncalibrated default
  // (plate/actuator_stack.h).
  std::optional<HingeCurve> hinge_curve;
};

// lambda1 of a bead printed with `material` at layer height `layer_height_mm` and print speed
// `print_speed_mm_s` (mm/s; a G-code F is mm/min): the thickness curve at h when the material has
// one, else material.lambda1, times speed_curve(v) / speed_curve(material.print_speed) when it has
// a speed curve. The model is multiplicative: the speed ramp is printed at one layer height, so it
// gives only how much the speed changes lambda1 relative to the speed the other ratios were
// measured at, and that factor is assumed to hold at every layer height. h and v are clamped to
// the curves' calibrated ranges rather than refused: a first layer printed at 15 mm/s for
// adhesion, outside a curve calibrated from 20 mm/s, must not make a printed design unreadable,
// and the nearest calibrated value is the best estimate there is. A speed of 0 (not known: a
// G-code without F) counts as material.print_speed.
double printed_lambda1(const Material& material, double layer_height_mm, double print_speed_mm_s);

// The material's thickness curve, which the thickness-controlled methods (SCF 2020 height fields,
// Geodesy) need to turn each path's shrink into a layer height. Throws UserError (kOption) naming
// the material and how to get a curve when it has none.
const ThicknessCurve& require_thickness_curve(const Material& material);

// Names of the built-in materials, in a fixed order.
std::vector<std::string> material_preset_names();

// A built-in material by name (profiles/materials/NAME.json, e.g. "pla-paper": Polymaker PolyMax
// PLA as measured in Shrink & Morph §4), or the material JSON file at `name_or_path` (same format;
// keys left out keep the paper PLA's values). Throws UserError naming the file or listing the
// presets when it cannot, and naming the key for a wrong, unknown or out-of-range value.
Material load_material(const std::string& name_or_path);

// Parses the text of a material file; `source` names it in error messages (UserError kProfile).
Material parse_material_json(std::string_view text, const std::string& source);

// The material file of `material` (JSON, every key, the order of docs/gcode.md), which
// load_material reads back to the same values.
std::string material_json(const Material& material);

// material_json, written atomically to `path`.
void write_material(const std::filesystem::path& path, const Material& material);

}  // namespace flatmorph
