// The outline of one Geodesy tile (CHI 2019 §3, §6): a closed polygon in the plate's plane, with
// the holes cut out of it, as every reader (DXF, SVG, the JSON layout, the built-in examples)
// delivers it and every later stage (rings, mesh, G-code) takes it. Millimetres.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace flatmorph {

struct TileOutline {
  // #P x 2, mm: counter-clockwise seen from +z, the first point not repeated at the end. Curves
  // (circles, arcs, bulges) arrive as chords.
  Eigen::MatrixX2d boundary;
  // Each #P x 2, mm, clockwise: loops inside the boundary that are not printed.
  std::vector<Eigen::MatrixX2d> holes;
  // Where it came from, for messages: "drawing.dxf: LWPOLYLINE at line 120", "layout.json: tile 3".
  std::string source;
};

}  // namespace flatmorph
