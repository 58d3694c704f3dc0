// What a G-code file deposited: every extruding move as a bead (where the nozzle went, how wide
// and high the bead is, which tool, layer and feed rate), read from any slicer's file or
// flatmorph's own, so that a printed file can be compared with a design or turned into one.
// Positions are the file's (bed) coordinates in mm, feed rates in mm/min, filament in mm³.
//
// The reader follows the firmware (Marlin 2): M82/M83 and G90/G91 (which set the E mode too, until
// the next M82/M83), G92, G0–G3 (a G0 that extrudes deposits like a G1; arcs in the XY plane, with
// I/J or R, full circles, helical z; P, Marlin's optional extra turns, is not read), T<n>,
// G10/G11, and flatmorph's ";FILAMENT_SWAP:T<n>" (a manual swap on one nozzle: tool n's material
// prints from there, which is not counted as a tool change). It needs no annotation; the ones it
// reads are listed with the rules below and in docs/gcode.md "Reading G-code".
//
// Deposits. A bead is a move that pushes filament forward while the head moves in x and y. A move
// that pulls filament back (or G10) is a retraction, also when it moves (a wipe): nothing is
// deposited. Filament pushed back after a retraction first refills what was pulled back (tracked
// per tool, each tool having its own filament), and only the rest is deposited; an E move without
// x/y motion (an unretraction, a prime or purge blob) deposits nothing. An arc is cut into chords
// whose sagitta is at most 0.005 mm, its filament and z shared out evenly along it.
//
// Layers. In a file with layer annotations (";LAYER_CHANGE" of PrusaSlicer, Orca and flatmorph,
// Bambu's "; CHANGE_LAYER", Cura's ";LAYER:n") each annotation starts a layer, and beads before
// the first (the start G-code's purge line) belong to layer 0. Otherwise a new layer starts at an
// extruding move that starts more than 0.02 mm above where the previous extruding move ended and
// more than 40 % of the current layer's nominal height (its z above the layer below's) above the
// current layer's lowest extruding z: a z-hop (a travel) never starts a layer, nor does a path
// whose z rises slowly.
//
// Heights and widths. A bead's height is the ";HEIGHT:" (Bambu "; LAYER_HEIGHT:") in effect;
// without one, its nominal height: its mean nozzle z above the z of the layer below (above the bed
// for layer 0, and for a bead not above the layer below, such as the first layer of the next object
// of a sequential print). Its width is the ";WIDTH:" (Bambu "; LINE_WIDTH:") in effect; without
// one, the rectangle model flatmorph's writer uses: filament volume / (3D length × height).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "material/speed_curve.h"
#include "material/thickness_curve.h"

