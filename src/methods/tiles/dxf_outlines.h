// Tile outlines from an ASCII DXF drawing (Geodesy CHI 2019 §6: "commercial CAD tools"; notes
// §6.4). Millimetres: the drawing's $INSUNITS (mm, cm, m, inch, foot) is converted, and curves
// arrive as chords.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "methods/tiles/outline_loops.h"
#include "methods/tiles/tile_outline.h"

namespace flatmorph {

// The tiles drawn in the ENTITIES section of an ASCII DXF `text` (`source` names it in messages):
// closed LWPOLYLINEs and 2D POLYLINEs (bulges are arcs), CIRCLEs, and LINEs, ARCs and open
// polylines chained end to end (within options.join_tolerance) into closed loops. Loops are nested
// even-odd (a loop inside a tile is its hole, a loop inside a hole a new tile); each tile's
// boundary is counter-clockwise seen from +z, its holes clockwise, and its `source` is
// "SOURCE: LWPOLYLINE at line N". Tiles come in the order their boundaries appear in the file.
// Entities with the extrusion direction (0, 0, -1) are mirrored in x (their object coordinate
// system; LINE and 3D POLYLINE coordinates are the world's whatever it is); z is ignored (the
// outline seen from above); paper-space entities and VIEWPORTs are not read. Circles and arcs
// become chords with their ends on the curve, at most options.chord_tolerance inside it (a
// circle of radius r loses at most (4/3) tolerance / r of its area).
//
// Throws UserError with one line "SOURCE:LINE: problem: what to do": kFormat for binary DXF, a
// damaged or truncated file, an entity of another type (SPLINE, ELLIPSE, INSERT, TEXT, HATCH, ...
// named, with how to convert it), a unit other than those above, a tilted extrusion; kGeometry for
// coordinates that are not finite or lie beyond 1e6 mm, a radius <= 0, an ARC of zero sweep,
// outlines that cross (with the place in mm), the same outline twice, no closed outline;
// kTopology for an open chain (with the gap's place in mm) or three ends meeting; kResource past
// options.max_bytes or options.max_points; kOption for options that are not positive.
// `warnings` (when given) receives what was assumed or left out: a drawing without units read as
// millimetres, loops of zero area and pieces of zero length dropped, paper-space entities.
std::vector<TileOutline> read_dxf_outlines(std::string_view text, const std::string& source,
                                           const OutlineReadOptions& options = {},
                                           std::vector<std::string>* warnings = nullptr);

}  // namespace flatmorph
