// The outline of one Geodesy tile (CHI 2019 §3, §6): a closed polygon in the plate's plane, with
// the holes cut out of it, as every reader (DXF, SVG, the JSON layout, the built-in examples)
// delivers it and every later stage (rings, mesh, G-code) takes it. Millimetres. It is a region of
// the plane as the sheet mesher takes any (mesh/plane_region.h): holes are not printed, and
// `source` reads like "drawing.dxf: LWPOLYLINE at line 120", "layout.json: tile 3".
#pragma once

#include "mesh/plane_region.h"

namespace flatmorph {

using TileOutline = PlaneRegion;

}  // namespace flatmorph
