// Tile outlines from an SVG drawing (Geodesy CHI 2019 §6: outlines drawn in a drawing program;
// notes §6.4). Millimetres, plate coordinates: the root's width, height and viewBox give the
// drawing's size, and SVG's y (down) is turned up so that the outline is not mirrored. Curves
// arrive as chords.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "methods/tiles/outline_loops.h"
#include "methods/tiles/tile_outline.h"

namespace flatmorph {

// The tiles drawn in the SVG `text` (`source` names it in messages): <polygon>, closed
// <polyline>, <circle>, <ellipse>, <rect> (rounded corners too) and <path> (M, L, H, V, Z and
// elliptical arcs A, absolute and relative; each subpath a loop, closed by Z or by ending at its
// start within options.join_tolerance), through the `transform` of the element and of its groups.
// Units: with a viewBox, width/height in mm, cm, in, pt, pc or px (CSS px = 25.4/96 mm, also for
// unitless) scale user units to mm (preserveAspectRatio honoured); without a viewBox one user
// unit is one CSS px; with neither width/height nor viewBox, one mm (with a warning). Plate
// y = -SVG y. Styles are ignored, except that hidden elements (display:none) are not read; so are
// <defs>, <style>, <text>, <title>, <desc>, <metadata>, <symbol>, gradients, markers and the
// elements of other namespaces (sodipodi:*, inkscape:*). Loops are nested even-odd as in
// read_dxf_outlines; each tile's boundary is counter-clockwise, its holes clockwise, its `source`
// "SOURCE: <circle id=\"c2\"> at line N"; tiles come in the order of their boundaries in the file.
//
// Throws UserError with one line "SOURCE:LINE: problem: what to do": kFormat for malformed XML
// (with the line), elements nested deeper than 256, a root that is not <svg>, curves (C, S, Q, T:
// flatten them to line segments first), <use>, <image>, <line>, nested <svg>, unknown elements,
// bad numbers, lengths or transforms; kTopology for an open polyline or subpath (with where it
// ends); kGeometry as read_dxf_outlines (radius or size <= 0, coordinates beyond 1e6 mm, outlines
// crossing, the same outline twice, no closed outline); kResource past options.max_bytes or
// options.max_points; kOption for options that are not positive. `warnings` (when given)
// receives what was assumed or left out.
std::vector<TileOutline> read_svg_outlines(std::string_view text, const std::string& source,
                                           const OutlineReadOptions& options = {},
                                           std::vector<std::string>* warnings = nullptr);

}  // namespace flatmorph
