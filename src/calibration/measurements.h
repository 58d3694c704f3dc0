// The measurement sheet of a calibration print (calibration_csv_template), read back and checked
// cell by cell, and what each sample says about the material (Shrink & Morph §4.1, §4.2). Lengths
// in mm, curvatures in 1/mm.
//
// The sheet is CSV: '#' lines are comments, some of them "# key = value" lines the template wrote
// (kind, samples, material); the first other line names the columns; then one row per sample.
// Every problem is a UserError(kFormat) naming the file, the line and the column.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "material/material.h"

namespace flatmorph {

struct SampleMeasurement {
  int line = 0;  // 1-based line of the row in the file
  int sample = 0;
  int set = 0;
  double nozzle_temperature = 0;  // degrees C
  double layer_height = 0;        // mm
  int layers = 0;
  double print_speed = 0;  // mm/s of every layer but the first: a speed-ramp sheet's column; 0 else
  double length_before = 0, width_before = 0, thickness_before = 0;  // as printed
  double length_after = 0, width_after = 0, thickness_after = 0;     // after heating
  // Signed curvature of the shrunk sample, > 0 when its top face is on the inside of the curl
  // (given, or from rise and chord); unset when neither was measured.
  std::optional<double> curvature;
  bool skipped = false;  // "skip" in length_after: the sample is left out
};

struct MeasurementSheet {
  std::string source;                // the file, for messages
  bool thickness_ramp = false;       // "# kind = thickness-ramp"
  bool speed_ramp = false;           // "# kind = speed-ramp" (it has a print_speed column)
  int expected_samples = -1;         // "# samples = N" (-1: not stated)
  int expected_samples_line = 0;     // the line that states it
  std::optional<Material> material;  // "# material = {...}": what the samples were printed with
  std::vector<SampleMeasurement> rows;
};

// Parses a sheet; `source` names it in messages. Checks every cell (a missing value, a value that
// is not a number, a length that grew along the path, a ratio no material has, sets whose
// parameters differ between rows, a speed-ramp sheet without its print_speed column, a repeated
// sample id, a row count other than the template's).
MeasurementSheet parse_measurements(std::string_view text, const std::string& source);

// Reads and parses the sheet at `path` (UserError kFile when it cannot be read).
MeasurementSheet read_measurements(const std::filesystem::path& path);

// The curvature (1/mm) of the circular arc whose chord is `chord` long and whose middle lies
// `rise` above the chord (signed): 2 rise / (rise^2 + chord^2 / 4).
double curvature_from_rise(double rise, double chord);

// The length of that arc (mm).
double arc_length_from_rise(double rise, double chord);

// Shrink & Morph §4.2, Eq. 15-18: the bilayer gradient of lambda1 that makes a strip of printed
// thickness h (mm) with ratios lambda1, lambda3 curl at curvature kappa (1/mm, > 0 with the top on
// the inside): delta_lambda1 = -h lambda3 lambda1 kappa.
double delta_lambda1_from_curvature(double h, double lambda3, double lambda1, double kappa);

// What one sample measured (not skipped).
struct SampleRatios {
  int sample = 0;
  int set = 0;
  double lambda1 = 0, lambda2 = 0, lambda3 = 0;  // after / before
  double contraction_pct = 0;                    // 100 (1 - lambda1)
  std::optional<double> curvature;               // 1/mm
  std::optional<double> delta_lambda1;           // from the curvature
};

std::vector<SampleRatios> sample_ratios(const MeasurementSheet& sheet);

}  // namespace flatmorph
