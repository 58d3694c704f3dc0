// The hinge calibration of Thermorph (CHI 2018, Fig. 6-7; notes §5 "Calibration print"): a sheet
// of strips, each two PLA faces joined by an actuator, at several active-PLA speeds and actuator
// widths, in case A (PLA on the bed, TPU on top) and case B (TPU on the bed). The user heats the
// sheet, measures each strip's fold angle (180° minus the included angle between the faces, as the
// paper defines it), and `calibrate fit` turns the angles into the material's hinge curve κ(v) =
// θ / W per case (material/hinge_curve.h). The sheet is data: strip rectangles, codes and
// toolpaths (PLA on tool 0, TPU on tool 1) that the ordinary G-code writer prints on a printer with
// two tools, or with one nozzle that pauses for a filament swap. Lengths in mm, speeds in mm/s,
// angles in radians inside (degrees in the sheet).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gcode/printer_profile.h"
#include "material/hinge_curve.h"
#include "material/material.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct HingeSheetOptions {
  // The active PLA's speeds (mm/s): the paper's 3000 to 9000 mm/min.
  std::vector<double> speeds = {50, 75, 100, 125, 150};
  std::vector<double> widths = {5, 10, 15, 20};  // actuator widths W across the hinge, mm
  bool case_a = true;                            // print case A strips
  bool case_b = true;                            // print case B strips
  double face_length = 20;                       // mm, each face, across the hinge
  double hinge_length = 10;                      // mm, along the hinge: the strip's width
  HingeStack stack;
  double spacing = 0;      // mm between lines; 0: the printer's nozzle diameter
  double gap = 5;          // mm between strips
  double margin = 10;      // mm kept free along the bed's edge
  double notch_depth = 3;  // mm, depth of the code notches
};

// One strip, in plate coordinates (the plate's centre is the bed's unless placed elsewhere): x
// across the hinge, y along it.
struct HingeStrip {
  int id = 0;    // 1, 2, ...: its row in the measurement sheet
  int code = 0;  // notched into the far end of its +x face: the (case, speed) group, 1, 2, ...
  bool pla_on_bed = true;
  double speed = 0;              // mm/s, the active PLA
  double width = 0;              // W, mm
  Eigen::AlignedBox2d outline;   // both faces and the actuator (before the notches)
  Eigen::AlignedBox2d actuator;  // the W wide band that folds
  Eigen::AlignedBox2d bonded;    // the actuator and `overlap` into each face: active PLA, TPU
};

struct HingeSheetPlan {
  HingeSheetOptions options;
  double extrusion_width = 0;  // mm, the line spacing
  int code_bits = 0;           // notch slots across the far end
  std::vector<HingeStrip> strips;
  // Layer k (0 on the bed) of stack.pla_layers + stack.tpu_layers: the faces in PLA (tool 0, the
  // material's speed, lines along x on even k and along y on odd k so that they stay flat), the
  // bonded band in active PLA along x at the strip's speed (tool 0) or in TPU along y at
  // stack.tpu_speed (tool 1) as the strip's case says. Within a layer all of one tool, then the
  // other, starting with the tool the layer below ended with (T0 before the first).
  Toolpath toolpath;
};

// The strips, their layout (rows from the far side of the bed, strips ordered by case, speed,
// width) and their toolpaths for `printer`. Throws UserError(kOption) for options out of range
// (speeds above the printer's travel speed or given in mm/min, widths, no case, an unusable stack,
// too many groups for the notch code), UserError(kInfeasible) for a printer with one tool or a
// sheet that does not fit its bed (naming the size it needs).
HingeSheetPlan plan_hinge_sheet(const PrinterProfile& printer, const HingeSheetOptions& options);

// How to read the notch codes and which (case, speed) each code is, in sentences (written into
// the CSV template and the SVG).
std::vector<std::string> hinge_sheet_legend(const HingeSheetPlan& plan);

// The measurement sheet to fill in (CSV: one row per strip, its case, speed and width filled in,
// the fold angle to measure). `pla` is recorded in it for `calibrate fit`.
std::string hinge_sheet_csv_template(const HingeSheetPlan& plan, const Material& pla,
                                     const PrinterProfile& printer);

// The layout (SVG, 1 mm = 1 mm): the bed with every strip (faces, actuator coloured by case,
// notches, its id, case, speed and width) at plate + `plate_to_bed`, and the legend.
std::string hinge_sheet_layout_svg(const HingeSheetPlan& plan, const PrinterProfile& printer,
                                   const Eigen::Vector2d& plate_to_bed,
                                   const std::string& gcode_name);

// One row of a filled-in sheet.
struct HingeStripMeasurement {
  int line = 0;  // 1-based line in the file
  int strip = 0;
  bool pla_on_bed = true;
  double speed = 0;       // mm/s
  double width = 0;       // mm
  double fold_angle = 0;  // rad: 180° minus the included angle; < 0 when it folded the other way
  bool skipped = false;   // "skip" in fold_angle
};

struct HingeSheet {
  std::string source;  // the file, for messages
  int expected_strips = -1;
  int expected_strips_line = 0;
  HingeStack stack;                  // "# hinge_stack = {...}"
  std::optional<Material> material;  // "# material = {...}": the PLA the strips were printed with
  std::vector<HingeStripMeasurement> rows;
};

// Whether `text` is a hinge sheet (its "# kind = hinge-sheet" line), and the same for a file
// (false when it cannot be read: the ordinary reader then says why).
bool is_hinge_sheet(std::string_view text);
bool is_hinge_sheet_file(const std::filesystem::path& path);

// Parses a filled-in sheet; `source` names it in messages. Every problem is a UserError(kFormat)
// naming the file, the line and the column: a missing or non-numeric value, a case other than A
// or B, a speed in mm/min, an angle outside [-180, 180] degrees, a repeated strip, a row count
// other than the template's.
HingeSheet parse_hinge_measurements(std::string_view text, const std::string& source);
HingeSheet read_hinge_measurements(const std::filesystem::path& path);

// What the fit says about one measured strip (radians).
struct HingeStripFit {
  int strip = 0;
  bool pla_on_bed = true;
  double speed = 0, width = 0;
  double fold_angle = 0;  // measured
  double predicted = 0;   // κ(v) W of the fitted curve
};

struct HingeCurveFit {
  HingeCurve curve;  // calibrated, on the speeds both cases were measured at
  std::vector<HingeStripFit> strips;
  double rms_residual_a = 0, rms_residual_b = 0;  // rad, of fold_angle − predicted
  double max_residual_a = 0, max_residual_b = 0;  // rad, largest |fold_angle − predicted|
};

// κ(v) = θ / W per case (Step 3's uniform model: the angle grows in proportion to W, Fig. 7): for
// each case the least-squares polynomial of degree at most `max_degree` (a line or a quadratic,
// the highest the distinct speeds support) through the strips' θ / W that is positive and
// strictly monotone (monotone_curve.h), on the range of speeds both cases were measured at; with
// every strip's residual. Throws UserError(kFormat) naming the sheet and the case when a case has
// fewer than two measured speeds, the two cases share no range, or no such curve fits.
HingeCurveFit fit_hinge_curve(const HingeSheet& sheet, int max_degree = 2);

}  // namespace flatmorph
