// A collision replay for the tests, independent of the G-code writer and of the tiles' scheduler
// (Geodesy CHI 2019 prints rings of different layer heights in one pass, so the nozzle's Z differs
// between neighbouring rings; note geodesy-tiles.md §4.6): the file, as read by gcode_replay, is
// replayed on a raster height map of the printed beads' tops, and every extrusion whose nozzle tip
// would run into a taller bead already printed is reported. Millimetres.
#pragma once

#include <cstddef>
#include <vector>

#include "gcode/gcode_replay.h"

namespace flatmorph::testing {

struct CollisionOptions {
  double tip_diameter = 1.0;  // mm: the flat of the nozzle tip, centred on the nozzle axis
  double cell = 0.05;         // mm: the height map's raster (note §4.6: w/4 or finer)
  // mm: how far a bead top may stand above the nozzle; < 0: min(0.25 h, 0.02) with h the
  // extrusion's ;HEIGHT: (0.02 when it has none), note §4.6.
  double tolerance = -1;
};

struct BeadCollision {
  int layer;         // index into ReadGcode::layers
  size_t extrusion;  // index into that layer's extrusions
  double x, y;       // mm: the nozzle axis where the tip is deepest below a bead top
  double nozzle_z;   // mm: the nozzle's height there
  double bead_top;   // mm: that bead top
};

// Every extrusion, in file order, whose tip passes below a bead top printed before it (the worst
// place of each); beads are as wide as their ;WIDTH: (0.4 mm without one) and their top is the
// nozzle's height where it laid them. Extrusions before the first ;LAYER_CHANGE (purge lines) and
// travels are not replayed.
std::vector<BeadCollision> replay_collisions(const ReadGcode& gcode,
                                             const CollisionOptions& options);

}  // namespace flatmorph::testing
