// The print's figures for people, as lines of text (no newline): shared by every run's summary and
// by `flatmorph toolpaths`.
#pragma once

#include <string>
#include <vector>

#include "gcode/printer_profile.h"
#include "run/print_plan.h"

namespace flatmorph {

// A print traced from a plate's layer stack: the refined plate, the per-layer table (z, paths,
// printed and travel mm, forks), travel, the tracing's timings, then gcode_summary_lines.
std::vector<std::string> plan_summary_lines(const PrintPlan& plan, const PrinterProfile& printer);

// Any print: the printer, where the plate sits on the bed (mm), the estimated print time and the
// filament.
std::vector<std::string> gcode_summary_lines(const PrintPlan& plan, const PrinterProfile& printer);

}  // namespace flatmorph
