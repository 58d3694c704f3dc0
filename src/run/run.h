// One run of a design method: "run method M on input I with options O", for the command line, a
// Python module and a local web server alike. The method designs the plate (what only it knows);
// the pipeline plans the print, writes and checks the G-code, closes the loop on it (the G-code
// read back and simulated by the shared simulator), and writes the run folder as one unit. The
// results come back as data too. No printing: progress goes to a callback, and a token cancels.
// docs/architecture.md, "The run pipeline". Millimetres and radians everywhere.
#pragma once

#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/cancel.h"
#include "common/progress.h"
#include "gcode/printer_profile.h"
#include "run/run_folder.h"
#include "run/run_input.h"

namespace flatmorph {

// Shrink & Morph (TOG 2023, docs/design.md): a disk-like target surface (OBJ, PLY, STL, OFF).
inline constexpr double kExamplePlateWidthMm = 100.0;  // a built-in example's plate, mm
struct ShrinkMorphRunOptions {
  // The plate's largest extent, mm; NaN: kExamplePlateWidthMm for an example (a file must give
  // it).
  double width_mm = std::numeric_limits<double>::quiet_NaN();
  double w_D = 0.0;   // Eq. 12 smoothing weight of the print directions
  double w_M = 0.01;  // Eq. 13 weight of the theta2 magnitude term
  double w_L = 0.01;  // Eq. 13 weight of the theta2 smoothness term
  // The paths' angle errors (rms, degrees) a design at a fold is designed again for; 0: none.
  double path_error_deg = 2.0;
  int faces = 10000;  // Loop-subdivide the target until it has at least this many faces
  int layers = 10;    // printed layers
  std::string material = "pla-paper";
  std::string printer = "generic-marlin";
  std::string side = "auto";     // auto, normal-up or normal-down
  std::string stretch = "auto";  // auto, all or an initial stretch 0 to 3
};

// Self-rising height fields (SCF 2020, docs/heightfield.md): a mesh z = h(x, y), a grayscale PNG
// (with size_wxd and height_mm) or an example.
inline constexpr double kExampleFieldHeightMm = 35.0;  // a built-in example's height, mm
struct HeightFieldRunOptions {
  double diameter_mm = 160.0;  // of an example
  // Of an example (NaN: kExampleFieldHeightMm), or of white in an image.
  double height_mm = std::numeric_limits<double>::quiet_NaN();
  std::string size_wxd;        // an image's extent, "WxD" in mm
  double resolution_mm = 1.0;  // an image's grid spacing
  std::string texture;         // a PNG the OBJ's texture coordinates point into
  double checkerboard_mm = 0;  // colour the surface with squares of this side (0: none)
  std::string material = "pla-geodesy";
  std::string printer = "generic-marlin";
  double level_spacing_mm = 0;      // 0: a twelfth of the height
  double upsample_length_mm = 2.0;  // the paper's l_u
  int layers = 0;                   // 0: the thickness curve's calibrated count
  double path_width_mm = 0;         // 0: the printer's nozzle
  bool optimize = true;             // refine the shrink against the simulated shape
  bool other_shapes = false;        // also simulate from the target and warn of another shape
  double dpi = 300;                 // texture.png's resolution
};

// Self-rising tiles (Geodesy, CHI 2019, docs/tiles.md): a layout (.json) or a drawing (.dxf,
// .svg) or an example. Empty or negative values leave each tile's own setting.
struct TilesRunOptions {
  std::string profile;      // every tile's profile, when given
  std::string profile_csv;  // every tile's profile from r,z rows, when given
  double height_mm = 0;     // every tile's height, when positive
  std::string side;         // "up" or "down" for every tile, when given
  double hole_mm = -1;      // every tile's hole radius, when 0 or more
  std::string material = "pla-geodesy";
  std::string lattice_material;  // empty: the tiles'
  std::string printer = "generic-marlin";
  double pitch_mm = 0;  // path width and ring spacing; 0: the printer's nozzle
  double thickness_mm = 0.6;
  double bilayer = 0;  // shrink difference between the halves (fraction); 0: per ring
  bool strict = false;
  double mesh_edge_mm = 0;  // 0: automatic
  bool optimize = true;
};

// Self-folding origami (Thermorph, CHI 2018, docs/origami.md): a mesh, a crease pattern (.svg)
// or an example solid.
struct OrigamiRunOptions {
  int faces = 70;      // at most this many planar faces
  double size_mm = 0;  // the solid's longest side; 0: as given
  std::string material = "pla-generic";
  std::string hinge_material = "tpu-generic";
  std::string printer = "prusa-xl-2t";
  double actuator_speed = 150;  // mm/s
  double actuator_width = 0;    // mm; 0: from the speed
  double flat_angle_deg = 1;    // folds of less than this print no actuator
  bool case_b_hinges = false;
  bool simulate = false;      // fold each sheet with the shared simulator
  double mesh_edge_mm = 1.5;  // --simulate's mesh
  int fit_hinges = 0;         // rounds of the widths' fit against the simulator
  bool slicer = true;         // ask PrusaSlicer (when installed) for the solid's print time
};

using MethodOptions =
    std::variant<ShrinkMorphRunOptions, HeightFieldRunOptions, TilesRunOptions, OrigamiRunOptions>;

// "shrink_morph", "heightfield", "tiles" or "origami": the method design.json names.
std::string_view method_name(const MethodOptions& options);

struct RunRequest {
  RunInput input;
  MethodOptions options;
  bool gcode = true;  // trace the paths and write the G-code
  // The run folder; empty: nothing is written (the results are only returned).
  std::filesystem::path output;
};

struct RunControl {
  ProgressCallback progress;  // stages and steps, on the calling thread; may be empty
  const CancelToken* cancel = nullptr;
};

struct RunResult {
  RunOutputs outputs;                 // what the run folder holds, as data
  nlohmann::ordered_json record;      // design.json
  PrinterProfile printer;             // the printer the G-code is for
  std::vector<std::string> warnings;  // shown as "warning: ..."
  std::vector<std::string> notes;     // shown as "note: ..."
  std::vector<std::string> summary;   // the human-readable summary, one line each
};

// Runs the method on the input. Throws UserError for bad options or input (before anything is
// written when it can tell), Cancelled when control.cancel is set (nothing is left behind), and
// the stages' errors. With request.output set, the run folder replaces that folder as one unit
// (write_run_folder).
RunResult run_design(const RunRequest& request, const RunControl& control = {});

}  // namespace flatmorph
