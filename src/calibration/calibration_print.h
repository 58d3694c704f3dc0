// The calibration print of Shrink & Morph §4.1: cuboid samples (80 x 20 x 0.8 mm by default) filled
// with parallel paths along their long side (x), one set of samples per combination of nozzle
// temperature and layer height, each set printed from the bed up with its own temperature (a
// PrintSection of the G-code writer). With `thickness_ramp`, the layer-thickness calibration of
// SCF 2020 §6 / Geodesy §3 instead: samples of a fixed number of layers (6) over a range of layer
// heights. With `speed_ramp`, the print-speed calibration of Thermorph (Fig. 6) instead: samples at
// one layer height, one set per print speed, every layer but the first at that speed (the first
// keeps the material's first-layer speed, so that it sticks). Every sample carries its id as a
// notch code on its +x end (calibration_notch_legend()), so it can be told apart after shrinking.
// Sets are laid out in disjoint rectangles on the bed, onto several plates (G-code files) when they
// do not fit on one. Lengths in mm, temperatures in degrees C, speeds in mm/s; plate coordinates
// are centred on the plate's middle, x along the samples' length.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct CalibrationPrintOptions {
  std::vector<double> nozzle_temperatures = {190, 200, 210};  // degrees C
  std::vector<double> layer_heights = {0.08, 0.12, 0.16};     // mm
  int repeats = 4;              // samples per set (the paper prints 4)
  double length = 80;           // mm, along the paths
  double width = 20;            // mm
  double thickness = 0.8;       // mm; a set prints round(thickness / layer height) layers
  bool thickness_ramp = false;  // print `ramp_layers` layers at every layer height instead
  int ramp_layers = 6;          // SCF 2020 §6
  // One set per speed (mm/s) at the one nozzle temperature and layer height given instead
  // (Thermorph varies 1500-9000 mm/min = 25-150 mm/s); at most the printer's travel speed.
  bool speed_ramp = false;
  std::vector<double> print_speeds = {20, 40, 60, 90, 120, 150};
  double spacing = 0;      // distance between paths (mm); 0: the printer's nozzle diameter
  double gap = 5;          // mm between the samples of a set
  double set_gap = 10;     // mm between sets
  double margin = 10;      // mm kept free along the bed's edge
  double notch_depth = 4;  // mm, depth of the code notches
};

struct CalibrationSet {
  int id = 0;  // 1, 2, ...
  double nozzle_temperature = 0;
  double layer_height = 0;
  int layers = 0;
  double print_speed = 0;  // mm/s of every layer but the first (speed ramp); 0: the material's
  double thickness() const { return layers * layer_height; }
  std::string label() const;  // "set 2: 200 C, 0.08 mm x 10 layers[, 60 mm/s]"
};

struct CalibrationSample {
  int id = 0;                    // 1, 2, ...: the notch code
  int set = 0;                   // CalibrationSet::id
  int repeat = 0;                // 1 .. repeats
  int plate = 0;                 // 1, 2, ...: the G-code file it is printed in
  Eigen::Vector2d center{0, 0};  // plate coordinates (mm)
};

// One bed load: one G-code file.
struct CalibrationPlate {
  Toolpath toolpath;  // sections one after the other (GcodeOptions::sections)
  std::vector<PrintSection> sections;
  std::vector<int> sets;  // CalibrationSet ids, in print order
};

struct CalibrationPlan {
  CalibrationPrintOptions options;
  double extrusion_width = 0;  // mm, = the path spacing (width / number of paths)
  int paths_per_layer = 0;     // per sample
  int code_bits = 0;           // notch slots on the coded end
  std::vector<CalibrationSet> sets;
  std::vector<CalibrationSample> samples;  // by id
  std::vector<CalibrationPlate> plates;
};

// The samples, their layout and their toolpaths for `printer`. Throws UserError(kOption) for
// options out of range (temperatures outside the material's safe range, layer heights above 80 %
// of the nozzle, print speeds above the printer's travel speed, both ramps at once, too many
// samples for the notch code) and UserError(kInfeasible) when one set does
// not fit the bed.
CalibrationPlan plan_calibration(const PrinterProfile& printer, const Material& material,
                                 const CalibrationPrintOptions& options);

// The notch pattern of sample `id` with `bits` slots: slot j (0-based, from the sample's -y side)
// is notched when bit j of id is set.
std::vector<bool> notch_code(int id, int bits);

// The fewest notch slots (bits) that give `count` codes 1 .. 2^bits − 2: none without a notch (a
// broken end) and none with every slot notched (an end with no full-length edge to measure).
int notch_code_bits(int count);

// A notch slot must be at least this wide (mm) to be seen after shrinking.
inline constexpr double kMinNotchSlotWidth = 2.0;

// A polyline of one straight extruded segment from a to b at height z (plate coordinates, mm).
PathPolyline straight_path(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z,
                           const SegmentStyle& style);

// How to read the notch code, in sentences (written into the CSV template and the SVG).
std::vector<std::string> calibration_notch_legend(const CalibrationPlan& plan);

// The material a plate is printed with: `material` with the nozzle temperature of its first set
// (the start G-code heats to it).
Material plate_material(const CalibrationPlan& plan, size_t plate, const Material& material);

// The measurement sheet to fill in (CSV, one row per sample; measurements.h reads it back).
std::string calibration_csv_template(const CalibrationPlan& plan, const Material& material,
                                     const PrinterProfile& printer);

// The layout (SVG, 1 mm = 1 mm): one panel per plate in bed coordinates (`plate_to_bed` per plate,
// GcodeResult::plate_to_bed), every sample with its notches and id, the sets and the code legend.
std::string calibration_layout_svg(const CalibrationPlan& plan, const PrinterProfile& printer,
                                   const std::vector<Eigen::Vector2d>& plate_to_bed,
                                   const std::vector<std::string>& gcode_names);

}  // namespace flatmorph
