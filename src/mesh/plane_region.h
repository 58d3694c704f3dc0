// A region of the plate's plane: a closed outline with holes cut out of it, as the sheet mesher
// (sheet_mesh.h) takes it: a Geodesy tile (methods/tiles/tile_outline.h), the lattice around
// tiles, an origami face or actuator. Millimetres.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace flatmorph {

struct PlaneRegion {
  // #P x 2, mm: counter-clockwise seen from +z, the first point not repeated at the end. Curves
  // (circles, arcs, bulges) arrive as chords.
  Eigen::MatrixX2d boundary;
  // Each #P x 2, mm, clockwise: loops inside the boundary that are not part of the region.
  std::vector<Eigen::MatrixX2d> holes;
  // Where it came from, for messages: "drawing.dxf: LWPOLYLINE at line 120", "face 3".
  std::string source;
};

}  // namespace flatmorph
