// A printer as the G-code writer and the safety check need it: bed, nozzle, firmware dialect,
// start/end G-code, retraction, speeds and motion limits. Lengths in mm, speeds in mm/s,
// accelerations in mm/s^2, in the firmware's (bed) coordinates. Profiles are JSON files: the
// presets shipped in profiles/printers/ (selected by name) or a user's file (docs/gcode.md).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

// The G-code dialect: which commands exist and how a few of them are spelled.
enum class GcodeFlavor { kMarlin, kKlipper, kRepRapFirmware, kBambu };

enum class BedShape { kRectangular, kCircular };

// How the planner of the firmware limits the speed through a corner.
enum class CorneringModel {
  kJunctionDeviation,  // Marlin 2 / grbl; Klipper's square_corner_velocity is converted to this
  kJerk,               // classic jerk: the largest instantaneous speed change per axis
};

// A change of tool, as the printer makes it. Volumes in mm^3, lengths in mm (bed coordinates).
struct ToolChange {
  // The template (tool_change_placeholders()): parks the previous tool and selects the next with a
  // line "T{next_tool} ...", waits for its temperature; on a shared nozzle, the firmware's own
  // change (Bambu's M620/M621, an MMU's T<n>) and the flush of the old filament.
  std::string gcode;
  // The tools are filament slots feeding one nozzle with one heater (Bambu AMS, Prusa MMU): the
  // nozzle takes each tool's temperature in turn, and each change pushes `flush_volume` of the
  // next filament through it ({flush_length} in the template) to clear the previous one.
  bool shared_nozzle = false;
  double flush_volume = 0;
  // After the template, the writer primes the next tool on the bed by laying `prime_volume`
  // (0: no prime) as a pad in the rectangle [prime_area_min, prime_area_max] (successive primes go
  // on where the last one stopped), then wipes the nozzle `wipe_length` back along the bead.
  double prime_volume = 0;
  Eigen::Vector2d prime_area_min{0, 0};
  Eigen::Vector2d prime_area_max{0, 0};
  double wipe_length = 0;
};

// A manual change of filament on a printer with one nozzle (Thermorph's PLA/TPU on a single
// extruder, notes §8): wherever the print goes on with another tool's material, the writer
// retracts, lifts above the print, shows `message`, heats the nozzle for the swap and waits, runs
// `gcode` (the firmware's pause, during which the user unloads and loads), then waits for the next
// material's own temperature. Templates with filament_swap_placeholders().
struct FilamentSwap {
  std::string message;  // shows {message} on the printer's screen: "M117 {message}"
  std::string gcode;    // the pause: "M600" (Marlin, Prusa), "M400 U1" (Bambu)
};

// What a profile's `"filament_swap": {}` means for each firmware: M117 and M600 for Marlin (with
// ADVANCED_PAUSE_FEATURE), Prusa firmware and RepRapFirmware; M117 and an M600 macro the user
// defines for Klipper; a comment and Bambu's pause M400 U1 for Bambu (docs/gcode.md).
FilamentSwap default_filament_swap(GcodeFlavor flavor);

struct PrinterProfile {
  std::string name;
  std::string description;
  GcodeFlavor flavor = GcodeFlavor::kMarlin;

  // The printable bed. Rectangular: bed_size is its width (x) and depth (y). Circular: both are the
  // diameter. Corner origin: the bed spans [0, size]; centre origin: [-size/2, size/2].
  BedShape bed_shape = BedShape::kRectangular;
  bool origin_at_center = false;
  Eigen::Vector2d bed_size{220, 220};  // mm
  double max_height = 250;             // mm, highest nozzle position
  // Where the head may go (rectangular beds), which can be wider than the printable bed: the purge
  // line of a Prusa runs at y = -3. Equal to the bed when the profile does not say.
  Eigen::Vector2d axis_min{0, 0};      // mm
  Eigen::Vector2d axis_max{220, 220};  // mm