namespace flatmorph {

struct DepositedBead {  // one extruding move (an arc gives several chords)
  // Nozzle positions, mm, in the file's (bed) coordinates; z is the nozzle height (top of the
  // bead).
  Eigen::Vector3d start{0, 0, 0}, end{0, 0, 0};
  double width = 0;         // mm: ;WIDTH: when the file gives it, else volume / (length × height)
  double height = 0;        // mm: ;HEIGHT: when given, else the nominal height (above)
  double feed_rate = 0;     // mm/min in effect (0 before any F)
  int tool = 0;             // 0-based tool (T0, T1, ...)
  int layer = 0;            // 0-based layer index (above)
  double filament_mm3 = 0;  // filament volume pushed: ΔE (refills excluded) × filament section
  int line = 0;             // 1-based line of the G-code command
  // ;TYPE: (Bambu "; FEATURE:") in effect, "" if none: "Skirt/Brim", "Wipe tower", ... lets
  // callers skip beads that are not part of the print.
  std::string type;
};

// A tool's shrink model as a flatmorph header writes it, the ratios the file was designed with:
// "; [Tn ]shrink = lambda1 A, lambda2 B, lambda3 C, delta_lambda1 D", "; [Tn ]speed_curve = none"
// or "= lambda1 coefficients C0 C1 ..., speeds LO..HI mm/s, layer height H mm", and
// "; [Tn ]thickness_curve = none" or "= lambda1 coefficients C0 C1 ..., layer heights LO..HI mm".
struct HeaderShrinkModel {
  double lambda1 = 1, lambda2 = 1, lambda3 = 1, delta_lambda1 = 0;
  std::optional<SpeedCurve> speed_curve;
  std::optional<ThicknessCurve> thickness_curve;
};

struct GcodeHeaderInfo {  // what the file's comments say, when they say it (never required)
  // flatmorph "; printer = NAME"; else PrusaSlicer/Orca "; printer_settings_id = NAME"; else
  // "; printer_model = NAME"; else Cura ";TARGET_MACHINE.NAME:" or ";MACHINE_NAME:".
  std::string printer;
  // Per tool: flatmorph "; material = NAME" or "; T0 material = NAME", "; T1 material = ...";
  // else PrusaSlicer/Orca "; filament_settings_id = "A";"B"".
  std::vector<std::string> tool_materials;
  // Per tool (index = tool; may be shorter than tool_materials): its shrink model when the three
  // lines of HeaderShrinkModel are there and read (usable curves); else unset.
  std::vector<std::optional<HeaderShrinkModel>> tool_shrink;
  // mm: "; filament_diameter = 1.75 mm" (flatmorph) or "= 1.75,1.75" (PrusaSlicer, one per
  // extruder): the first, and all of them in tool order.
  std::optional<double> filament_diameter;
  std::vector<double> tool_filament_diameters;
  // mm: flatmorph's "; plate_to_bed = x_bed = x_plate - 12.000, y_bed = y_plate + 3.000, ..."
  // gives (−12, 3): bed = plate + plate_to_bed.
  std::optional<Eigen::Vector2d> plate_to_bed;
};

struct GcodeDeposition {
  std::vector<DepositedBead> beads;  // in file order
  int num_layers = 0;
  // Per layer, mm: the layer's ";Z:" (Bambu "; Z_HEIGHT:") when the file gives it, else the lowest
  // nozzle z of its extruding moves (in an annotated file, those after its annotation), else (a
  // layer without extrusion) the z of the layer below, 0 for the first.
  std::vector<double> layer_z;
  GcodeHeaderInfo header;
  int tool_changes = 0;  // T<n> lines that select another tool than the one in use
  // Retractions: E starting to move back (G1 E-…, also spread over a wipe's moves) or a G10 of a
  // tool not already retracted; counted, not deposited.
  int retractions = 0;
};

struct GcodeReadOptions {
  // Filament diameter, mm. Used unless the header gives one and `filament_diameter_given` is
  // false.
  double filament_diameter = 1.75;
  bool filament_diameter_given = false;
  size_t max_lines = 50'000'000;  // longer files are refused (memory and time)
  size_t max_beads = 20'000'000;  // so are files with more beads (arc chords included)
};

// The beads `text` deposits. Throws UserError with one line "SOURCE:LINE: problem: what to do"
// naming `source`: kFormat for content it cannot read or that deposits implausibly (inches
// (G20), arcs outside the XY plane (G18/G19), a parameter that is not a finite number, an
// extruding move at z <= 0, a bead of 0.05 mm or more wider than 5 mm or 20 times its height (E
// in the wrong mode; beads before the first layer annotation, purge lines, are not judged), a file
// that deposits nothing), kResource beyond `max_lines` or `max_beads`, kOption for a filament
// diameter in `options` that is not a positive number. A last line cut short (a truncated file)
// is read when it can be, skipped otherwise.
GcodeDeposition read_gcode_deposition(std::string_view text, const std::string& source,
                                      const GcodeReadOptions& options = {});

// Only what the header's comments say (the same keys as read_gcode_deposition), from any text:
// nothing is judged and nothing thrown.
GcodeHeaderInfo read_gcode_header(std::string_view text);

}  // namespace flatmorph
