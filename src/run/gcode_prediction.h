// The shape a G-code file makes in hot water: what it deposits (gcode/gcode_reader.h), rasterized
// onto a plate mesh (gcode/deposited_plate.h), laminated and simulated like any other plate. One
// simulator for every method and for any slicer's file. Lengths in mm.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gcode/deposited_plate.h"
#include "gcode/gcode_reader.h"
#include "material/material.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph {

struct GcodePredictionOptions {
  GcodeReadOptions read;
  DepositedPlateOptions deposit;
  // The plate mesh the file was printed from (flat.ply: #V x 2 or 3 in plate coordinates, mm, and
  // its faces); empty: the first layer's footprint, meshed at deposit.resolution_mm.
  Eigen::MatrixXd plate_V;
  Eigen::MatrixXi plate_F;
  // Where the simulation starts, per vertex of plate_V (e.g. the design's target); empty: flat
  // (flat_start, the honest forward prediction).
  Eigen::MatrixXd start;
  SimulationOptions simulation;
};

struct GcodePrediction {
  DepositedPlate plate;  // in plate coordinates (bed coordinates when there was no plate mesh)
  // bed = plate + plate_to_bed (mm): from the file's header when it says, else the shift that
  // centres the plate mesh's bounding box on the first layer's beads; 0 for a footprint.
  Eigen::Vector2d plate_to_bed{0, 0};
  bool placed_by_header = false;
  // The part's frame the footprint was meshed in (gcode/deposited_plate.h); the bed's frame when
  // a plate mesh was given.
  PartFrame footprint_frame;
  SimulationResult result;  // on the kept vertices (plate.kept_vertices of plate_V)
  int num_beads = 0;
  double read_seconds = 0, rasterize_seconds = 0;
};

// Reads `text` (a G-code file; `source` names it in errors) printed with tool_materials[t] on tool
// t, and predicts the shape. Throws the reader's and the rasterizer's UserErrors.
GcodePrediction predict_from_gcode(std::string_view text, const std::string& source,
                                   const std::vector<Material>& tool_materials,
                                   const GcodePredictionOptions& options = {});

// A design's loop closed: its own G-code read back and simulated on its plate (from `start`, the
// start its fields' prediction had), and compared with the target and with that prediction, each
// after the rigid motion that best fits them (the two are registered differently when the G-code
// leaves faces of the plate out). Distances over the vertices the G-code prints, in % of the
// target's diagonal. `deposit`: how beads become faces' layers (a sparse lattice covers less of
// a face than the default least coverage).
struct ClosedLoop {
  GcodePrediction prediction;
  Eigen::MatrixXd on_target;    // its shape, rigidly fitted to the target (kept vertices)
  ShapeDistance to_target;      // the G-code's predicted shape against the target
  ShapeDistance to_prediction;  // ... against the prediction from the design's fields
};
ClosedLoop close_the_loop(std::string_view gcode, const std::string& source,
                          const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                          const std::vector<Material>& tool_materials, const Eigen::MatrixXd& start,
                          const Eigen::MatrixXd& target, const Eigen::MatrixXd& fields_prediction,
                          const DepositedPlateOptions& deposit = {});

}  // namespace flatmorph
