// Height fields, the input of the self-rising method (SCF 2020): a surface z = h(x, y) given as a
// triangle mesh over its footprint in the xy plane, and the checks that it can rise from a flat
// sheet (paper §4 step 2, §8 "Invalid shapes"). Units: millimetres for x, y, z and every size.
#pragma once

#include <Eigen/Core>
#include <string>

#include "mesh/mesh.h"
#include "methods/heightfield/gray_image.h"

namespace flatmorph {

struct HeightField {
  Eigen::MatrixXd V;  // #V x 3 positions, mm; z is the height over the xy plane
  Eigen::MatrixXi F;  // #F x 3; counter-clockwise seen from +z when made by height_field_from_*
  // Per-vertex colour, #V x 3 with channels in [0, 1], or empty when the surface has none.
  Eigen::MatrixXd colors;
};

// A face steeper than this (its normal's z below kWallNormalZ, i.e. more than 89.94 degrees from
// level) is a wall, not a slope: a graph has none, and float rounding of an exported vertical wall
// tilts it by far less.
inline constexpr double kWallNormalZ = 1e-3;

// Depressions shallower than this (mm) are let through: far below a printed layer, and above the
// float rounding of a metre-sized model exported in single precision.
inline constexpr double kDepressionToleranceMm = 1e-3;

// The most vertices height_field_from_image makes (a 2000 x 2000 grid).
inline constexpr long long kMaxHeightFieldVertices = 4'000'000;

// A point of the plate's plane as messages print it: "(x, y) mm", one decimal.
std::string at_xy(const Eigen::Vector2d& p);

// Throws UserError with one line "<source>: <problem> at (x, y) mm ...; <what to do>" for the first
// of these it finds, in this order:
// - the problems of diagnose_mesh other than pieces, closure and holes (empty, NaN, non-manifold,
//   inconsistent orientation, ...), worded as require_disk words them;
// - kTopology: several pieces (where the second one is), a closed surface (no boundary), more than
//   one boundary loop (where the first hole is: the loops other than the one enclosing the largest
//   area in xy are holes), an Euler characteristic other than 1 (handles; where the footprint is);
// - kGeometry, an overhang (the surface is not a graph over xy), in three forms: a face whose xy
//   projection is flipped against the orientation of the larger projected area, or a wall
//   (kWallNormalZ), named by its centroid; a vertex around which the faces wind more than once
//   seen from above; a boundary that crosses itself seen from above (where);
// - kGeometry, a depression: a vertex that water poured on the surface could not leave without
//   climbing, i.e. whose height is below the lowest level over all paths along edges to the
//   boundary (the boundary drains) by more than kDepressionToleranceMm. This covers a vertex lower
//   than its whole one-ring and a flat-bottomed pit (a plateau lower than all around it), and lets
//   through a flat base at the height of the boundary (it drains over the boundary) and any slope
//   or saddle. The paper refuses such areas because the symmetric sheet has no preferred direction
//   to sink into them. The message gives the lowest point of the deepest one, its depth and the
//   level of its rim.
// Throws std::invalid_argument when `colors` is neither empty nor #V x 3.
void check_height_field(const HeightField& field, const std::string& source);

// The mesh (mm, as read by read_mesh) as a height field: repaired first (repair_mesh: coincident
// vertices welded, as an OBJ split along texture seams needs, degenerate and duplicate faces
// removed, orientation made consistent), turned so that its faces are counter-clockwise seen from
// +z, then checked with check_height_field.
HeightField height_field_from_mesh(const Mesh& mesh, const std::string& source);

// The image as a height field over width_mm (x) by depth_mm (y), centred on the origin, x to the
// right and y up (the image's rows run down). The pixels are samples from corner to corner: the
// top-left pixel's centre lies at (-width_mm / 2, depth_mm / 2) and the bottom-right one's at
// (width_mm / 2, -depth_mm / 2); black is z = 0 and the largest sample value (255 or 65535) is
// z = height_mm. Resampled bilinearly onto a regular grid whose spacing is at most resolution_mm in
// x and in y (a spacing of width_mm / (image.width - 1) reproduces the pixels exactly), each
// square split into two counter-clockwise triangles along alternating diagonals; then checked with
// check_height_field. Throws UserError: kOption when a size is not a positive number or the grid
// would have more than kMaxHeightFieldVertices vertices, kFormat when the image is smaller than
// 2 x 2 pixels.
HeightField height_field_from_image(const GrayImage& image, double width_mm, double depth_mm,
                                    double height_mm, double resolution_mm,
                                    const std::string& source);

}  // namespace flatmorph
