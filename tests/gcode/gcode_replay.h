// A small G-code reader for the tests, written separately from the writer and the safety check
// (it shares no code with src/gcode/): it replays a file as a printer would and reports what was
// printed, so the tests can compare it with the toolpath the file was written from. Lengths in mm,
// temperatures in degrees C.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace flatmorph::testing {

// One extruding move (G1 that moves the head and pushes filament).
struct ReadExtrusion {
  double x0, y0, x1, y1, z;  // start and end in bed coordinates, and the height it ends at
  double filament;           // mm of filament
  std::string type;          // the ;TYPE: in effect ("" if none)
  double width;              // the ;WIDTH: in effect (0 if none)
  double height;             // the ;HEIGHT: in effect (0 if none)
  // The tool selected by the last T command, or whose material the last ";FILAMENT_SWAP:T<n>"
  // loaded into a single nozzle (0 before any).
  int tool;
  double nozzle_target;  // that tool's last M104/M109 target (-1 if none)
  // The last M104/M109 target given to any tool: what a nozzle shared by all tools is set to.
  double heater_target;
  double feed;  // the F in effect, mm/min (-1 if none)
  double z0;    // the height the move starts at (the head's z before it; NaN if never set)
};

// A T command that selects another tool than the one in use.
struct ReadToolChange {
  int line;                  // 1-based line of the T command
  int from, to;              // tools
  size_t extrusions_before;  // extrusions of the layers read before it (the print's, in order)
};

struct ReadLayer {
  double z_tag = -1;       // from ;Z:
  double height_tag = -1;  // from ;HEIGHT: right after ;LAYER_CHANGE
  std::vector<ReadExtrusion> extrusions;
  double filament() const;  // sum over the extrusions
};

struct ReadGcode {
  std::vector<ReadLayer> layers;      // one per ;LAYER_CHANGE
  double filament_before_layers = 0;  // purge lines of the start G-code
  // Extent of every head position once known (start and end G-code included).
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300, max_z = -1e300;
  double min_z = 1e300;
  // The largest distance of a head position from (cx, cy) given to read_gcode.
  double max_radius = 0;
  std::vector<double> nozzle_targets;                      // every M104/M109 target, in order
  std::map<int, std::vector<double>> tool_nozzle_targets;  // the same per tool (T word or active)
  std::map<int, double> final_tool_nozzle;                 // per tool, at the end
  std::vector<ReadToolChange> tool_changes;
  // ";FILAMENT_SWAP:T<n>" annotations that load another tool's material (line: the annotation's).
  std::vector<ReadToolChange> filament_swaps;
  // Lines of the commands that pause a print: M0, M1, M25, M600, M601, PAUSE, M400 U1 (Bambu).
  std::vector<int> pauses;
  std::vector<double> bed_targets;           // every M140/M190 target, in order
  double final_nozzle = -1, final_bed = -1;  // the targets at the end (-1: never set)
  bool motors_off_at_end = false;
  bool mode_declared_before_extrusion = false;  // M82 or M83 came before the first extrusion
  bool relative_e = false;                      // the mode in effect at the end
  int g0_with_e = 0;                            // G0 lines carrying an E word
  int extrusions_while_retracted = 0;  // moves that push filament while retracted and travelling
  int g92_e0_in_layers = 0;            // "G92 E0" lines after the first ;LAYER_CHANGE
  std::vector<std::string> annotation_errors;  // PrusaSlicer's conventions, broken
  std::map<std::string, std::string> header;   // "; key = value" comment lines
  std::vector<std::string> lines;              // the file, for tests that look at neighbours
};

// Replays `text`. (cx, cy) is the point max_radius is measured from.
ReadGcode read_gcode(const std::string& text, double cx = 0, double cy = 0);

}  // namespace flatmorph::testing
