// What printing the solid itself would cost, to set against the folded sheet (Thermorph Fig. 2:
// 60-87 % less printing time; notes §10): a stated estimate from the solid's volume and surface,
// and the slicer's own figures when PrusaSlicer is installed. Millimetres, seconds, grams.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "material/material.h"
#include "methods/origami/polyhedron.h"

namespace flatmorph {

// How a slicer would print the solid, for the volume estimate: shells of `shell_mm` under the
// whole surface, the inside filled to `infill`, every bead `line_width` x `layer_height` laid at
// `speed`, plus `overhead` for travels, accelerations and layer changes. Supports are not counted
// (a solid on its flattest face needs few; the paper's bunny needs many: the estimate errs on the
// side of the solid).
struct SolidPrintSettings {
  double shell_mm = 0.8;      // 2 perimeters of 0.4 mm; top and bottom 4 layers of 0.2 mm
  double infill = 0.15;       // share of the inside
  double line_width = 0.45;   // mm
  double layer_height = 0.2;  // mm
  double speed = 50;          // mm/s
  double overhead = 0.25;     // share added to the extrusion time
};

struct SolidPrintEstimate {
  std::string source;  // how it was obtained, one phrase for the report
  double volume = 0;   // mm^3, the closed solid's
  double printed = 0;  // mm^3 of filament laid
  double filament_mm = 0;
  double filament_g = 0;
  double time_s = 0;
};

// The volume (mm^3) a closed solid encloses, by the divergence theorem over its faces (each a
// planar polygon, counter-clockwise seen from outside); its surface area (mm^2).
double polyhedron_volume(const Polyhedron& solid);
double polyhedron_area(const Polyhedron& solid);

// The estimate from the solid's volume and area (an open solid: its faces as shells alone).
SolidPrintEstimate estimate_solid_print(const Polyhedron& solid, const Material& material,
                                        double filament_diameter,
                                        const SolidPrintSettings& settings = {});

// PrusaSlicer's estimate (prusa-slicer on the PATH, run headless on the solid as an OBJ in a
// temporary folder with its default settings and `filament_diameter`), read from the comments
// of the G-code it writes; nullopt when it is not installed, fails or takes longer than
// `timeout_s` (the reason in `why` when given).
std::optional<SolidPrintEstimate> slicer_solid_print(const Polyhedron& solid,
                                                     double filament_diameter, double timeout_s,
                                                     std::string* why = nullptr);

// The slicer's figures from its G-code text: "; estimated printing time (normal mode) = 1h 2m 3s",
// "; filament used [mm] = ...", "; filament used [g] = ...". nullopt when the time is missing.
std::optional<SolidPrintEstimate> read_slicer_estimate(const std::string& gcode);

}  // namespace flatmorph
