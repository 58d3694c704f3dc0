// Reading back the print paths of a G-code file flatmorph wrote (plate.gcode), for the report: the
// extruding moves of every layer as polylines in the plate's frame (as in flat.ply), in print
// order, and the header's `; key = value` lines (print time, filament, printer, material, ...).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "toolpath/toolpath.h"

namespace flatmorph {

struct GcodePaths {
  // The header's `; key = value` comment lines, in file order.
  std::vector<std::pair<std::string, std::string>> header;
  // One layer per ;LAYER_CHANGE of the print, bottom first; each polyline is a maximal run of
  // extruding moves (the travels between consecutive polylines are implicit), skirt included. Plate
  // frame: bed coordinates minus the header's plate_to_bed translation.
  Toolpath toolpath;
};

// Reads a G-code file written by flatmorph (the `; ---- flatmorph: print begins` marker and
// PrusaSlicer annotations). Absolute and relative E, G92 and firmware retraction are understood.
// Throws UserError(kFile) when the file cannot be read and UserError(kFormat) naming the file when
// it was not written by flatmorph.
GcodePaths read_gcode_paths(const std::filesystem::path& path);

// The value of a header key, or "" when absent.
std::string header_value(const GcodePaths& gcode, const std::string& key);

}  // namespace flatmorph
