// A crease pattern drawn as SVG (issue 27's forward flow, item 5; notes §9): the sheet's outline
// and its fold lines, each fold's kind and angle from a data-fold-angle attribute or from Origami
// Simulator's colour and opacity convention; the lines cut each other into the sheet's faces.
// Millimetres and radians; plate coordinates (the drawing seen from above, not mirrored).
#pragma once

#include <cstddef>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "methods/origami/crease_pattern.h"

namespace flatmorph {

struct CreasePatternReadOptions {
  // mm: line ends, corners and crossings closer than this are one point, and a line that ends
  // this close to another meets it there (a T-junction). Drawing programs round coordinates to a
  // few decimals of their own unit (0.001 px is 0.3 µm), far below this; a sheet's faces are far
  // above it.
  double snap_tolerance = 0.01;
  // rad: a mountain or valley folding less than this is a flat crease, as for a solid's nets
  // (notes §4: no actuator under 1°).
  double flat_angle = std::numbers::pi / 180;
  std::string name;             // the sheet's name in messages and files; empty: the source
  size_t max_bytes = 64 << 20;  // larger files are refused (kResource)
  // So are drawings of more straight segments, and lines crossing each other in more than 25
  // times as many points.
  size_t max_segments = 20'000;
};

// The pattern drawn in the SVG `text` (`source` names it in messages), read through
// svg::read_drawing (units, viewBox, transforms, y turned up). Lines: <line>, <polyline>,
// <polygon>, <rect> (square corners) and <path> (M, L, H, V, Z), each segment a side of the
// outline or a crease by its stroke colour (inherited from groups; Origami Simulator's colours,
// by name, #rgb, #rrggbb or rgb()): black #000000 or green #00ff00 the outline, red #ff0000 a
// mountain, blue #0000ff a valley, yellow #ffff00 a flat crease. A fold's angle is its
// data-fold-angle (degrees, FOLD's sign: a valley positive, a mountain negative) when it has one,
// else its opacity (or stroke-opacity) × 180° signed by its colour, as Origami Simulator reads it;
// |θ| < options.flat_angle makes a flat crease. Elements without a stroke (fills, backgrounds) are
// left out with a warning.
//
// The lines are split where they cross or where one ends on another (within
// options.snap_tolerance), and the bounded regions they enclose are the faces (counter-clockwise
// from +z), numbered in the order the drawing first reaches them. Pieces of lines with a free end
// that lie outside the sheet (overshoots) are left out with a warning. The fold tree is a maximum
// spanning tree on crease length over the mountain, valley and flat creases (long hinges are the
// strong ones, as for a solid's nets), rooted at the largest face; fold_order is the order the
// tree reaches the faces; solid_face is −1 throughout.
//
// Throws UserError with "SOURCE:LINE: problem: what to do": kFormat for what svg::read_drawing
// refuses, elements other than those lines (<circle>, <use>, <image>, ...), curved path commands,
// stroke colours outside the convention (naming it), magenta (Origami Simulator's undriven hinge:
// no angle to print), an opacity outside [0, 1], a data-fold-angle that is not a number in
// [−180, 180] or disagrees with its colour; kTopology for no closed outline, a fold line that
// ends inside a face or runs inside one without cutting it in two, a fold on the outline (one
// face), an outline line between two faces (a zero-width cut cannot be printed), lines drawn
// over each other with different kinds or angles, a face with a hole, and a sheet in several
// pieces (one sheet per file); kGeometry for coordinates beyond 1e6 mm; kResource past
// options.max_bytes or options.max_segments (or 25 times as many crossings); kOption for a
// tolerance that is not positive or a flat angle outside [0, π). `warnings` (when given) receives
// what was assumed or left out.
CreasePattern read_crease_pattern_svg(std::string_view text, const std::string& source,
                                      const CreasePatternReadOptions& options = {},
                                      std::vector<std::string>* warnings = nullptr);

}  // namespace flatmorph
