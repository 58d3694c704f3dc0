// The whole self-rising height-field method (SCF 2020) on one height field: the printing graph
// (isoline_mesh.h), the flat sheet and its shrink per printing edge (sheet_flattening.h), the
// printed layer stack and the shape it rises to (rise_prediction.h), the shrink refined against
// that shape (optimize_shrinkage.h), and the continuous paths that print it
// (continuous_paths.h). docs/heightfield.md describes each stage. Millimetres and radians.
#pragma once

#include <Eigen/Core>
#include <string>

#include "common/progress.h"
#include "material/material.h"
#include "methods/heightfield/continuous_paths.h"
#include "methods/heightfield/height_field.h"
#include "methods/heightfield/isoline_mesh.h"
#include "methods/heightfield/optimize_shrinkage.h"
#include "methods/heightfield/rise_prediction.h"
#include "methods/heightfield/sheet_flattening.h"

namespace flatmorph {

struct HeightFieldDesignOptions {
  Material material;  // with a thickness curve (the preset pla-geodesy, or a calibration's)
  // Identical layers printed (SCF 2020 §6.4), in the stack that is simulated (the prediction, the
  // optimization, flat.stack.json) and in the paths alike; 0: as many as the thickness curve was
  // calibrated with (6 for pla-geodesy). path_options.num_layers is set from it, whatever it says.
  int num_layers = 0;
  IsolineMeshOptions meshing;
  // The printable range and the growth across the paths are set from the material (its thickness
  // curve's reachable shrink, its λ2), whatever these say.
  SheetFlatteningOptions flattening;
  // Refine the flattening's shrink against the simulated shape (beyond the paper).
  bool optimize = true;
  OptimizeShrinkageOptions optimization;
  RisePredictionOptions prediction;
  // Trace the continuous paths (the print); off for a design without G-code.
  bool paths = true;
  ContinuousPathOptions path_options;
  ProgressCallback progress;
};

struct HeightFieldDesignTimes {  // wall clock, seconds
  double meshing = 0;
  double flattening = 0;
  double prediction = 0;  // the flattening's shrink simulated
  double optimization = 0;
  double final_prediction = 0;  // the printed shrink simulated from the flat sheet
  double paths = 0;
  double total = 0;
};

struct HeightFieldDesign {
  IsolineMesh mesh;  // the printing graph; its V is the target
  FlatSheet sheet;   // the flat sheet and the flattening's σ per edge
  // The flattening's σ per vertex (clamped to the material's range) and, what is printed, the
  // optimized one (the same without optimization).
  Eigen::VectorXd flattened_vertex_shrinkage;
  Eigen::VectorXd vertex_shrinkage;
  HeightFieldPlate flattened_plate;  // printed with the flattening's σ
  HeightFieldPlate plate;            // printed with vertex_shrinkage: the design
  RisePrediction flattened_prediction;
  RisePrediction prediction;  // of `plate`, from the flat sheet: the design's predicted shape
  bool optimized = false;
  ShrinkageResult optimization;  // when optimized
  ContinuousPaths paths;         // when options.paths
  HeightFieldDesignTimes times;
};

// Designs the sheet for `field` (checked by check_height_field; `source` names it in messages).
// Throws the stages' UserErrors: a boundary that is not level, a material without a thickness
// curve, out-of-range options.
HeightFieldDesign design_height_field(const HeightField& field, const std::string& source,
                                      const HeightFieldDesignOptions& options);

}  // namespace flatmorph
