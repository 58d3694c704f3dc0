// Self-rising tiles (Geodesy, CHI 2019), the whole design: per tile its profile → shrink per ring
// (tile_profile.h, tile_levels.h), the rings offset from its outline (tile_rings.h), the print
// with per-ring layer heights in a collision-free order (tile_passes.h), the lattice joining
// tiles printed apart (tile_lattice.h), and the risen sheet predicted by the shared simulator from
// the printed layer stack (tile_plate.h), each tile's profile measured on it. Millimetres.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/progress.h"
#include "material/material.h"
#include "mesh/sheet_mesh.h"
#include "methods/tiles/tile_lattice.h"
#include "methods/tiles/tile_layout.h"
#include "methods/tiles/tile_levels.h"
#include "methods/tiles/tile_passes.h"
#include "methods/tiles/tile_plate.h"
#include "methods/tiles/tile_profile.h"
#include "methods/tiles/tile_rings.h"
#include "simulate/simulate.h"

namespace flatmorph {

struct TilesDesignOptions {
  Material material;          // with a thickness curve (pla-geodesy)
  Material lattice_material;  // used when the layout has a lattice
  RingLevelOptions levels;    // pitch, sheet thickness, bilayer, strict
  double feed_rate = 50;      // mm/s, the tiles (3000 mm/min)
  // mm: the longest edge of the simulator's mesh; 0: 1 mm, or longer on large sheets so that the
  // mesh keeps to about 8000 faces (the 3 x 3 coaster: 1.9 mm, 6 edges along a tile's radius).
  double mesh_edge = 0;
  bool simulate = true;
  // Refine a polygonal tile's per-ring shrink so its risen profile along the inscribed radius
  // matches the circular tile's (beyond the paper, whose mapping Sh′ is exact only for circles).
  bool optimize = true;
  int optimize_iterations = 6;
  SimulationOptions simulation{.max_iterations = 300};
  ProgressCallback progress;
};

// A tile's risen profile, measured on the simulated sheet: per vertex of the tile its flat radius
// on the design circle (R − depth), its distance to the tile's axis (through the apex and the
// rim's centroid) and its height above the rim's centroid along that axis, toward the side it
// rose to.
struct TileMeasure {
  int side = 0;                   // +1 risen toward +z, −1 toward the bed
  double height_mm = 0;           // apex above the rim's centroid
  double expected_height_mm = 0;  // what the printed shrink gives geometrically
  // Between the ring at 0.2 R and the rim (the apex rounds over a few thicknesses): simulated and
  // geometric, and their difference in % of the geometric one.
  double depth_mm = 0, expected_depth_mm = 0, depth_error_pct = 0;
  // Largest |distance to the axis − (1 − Sh) r| of a ring (the mean over its vertices) over the
  // rings but the outermost, whose edge is free (circles only).
  double ring_radius_error_mm = 0;
  // Along the inscribed radii, away from the apex (r ≥ 0.2 R), per ring level the mean height
  // against the target profile: their rms about their mean (the shape, whatever the rim's
  // height), mm. And how far the radii's heights lie from their level's mean (rms, mm): a
  // polygon's apex flexes toward one side at almost no cost, which per-ring shrink cannot set.
  double profile_rms_mm = 0;
  double profile_spread_mm = 0;
  // The curves for the plot: target (the profile asked), geometric (the printed shrink), simulated
  // (per level: mean radius and height), as (ρ, z) rows, z above the rim.
  Eigen::MatrixX2d target, geometric, simulated;
};

struct TileResult {
  TileProfile profile;
  TileRings rings;
  TileLevels levels;
  bool circular = false;  // the outline is a circle: every ring exactly at its radius
  TileMeasure measure;
  // Polygonal tiles: the profile error with the circle's mapping Sh′ alone, and whether the
  // optimized per-ring shrink replaced it.
  double mapped_profile_rms_mm = 0;
  bool optimized = false;
};

struct TilesDesign {
  TileLayout layout;
  std::vector<TileResult> tiles;
  TileLattice lattice;   // empty without one
  SheetMesh mesh;        // regions: the tiles in order, then the lattice's pieces
  double mesh_edge = 0;  // mm, the longest edge it was refined to
  TilePlate plate;
  TilesToolpath print;
  SimulationResult simulation;  // V: the risen sheet (plate frame, registered at its centre)
  bool simulated = false;
  std::vector<std::string> warnings;  // printability, one per tile that needed clamping
  struct Times {
    double rings = 0, mesh = 0, paths = 0, simulation = 0, optimization = 0, total = 0;
  } times;
};

// The whole design of `layout`. Throws UserError for what cannot be printed (an outline too small
// for one ring, a profile with no printable ring or needing a clamp with options.levels.strict, a
// material without a thickness curve).
TilesDesign design_tiles(const TileLayout& layout, const TilesDesignOptions& options);

}  // namespace flatmorph