  double nozzle_diameter = 0.4;     // mm
  double filament_diameter = 1.75;  // mm
  // Tools selected with T0, T1, ...: independent nozzles, each with its own heater and filament
  // (IDEX, tool changers), or filament slots feeding one nozzle (AMS, MMU: see ToolChange).
  int extruder_count = 1;
  bool relative_e = false;  // M83 (relative) rather than M82 (absolute) extrusion distances

  double retract_length = 1.0;       // mm of filament
  double retract_speed = 35;         // mm/s
  double z_hop = 0.2;                // mm lift during retracted travels (0: none)
  double retract_min_travel = 2.0;   // mm: shorter travels neither retract nor lift
  bool firmware_retraction = false;  // G10/G11 instead of E moves

  // Default speeds (mm/s); the material's own print speeds take precedence (material.h).
  double print_speed = 40;
  double first_layer_speed = 20;
  double travel_speed = 120;
  double z_speed = 10;  // for moves along z alone (layer changes, z-hop)

  double print_acceleration = 1000;   // mm/s^2 for extruding moves
  double travel_acceleration = 1000;  // mm/s^2 for the others
  CorneringModel cornering = CorneringModel::kJunctionDeviation;
  double junction_deviation = 0.013;  // mm (kJunctionDeviation)
  double jerk = 8;                    // mm/s (kJerk)

  // Templates with {placeholders} (gcode_placeholders()); lines separated by '\n'.
  std::string start_gcode;
  std::string end_gcode;
  // What happens wherever the print goes on with another tool; used when extruder_count > 1.
  ToolChange tool_change;
  // One nozzle only: how the print pauses for the user to load another tool's material. Unset:
  // the printer prints one material.
  std::optional<FilamentSwap> filament_swap;
};

// Presets in a fixed order (alphabetical).
std::vector<std::string> printer_preset_names();

// A preset by name, or the printer JSON file at `name_or_path`. Throws UserError: kOption for an
// unknown name that is no file either, kProfile for a malformed profile (the message names the
// file, the key and the fix: missing key, wrong type, negative size, unknown flavor, unknown
// placeholder, unknown key, an end G-code that leaves heaters or motors on).
PrinterProfile load_printer(const std::string& name_or_path);

// Parses the JSON text of a profile; `source` names it in error messages.
PrinterProfile parse_printer(std::string_view json_text, const std::string& source);

std::string_view to_string(GcodeFlavor flavor);

// A one-line summary of the bed: "300 x 300 mm, 400 mm high" or "200 mm round, centre origin".
std::string describe_bed(const PrinterProfile& printer);

// The centre of the bed in bed coordinates (mm).
Eigen::Vector2d bed_center(const PrinterProfile& printer);

// Whether the point (bed coordinates, mm) lies on the printable bed, within `tolerance` mm.
bool on_bed(const PrinterProfile& printer, const Eigen::Vector2d& p, double tolerance);

// The rectangle (width, depth; mm) that parts placed on the bed may fill, `margin` mm from every
// edge: the bed less twice the margin, or on a round bed the inscribed square less twice the
// margin. One rule for every caller that lays parts out.
Eigen::Vector2d usable_bed_area(const PrinterProfile& printer, double margin);

// A placeholder a template may use, with its meaning.
struct GcodePlaceholder {
  std::string_view name;
  std::string_view meaning;
};
// Those of the start and end templates.
const std::vector<GcodePlaceholder>& gcode_placeholders();
// Those of the tool-change template (tool numbers, temperatures, the flush, where the next tool
// starts and the height above the print).
const std::vector<GcodePlaceholder>& tool_change_placeholders();
// Those of the filament-swap templates (the message, tools, materials, temperatures, the height
// above the print).
const std::vector<GcodePlaceholder>& filament_swap_placeholders();

// Replaces every {name} in `text` by values[name] ("{{" and "}}" stand for braces). Throws
// UserError(kProfile) naming `source` and the line for a placeholder not in `known` or unclosed;
// with an empty `values`, only checks the template.
std::string expand_gcode_template(
    std::string_view text, const std::vector<std::pair<std::string, std::string>>& values,
    const std::string& source, const std::vector<GcodePlaceholder>& known = gcode_placeholders());

}  // namespace flatmorph
