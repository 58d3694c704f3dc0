// Pictures of a folding sheet as SVG (notes §9), both drawn as the sheet is seen from above (SVG's
// y points down, so plate y is written as −y: the picture is not mirrored), sized in mm.
#pragma once

#include <string>

#include "methods/origami/crease_pattern.h"

namespace flatmorph {

// The sharp crease pattern as Origami Simulator's pattern importer reads it: one <line> per
// crease, directly under the root, its stroke colour the kind (border #000000, mountain #ff0000,
// valley #0000ff, flat #ffff00: Origami Simulator's flat "facet" crease) and its stroke-opacity
// |fold angle| / 180° (1 for borders and flat creases). Each folding or flat crease also carries
// its exact angle as data-fold-angle (degrees, FOLD's sign, shortest round-trip digits), which
// read_crease_pattern_svg prefers to the opacity; coordinates are written the same way, so that
// the pattern reads back to the bit.
std::string crease_pattern_svg(const CreasePattern& pattern);

// The sheet as printed (`sheet`, made from `pattern`): groups with ids "faces" (each trimmed face,
// grey), "actuators" (each actuator's strip filled, case A orange, case B light blue), "hinges"
// (each actuator's centre line along its hinge, mountain red, valley blue), "cut" (the outline to
// cut: the union of the faces and actuators, black), "face-numbers" (each face's index + 1 at the
// point of the trimmed face farthest from its sides, with data-face = the index) and "legend".
// Throws std::invalid_argument when `sheet` does not have the pattern's faces or names a crease
// the pattern does not have.
std::string net_svg(const CreasePattern& pattern, const ActuatedSheet& sheet);

}  // namespace flatmorph
