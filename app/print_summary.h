// The print's figures for people: per-layer table, travel, timings, placement, print time and
// filament, on stdout (shared by `toolpaths` and `design`).
#pragma once

#include "gcode/printer_profile.h"
#include "run/print_plan.h"

namespace flatmorph::cli {

void print_plan_summary(const PrintPlan& plan, const PrinterProfile& printer);

}  // namespace flatmorph::cli
