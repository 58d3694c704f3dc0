// The print's figures for people: per-layer table, travel, timings, placement, print time and
// filament, on stdout (shared by `toolpaths` and `design`).
#pragma once

#include "gcode/printer_profile.h"
#include "run/print_plan.h"

namespace flatmorph::cli {

void print_plan_summary(const PrintPlan& plan, const PrinterProfile& printer);

// Its last lines, for any print: the printer, where the plate sits on the bed, the estimated print
// time and the filament.
void print_gcode_summary(const PrintPlan& plan, const PrinterProfile& printer);

}  // namespace flatmorph::cli
