// What a design run left in its folder (flatmorph design -o DIR, or flatten / simulate / toolpaths
// into one folder), read for the report and the viewer. Every file is optional except that at
// least one must be there; what is missing is listed so the report can say so.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/io.h"
#include "plate/plate_design.h"
#include "toolpath/toolpath_file.h"

namespace flatmorph {

struct RunFolder {
  std::filesystem::path dir;
  std::string
      name;  // the folder's name as the report shows it (dir's, unless written elsewhere first)
  // flat.ply and its stack file; design_fields hold theta1 per face, theta2 per vertex.
  std::optional<PlateDesign> flat;
  std::optional<MeshFile> target;     // target.ply
  std::optional<MeshFile> simulated;  // simulated.ply, per-vertex deviation_mm if computed
  // gcode_simulated.ply: the shape predicted from plate.gcode (not listed as missing: only runs
  // with a print have it).
  std::optional<MeshFile> gcode_simulated;
  nlohmann::ordered_json design;      // design.json (null when absent)
  std::optional<ToolpathFile> print;  // toolpath.json: what plate.gcode prints, as data
  // The method's own drawings that design.json lists under "drawings" (file names of SVG files in
  // the folder: origami's net.svg, the tiles' profiles): each name and its text.
  std::vector<std::pair<std::string, std::string>> drawings;
  std::vector<std::string> missing;  // the file names that were not there
};

// Reads DIR/flat.ply, target.ply, simulated.ply, design.json and toolpath.json, whichever exist,
// and the drawings design.json lists (a listed drawing that is not there is named in `missing`).
// Throws UserError(kFile) when DIR is not a folder or holds none of them, and the readers' errors
// (naming the file) when one is malformed.
RunFolder read_run_folder(const std::filesystem::path& dir);

}  // namespace flatmorph
