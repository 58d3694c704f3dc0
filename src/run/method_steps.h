// The three steps of each method (method_run.h), overloaded on its options type so that run.cpp
// chains them once for every method. Internal to src/run/; each method's steps live in its own
// file (shrink_morph_run.cpp, heightfield_run.cpp, tiles_run.cpp, origami_run.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/heightfield/design_height_field.h"
#include "methods/origami/design_origami.h"
#include "methods/origami/sheet_simulation.h"
#include "methods/shrink_morph/design.h"
#include "methods/tiles/design_tiles.h"
#include "run/method_run.h"
#include "run/run.h"

namespace flatmorph {

// --- Shrink & Morph ---

struct ShrinkMorphSetup {
  RunInput input;
  ShrinkMorphRunOptions options;  // checked; width_mm set
  bool gcode = true;
  PrintedSide side = PrintedSide::kAutomatic;
  int stretch = kAutomaticStretch;
  Material material;
  PrinterProfile printer;
};

struct ShrinkMorphState {
  Design design;
  MethodDesign run;
};

ShrinkMorphSetup prepare_run(const RunRequest& request, const ShrinkMorphRunOptions& options);
ShrinkMorphState design_run(const ShrinkMorphSetup& setup, const ProgressCallback& progress);
MethodReport report_run(const ShrinkMorphSetup& setup, const ShrinkMorphState& state,
                        const PrintOutcome& print, const ProgressCallback& progress);

// --- Height fields ---

struct HeightFieldSetup {
  RunInput input;
  HeightFieldRunOptions options;
  bool gcode = true;
  Material material;
  PrinterProfile printer;
};

struct HeightFieldState {
  HeightField field;
  HeightFieldDesignOptions design_options;
  HeightFieldDesign design;
  double load_seconds = 0;
  MethodDesign run;
};

HeightFieldSetup prepare_run(const RunRequest& request, const HeightFieldRunOptions& options);
HeightFieldState design_run(const HeightFieldSetup& setup, const ProgressCallback& progress);
MethodReport report_run(const HeightFieldSetup& setup, const HeightFieldState& state,
                        const PrintOutcome& print, const ProgressCallback& progress);

// --- Tiles ---

struct TilesSetup {
  RunInput input;
  TilesRunOptions options;
  bool gcode = true;
  Material material, lattice_material;
  PrinterProfile printer;
};

struct TilesState {
  TileLayout layout;
  TilesDesignOptions design_options;
  TilesDesign design;
  MethodDesign run;
};

TilesSetup prepare_run(const RunRequest& request, const TilesRunOptions& options);
TilesState design_run(const TilesSetup& setup, const ProgressCallback& progress);
MethodReport report_run(const TilesSetup& setup, const TilesState& state, const PrintOutcome& print,
                        const ProgressCallback& progress);

// --- Origami ---

struct OrigamiSetup {
  RunInput input;
  OrigamiRunOptions options;
  bool gcode = true;
  OrigamiOptions design_options;  // materials, actuators, the bed's room
  PrinterProfile printer;
};

struct OrigamiState {
  OrigamiDesign design;
  OrigamiPlate plate;
  std::vector<std::string> notes;
  std::optional<HingeFit> hinge_fit;
  double fit_seconds = 0;
  MethodDesign run;
};

OrigamiSetup prepare_run(const RunRequest& request, const OrigamiRunOptions& options);
OrigamiState design_run(const OrigamiSetup& setup, const ProgressCallback& progress);
MethodReport report_run(const OrigamiSetup& setup, const OrigamiState& state,
                        const PrintOutcome& print, const ProgressCallback& progress);

}  // namespace flatmorph
