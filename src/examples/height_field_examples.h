// Built-in height fields for the self-rising method (SCF 2020), generated procedurally so that the
// method runs without files: a hill, two hills with a saddle, an island with three peaks and a
// ridge. Units: millimetres.
#pragma once

#include <string>
#include <vector>

#include "examples/examples.h"
#include "methods/heightfield/height_field.h"

namespace flatmorph {

// The defaults are the paper's sizes (Table 1: 146-181 mm across, 26-42 mm high; Hawaii is
// 159.0 x 34.7 mm).
struct HeightFieldExampleOptions {
  double diameter_mm = 160.0;  // of the disk footprint, centred on the origin
  double height_mm = 35.0;     // of the highest vertex above the boundary (which is at z = 0)
  double resolution_mm = 2.0;  // the most the rings are apart (radially); the lattice is 6-fold
};

// "hill", "saddle", "island", "ridge", in that order, with a line each.
std::vector<ExampleInfo> height_field_example_list();
std::vector<std::string> height_field_example_names();

// The named height field on a disk footprint meshed in rings (a hexagonal lattice bent onto
// circles, faces counter-clockwise seen from +z): zero on the boundary, positive inside, and
// scaled so that its highest vertex is exactly height_mm; deterministic. Every one passes
// check_height_field (no depression: each is a taper 1 - (r / R)^2 times a sum of Gaussian bumps,
// whose only interior critical points are peaks and saddles):
// - hill: one round peak at the centre;
// - saddle: two equal peaks on the x axis, 0.9 R apart, with a saddle between them;
// - island: three peaks in a chain over a broad base, the middle one highest;
// - ridge: a crest along the x axis, about four times as long as it is wide at half height.
// Throws UserError(kOption) for an unknown name (listing the valid ones) or a size that is not a
// positive number, or a resolution coarser than a quarter of the diameter.
HeightField height_field_example(const std::string& name,
                                 const HeightFieldExampleOptions& options = {});

}  // namespace flatmorph
