// Toolpath + printer + one material per tool -> G-code a real printer accepts. The writer never
// decides geometry: it places the plate on the bed, turns segment lengths into filament, travels
// with retraction and z-hop, annotates layers the way PrusaSlicer's viewer reads them, estimates
// time and filament, and refuses a plate that does not fit. Plate coordinates (as in flat.ply and
// the Toolpath) map to bed coordinates by a translation in x and y: bed = plate + plate_to_bed, z
// unchanged. Lengths in mm, speeds in mm/s, temperatures in degrees C. docs/gcode.md describes the
// output line by line.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gcode/printer_profile.h"
#include "material/material.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

// Part of a print made of objects printed one after the other, each from the bed up: the layers of
// the toolpath from `first_layer` on (up to the next section) are one object, or one set of
// objects printed together (the calibration samples: one section per nozzle temperature and layer
// height). The toolpath's layers then run bottom to top within each section and start again near
// the bed at the next one. At the start of a section the writer lifts the nozzle above everything
// printed so far, sets the section's nozzle temperature and waits for it (M109), and treats the
// section's first layer as a first layer (speed and fan). The objects of different sections must
// not overlap, and each section's own travels must stay clear of the others (e.g. sections in
// disjoint convex regions): the writer only lifts at section changes.
struct PrintSection {
  size_t first_layer = 0;         // index into Toolpath::layers; the first section starts at 0
  double nozzle_temperature = 0;  // degrees C; 0: the material's; > 0 needs a one-tool print
  std::string label;              // written as a comment where the section begins
};

struct GcodeOptions {
  // Where the centre of the plate's bounding box goes on the bed (bed coordinates, mm, as the
  // firmware sees them: `--at X,Y`). Unset: the centre of the bed.
  std::optional<Eigen::Vector2d> at;
  // Skirt loops printed around the plate on the first layer (0: none), and their gap to the plate.
  int skirt_loops = 0;
  double skirt_distance = 3.0;  // mm
  // Empty: the whole toolpath is one object printed bottom to top (PrintSection above).
  std::vector<PrintSection> sections;
};

struct GcodeResult {
  std::string text;                    // the whole file
  Eigen::Vector2d plate_to_bed{0, 0};  // mm: bed = plate + plate_to_bed
  Eigen::Vector2d print_min{0, 0};     // bed coordinates of the print's bounding box (mm),
  Eigen::Vector2d print_max{0, 0};     // skirt included
  double print_time = 0;               // s, moves of the print (start G-code excluded)
  std::vector<double> layer_times;     // s per layer
  double filament_length = 0;          // mm of filament extruded, all tools
  double filament_volume = 0;          // mm^3, all tools
  double filament_mass = 0;            // g, all tools
  // Per tool (index = tool, as many as materials were given): mm of filament and g.
  std::vector<double> tool_filament_length;
  std::vector<double> tool_filament_mass;
  int tool_changes = 0;  // times the tool-change template (or a filament swap) runs
  // The header's `key = value` lines as data (print time, filament, printer, materials, speeds),
  // in file order: what a run folder's report shows without reading the G-code back.
  std::vector<std::pair<std::string, std::string>> summary;
};

// The G-code of `toolpath` for `printer`, printing each tool's segments (SegmentStyle::tool) with
// `tool_materials[tool]`: its temperature, speeds, fan and density. Wherever the print goes on
// with another tool, the profile's tool change runs (ToolChange), or on a printer with one nozzle
// and a FilamentSwap, a pause for the user to load the next tool's material (T0's is loaded at
// the start). One material: `{material}`. The result has passed check_gcode (a violation is a bug
// of the writer or the profile: std::logic_error). Throws UserError: kInfeasible when the plate
// does not fit the bed or the printer's height, or needs a tool the printer lacks (and cannot
// swap); kOption when a tool the toolpath uses has no material, when there are more materials
// than the printer has tools (and it cannot swap), or when T0's bed temperature is too hot for
// another material.
GcodeResult make_gcode(const Toolpath& toolpath, const PrinterProfile& printer,
                       const std::vector<Material>& tool_materials,
                       const GcodeOptions& options = {});

// make_gcode, then writes the text to `path` atomically.
GcodeResult write_gcode(const std::filesystem::path& path, const Toolpath& toolpath,
                        const PrinterProfile& printer, const std::vector<Material>& tool_materials,
                        const GcodeOptions& options = {});

// One G-code file of a print cut where the material changes (the paper's files F1-F5 for a printer
// that can neither change tools nor pause): each file prints one run of one tool's segments in
// print order, from its printer's start G-code to its end G-code, at the bed position the whole
// print would have, and the user starts them one after the other with the plate left on the bed.
struct MaterialFile {
  std::string label;       // "F1", "F2", ...: the file's place in the order
  int tool = 0;            // whose material it prints (written as T0 of a one-material file)
  size_t first_layer = 0;  // the toolpath's layers it prints in, first and last (indices)
  size_t last_layer = 0;
  GcodeResult gcode;
};

// The print of `toolpath` as MaterialFiles, each made by make_gcode with its tool's material
// alone and `options` (the skirt in the first file only; the whole print's placement). Throws
// what make_gcode throws, and std::invalid_argument for options with sections.
std::vector<MaterialFile> make_material_files(const Toolpath& toolpath,
                                              const PrinterProfile& printer,
                                              const std::vector<Material>& tool_materials,
                                              const GcodeOptions& options = {});

// make_material_files, each written atomically beside `path` with its label: plate.gcode gives
// plate-F1.gcode, plate-F2.gcode, ...
std::vector<MaterialFile> write_material_files(const std::filesystem::path& path,
                                               const Toolpath& toolpath,
                                               const PrinterProfile& printer,
                                               const std::vector<Material>& tool_materials,
                                               const GcodeOptions& options = {});

// The PrusaSlicer ;TYPE: name of a path type ("Solid infill", "Skirt/Brim", ...).
std::string_view prusaslicer_type_name(PathType type);

// The skirt loops around the first layer of `toolpath`: closed polylines in plate coordinates,
// outermost first, offset from the convex hull of the layer by `distance` + k x `width` (mm).
std::vector<PathPolyline> skirt_loops(const Toolpath& toolpath, int loops, double distance,
                                      double width, double layer_height);

}  // namespace flatmorph
