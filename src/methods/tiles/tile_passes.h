// The print of a sheet of Geodesy tiles (CHI 2019 §3, notes §4.3-4.8): per tile and per pass one
// continuous path through its rings, each ring at its own layer height and nozzle height, in an
// order in which the nozzle never runs into a taller bead printed before it:
// - within a pass, rings are printed in ascending nozzle height (a dome, whose layers thin toward
//   the rim, rim to centre; a horn centre to rim; a profile that is not monotone in monotone runs);
// - a tile's passes go bottom to top, and the tiles' (and the lattice's) passes are interleaved by
//   the nozzle height of their outermost ring, where neighbouring tiles meet.
// Millimetres, mm/s.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "methods/tiles/tile_levels.h"
#include "methods/tiles/tile_rings.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct TilePassOptions {
  double pitch = 0.4;     // path width, mm
  double feed_rate = 50;  // mm/s: 3000 mm/min (CHI 2019 §5)
  // Where a pass's path starts moves on by this fraction of the first ring per pass (the golden
  // ratio's 0.382), so the connectors of successive passes do not stack.
  double seam_step = 0.381966;
};

// A lattice layer (tile_lattice.h) already traced: its lines at nozzle height z.
struct LatticePass {
  std::vector<PathPolyline> lines;
  double z = 0;
};

struct TilesToolpath {
  Toolpath toolpath;
  // Per tile, per pass (1-based index − 1): the continuous paths printed (1 unless the profile
  // is not monotone or the outline splits).
  std::vector<std::vector<int>> paths_per_pass;
  double min_layer_height = 0, max_layer_height = 0;  // mm, over all ring beads
  double path_length = 0;                             // mm, extruded
};

// The toolpath of `tiles` (each tile's rings and levels, in the layout's order) and of the
// lattice's passes (may be empty). Throws std::invalid_argument for sizes that differ.
TilesToolpath tiles_toolpath(const std::vector<TileRings>& rings,
                             const std::vector<TileLevels>& levels,
                             const std::vector<LatticePass>& lattice,
                             const TilePassOptions& options);

}  // namespace flatmorph
