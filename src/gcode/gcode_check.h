// The safety check run on every G-code file flatmorph writes, and on any G-code with
// `flatmorph check`: a G-code goes to a machine with a 200 degree nozzle, so it must stay on the
// bed, stay within the material's temperatures, never extrude while travelling, keep its extrusion
// distances consistent with the declared mode, and leave heaters and motors off. The rules, with
// their thresholds, are listed in docs/gcode.md. Lengths in mm, temperatures in degrees C.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "gcode/printer_profile.h"
#include "material/material.h"

namespace flatmorph {

enum class ViolationKind {
  kMalformed,             // a parameter of a known command that is not a finite number
  kOutsideBed,            // a move (or a point of an arc) outside the reachable bed area
  kBelowBed,              // a move below z = 0
  kAboveMaxHeight,        // a move above the printer's maximum height
  kNozzleTemperature,     // a nozzle target above the material's maximum
  kBedTemperature,        // a bed target above the material's maximum
  kColdExtrusion,         // extrusion while the tool's target is below its material's minimum
  kExtrusionOnTravel,     // a G0 move that extrudes
  kUnretractWhileMoving,  // filament pushed back while the head travels (ooze along the travel)
  kRetractWhileMoving,    // filament pulled back while the head travels
  kEBackwards,            // absolute E running back further than a retraction, without G92
  kOverExtrusion,         // more filament than a bead can hold (E values in the wrong mode)
  kNoExtrusionMode,       // extrusion before any M82/M83 declares the E mode
  kHeatersOnAtEnd,        // a heater still on at the end of the file
  kMotorsOnAtEnd,         // no M84/M18 after the last move
  kUnknownTool,           // a tool selected, heated or used that the printer lacks
  kToolWithoutMaterial,   // a tool heated or used that no material was given for
  kSwapTemperature,       // extrusion after a filament swap without waiting (M109) since it
};

// "outside-bed", "cold-extrusion", ...: the names `flatmorph check` prints and the unsafe test
// files of tests/data/gcode/unsafe/ expect.
std::string_view to_string(ViolationKind kind);

struct GcodeViolation {
  int line = 0;  // 1-based line number in the file (the last line for end-of-file rules)
  ViolationKind kind = ViolationKind::kMalformed;
  std::string reason;  // one sentence with the numbers involved
};

// Thresholds of the rules (mm), fixed so that a file is judged the same way everywhere.
// A retraction or unretraction may come with at most this much XY travel.
constexpr double kRetractMoveTolerance = 1.0;
// Positions are compared to the bed with this slack (the writer prints 3 decimals).
constexpr double kBedTolerance = 0.002;
// An extruding move may lay at most this many nozzle-diameter squares of bead cross-section.
constexpr double kMaxBeadAreaInNozzleSquares = 10;
// Absolute E may run back below its running maximum by the profile's retraction plus this.
constexpr double kEBackwardsSlack = 1.0;

// Every violation in `text`, in line order (at most `max_violations`). `tool_materials[t]` is the
// material of tool t (T0 first, at least one): the check follows T commands and judges each tool's
// temperatures and extrusion by its own material; the shared bed by the least of their maxima. On
// a shared nozzle (ToolChange::shared_nozzle) the tools have one heater: each tool's extrusion is
// judged against the one target, which must lie within that tool's material's range. On a printer
// with one extruder, the annotation ";FILAMENT_SWAP:T<n>" (the writer's FilamentSwap) says that
// tool n's material is loaded from there on: it is judged the same way, and must not extrude
// before an M109 has waited for the nozzle after the swap.
std::vector<GcodeViolation> check_gcode(std::string_view text, const PrinterProfile& printer,
                                        const std::vector<Material>& tool_materials,
                                        size_t max_violations = 1000);

}  // namespace flatmorph
