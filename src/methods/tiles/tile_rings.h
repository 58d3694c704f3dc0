// The print path of one Geodesy tile (CHI 2019 §3, Fig. 2c; note §4): nested closed rings offset
// inward from the tile's outline by the path pitch w (curves of constant distance to the outline,
// note A6), their containment tree split into chains, and a chain joined into one continuous path
// by blending the end of each ring into the next.
//
// Millimetres everywhere; the plane is seen from +z (counter-clockwise = positive area).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "methods/tiles/tile_outline.h"

namespace flatmorph {

struct RingOptions {
  // mm: the spacing between rings, equal to the printed path width w (note 2.1).
  double pitch = 0.4;
  // mm: the outermost ring's distance from the outline; < 0 means pitch / 2, the bead just inside
  // the outline (note A9; 0 is the paper's bead centred on the outline).
  double first_offset = -1;
  // mm: how far a ring may stray from the exact level set: half of it for the chords of round
  // joins, half for simplifying the outline first (a densely chorded curve makes Clipper's deep
  // offsets slow).
  double arc_tolerance = 0.01;
  // A piece of an offset is printed only if its outer ring is at least min_length long and the
  // piece (outer ring minus the rings around holes) covers at least min_area (note 4.2). mm; < 0:
  // π·pitch.
  double min_length = -1;
  // mm²; < 0: pitch².
  double min_area = -1;
  // Clipper's integer units per mm.
  double scale = 1e4;
};

struct Ring {
  // #P x 2, mm: closed, the first point not repeated; counter-clockwise for a ring around the
  // outside of its piece, clockwise for a ring around a hole. Starts at its vertex with the
  // smallest x (then y): the reference point the seam is measured from.
  Eigen::MatrixX2d points;
  // m: 0 for the outermost rings.
  int level = 0;
  // mm from the outline: first_offset + m·pitch.
  double depth = 0;
  // Index in TileRings::rings of the ring at level m − 1 it came from (around the outside: the
  // outer ring of the piece that contains it; around a hole: the ring around the same hole one
  // level out), −1 at level 0.
  int parent = -1;
};

struct TileRings {
  // Ordered by level; within a level by parent, rings around the outside before rings around holes,
  // then by reference point.
  std::vector<Ring> rings;
  // mm: the largest distance from the outline to a point of the tile (the inradius of a convex
  // tile): the deepest region is located by bisection on the offset depth, then the exact
  // distance is climbed to a local maximum from its centre (to 1e-6 mm).
  double max_depth = 0;
};

// The rings of `outline`: offsets of the original outline (with its holes) by −depth_m with round
// joins, m = 0, 1, ... (note 4.1), each piece of an offset its own rings, until no piece is left
// that meets min_length and min_area (note 4.2). A piece is kept only inside a piece kept one level
// out. For a disc of radius R this gives N = floor((R − first_offset − r_min) / pitch) + 1 rings at
// radii R − first_offset − m·pitch, r_min = max(min_length / 2π, sqrt(min_area / π)).
// Throws UserError(kOption) for options out of range, and UserError(kGeometry) naming
// outline.source and a point for a boundary or hole with fewer than 3 distinct points, NaN/Inf or
// absurd (> 1e6 mm) coordinates, zero area, edges that cross or touch, a hole outside the boundary
// or inside another hole, or a tile too small for one ring.
TileRings tile_rings(const TileOutline& outline, const RingOptions& options = {});

// mm: the distance from p to the outline's boundary and holes, positive inside the tile, negative
// outside it or inside a hole. Throws std::invalid_argument for a boundary of fewer than 3 points.
double outline_depth(const TileOutline& outline, const Eigen::Vector2d& p);

// The containment tree of `rings` as maximal chains of ring indices, each from its outermost ring
// inward: a ring that is the only child of its parent continues the parent's chain, every child of
// a ring with several children starts a chain of its own (note 4.4). Depth first: a chain, then
// the chains that branch off its last ring, in ring order.
std::vector<std::vector<int>> ring_chains(const TileRings& rings);

struct JoinOptions {
  // mm: the length of each ring's end that blends into the next ring (note 4.3b); < 0: 8 × the
  // ring spacing; 0: the paper's straight jog to the nearest point of the next ring.
  double blend_length = -1;
  // The blend is at most this fraction of its ring's length.
  double max_blend_fraction = 0.25;
  // Where the first ring starts, as a fraction of its length from its reference point (Ring), in
  // the direction of travel; any real number, taken modulo 1 (a caller adds 0.382 per pass).
  double seam = 0;
  // mm: no segment of the path is longer than this; < 0: the rings' own vertices.
  double point_spacing = -1;
};

struct RingPath {
  // #P x 2, mm: an open polyline.
  Eigen::MatrixX2d points;
  // Per point: the level m of the ring it lies on, fractional along a connector, so that a caller
  // can blend the layer height and Z along it (note 4.3b).
  Eigen::VectorXd ring_coordinate;
};

// One continuous path through the rings `sequence` (indices into rings.rings, in print order;
// consecutive rings must be parent and child, either way round: outer → inner for a dome, inner →
// outer for a horn). Every ring is travelled counter-clockwise seen from +z, those around holes too
// (against their stored order), so the nozzle turns one way throughout.
// Each ring is travelled once round from its start. Over its last blend length b the path moves
// linearly (by arc-length fraction) from the ring onto the next one. The point it moves toward
// starts at the next ring's point nearest the blend's beginning and runs along the next ring as far
// as the nozzle runs along this one, so the next ring's blend begins where this target began: the
// connectors of successive rings lie side by side, a spacing w apart, and lie within about
// atan(w / b) of the rings' tangent. On small rings that target would run far ahead of (or behind)
// the nozzle's nearest point and pull the connector across the inner ring, so its lead over that
// point is kept within w × (shorter ring / longer ring); for a disc every point then stays between
// the two rings, and the connector is steeper there: atan(w / min(b, (b + w) r_inner / r_outer)).
// The next ring starts where the connector lands, which moves the start from ring to ring (by
// about b·w / r² radians on a disc). The last ring ends where it started.
// Throws std::invalid_argument for an empty sequence, an index out of range or consecutive rings
// that are not parent and child, and UserError(kOption) for NaN/Inf options or a
// max_blend_fraction outside (0, 1].
RingPath join_rings(const TileRings& rings, const std::vector<int>& sequence,
                    const JoinOptions& options = {});

}  // namespace flatmorph
