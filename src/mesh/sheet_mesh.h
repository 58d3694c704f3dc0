// The triangle mesh of a sheet of regions for the plate simulator (src/simulate): Geodesy tiles and
// their lattice, where it replaces the paper's ring-spring model (CHI 2019 §7; note
// geodesy-tiles.md §7.2), or an origami sheet's faces and actuators. Quality triangles that conform
// to every region's outline, each labelled with the region it lies in; and the ring frame (depth
// below the outline, ring tangent) at any points, which becomes a tile's layers' shrink and
// material angle. Millimetres and radians. The only file compiled with CGAL's flags.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/plane_region.h"

namespace flatmorph {

struct SheetMeshOptions {
  // mm: no triangle edge longer; the outlines are sampled at most this far apart.
  double max_edge = 1.0;
  // Degrees, in (0, 30]: CGAL's refinement is guaranteed to end up to 20.7, and in practice does
  // to about 30 (faces at sharper corners of the outlines keep those corners' angles).
  double min_angle_deg = 25;
  int max_vertices = 200'000;  // refuse (UserError kResource) rather than mesh beyond this
};

struct SheetMesh {
  // #V x 2, mm: the outlines' points first (as given, in the regions' order, once where they
  // coincide within 1e-6 mm), then the points sampling the outlines, then the interior's.
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;  // #F x 3, counter-clockwise; sorted by region, then by centroid (x, y)
  Eigen::VectorXi face_region;  // #F: index into the regions given
};

// Meshes the union of `regions` (tiles and a lattice with the tiles cut out as holes, an origami
// sheet's faces and actuators).
// Regions may share edges, with different vertices along them (both sides are split alike so the
// mesh is one piece there), and may nest inside other regions' holes; they must not overlap in
// area (UserError kGeometry naming where). Holes not filled by another region stay empty.
SheetMesh sheet_mesh(const std::vector<PlaneRegion>& regions, const SheetMeshOptions& options);

struct RingFrame {
  // mm: distance to the nearest point of the outline (boundary and holes); ring m of the tile lies
  // at depth (m + 1/2) w (note §4.1).
  Eigen::VectorXd depth;
  // rad in [0, pi): the ring tangent, i.e. the direction of the offset curve through the point,
  // perpendicular to the direction to the nearest outline point (note §7.2: grad d rotated by 90
  // degrees); on the outline itself, the outline's direction.
  Eigen::VectorXd direction;
};

// The ring frame of one region (a tile) at each row of `points` (#P x 2, mm). Exact distance to the
// outline's segments; points outside the region get their (unsigned) distance too.
RingFrame ring_frame(const PlaneRegion& outline, const Eigen::MatrixX2d& points);

}  // namespace flatmorph
