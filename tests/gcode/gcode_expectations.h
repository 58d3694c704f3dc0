// What every G-code file the project writes must satisfy, checked on its replay (gcode_reader.h):
// shared by the tests of the writer and of the files built on it (calibration prints).
#pragma once

#include <gtest/gtest.h>

#include "gcode/printer_profile.h"
#include "gcode_replay.h"
#include "material/material.h"

namespace flatmorph::testing {

// The annotations follow PrusaSlicer's conventions, and every head position is on the printer's
// reachable bed, between the bed and the maximum height.
inline void expect_annotated_and_within_printer(const ReadGcode& read,
                                                const PrinterProfile& printer) {
  EXPECT_TRUE(read.annotation_errors.empty()) << read.annotation_errors.front();
  if (printer.bed_shape == BedShape::kCircular) {
    EXPECT_LE(read.max_radius, printer.bed_size.x() / 2 + 1e-9);
  } else {
    EXPECT_GE(read.min_x, printer.axis_min.x());
    EXPECT_LE(read.max_x, printer.axis_max.x());
    EXPECT_GE(read.min_y, printer.axis_min.y());
    EXPECT_LE(read.max_y, printer.axis_max.y());
  }
  EXPECT_LE(read.max_z, printer.max_height);
  EXPECT_GE(read.min_z, 0);
}

// No temperature above the material's limits; heaters and motors off at the end.
inline void expect_within_limits_and_off_at_end(const ReadGcode& read, const Material& material) {
  for (double t : read.nozzle_targets) EXPECT_LE(t, material.max_nozzle_temperature);
  for (double t : read.bed_targets) EXPECT_LE(t, material.max_bed_temperature);
  EXPECT_EQ(read.final_nozzle, 0);
  EXPECT_EQ(read.final_bed, 0);
  EXPECT_TRUE(read.motors_off_at_end);
}

}  // namespace flatmorph::testing
