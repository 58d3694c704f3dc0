// Tool changes as the printer makes them (printer_profile.h's ToolChange), for the G-code writer:
// where the primes go on the bed, the temperature a shared nozzle flushes at, and what a print
// needs of its changes. Bed coordinates and lengths in mm, volumes in mm^3, temperatures in
// degrees C.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <set>
#include <vector>

#include "gcode/printer_profile.h"
#include "material/material.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

// Where the primes of tool changes go (ToolChange::prime_*): a serpentine of touching beads filling
// the profile's prime area row by row along x, each prime going on where the last one stopped.
struct PrimePad {
  std::vector<Eigen::Vector2d> corners;
  std::vector<double> arclength;  // along the serpentine, at each corner
  double bead_width = 0;
  double bead_height = 0;
  double capacity() const { return arclength.back(); }  // mm of bead

  // The point `s` mm along the serpentine.
  Eigen::Vector2d point(double s) const;
  // The corners strictly between s0 and s1, in the order met going from s0 to s1 (either way).
  std::vector<Eigen::Vector2d> corners_between(double s0, double s1) const;
};

PrimePad prime_pad(const PrinterProfile& printer);

// The temperature a shared nozzle flushes at when `from` gives way to `to`: the hotter of the two,
// which clears the previous filament best, but no hotter than either allows. Needs overlapping
// ranges (validate_tool_changes).
double flush_temperature(const Material& from, const Material& to);

// The temperature a single nozzle waits at while the user swaps `from` for `to` (FilamentSwap):
// flush_temperature when a temperature suits both, else `to`'s.
double swap_temperature(const Material& from, const Material& to);

// How many times the print changes tool: from T0 (where the start G-code leaves the firmware) to
// the first tool, then wherever consecutive extruding segments change tool.
int count_tool_changes(const Toolpath& toolpath, int first_tool);

// What the printer's tool changes need of this print, whose footprint on the bed (skirt included)
// is [print_min, print_max]: on a shared nozzle, a temperature every pair of the materials takes
// (UserError kOption); with a prime pad, room on it for every change and a pad clear of the print
// (UserError kInfeasible). Returns the pad when the print primes.
std::optional<PrimePad> validate_tool_changes(const Toolpath& toolpath,
                                              const PrinterProfile& printer,
                                              const std::vector<Material>& tool_materials,
                                              const std::set<int>& tools, int first_tool,
                                              const Eigen::Vector2d& print_min,
                                              const Eigen::Vector2d& print_max);

}  // namespace flatmorph
