// A crease pattern as a FOLD 1.2 file (notes §9; edemaine/fold's spec), which Origami Simulator
// and the FOLD tools open: the sheet seen from above in mm (FOLD's y is up, as flatmorph's), each
// edge's assignment and signed fold angle in degrees, faces counter-clockwise, and flatmorph's
// hinge designs under the `flatmorph:` prefix.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "methods/origami/crease_pattern.h"

namespace flatmorph {

// The FOLD text (JSON, one key per line, numbers in shortest round-trip form: the same pattern
// gives the same bytes). Frame 0 is the crease pattern: file_spec 1.2, file_creator "flatmorph",
// frame_classes ["creasePattern"], frame_attributes ["2D"], frame_unit "mm", vertices_coords,
// edges_vertices (v0, v1 as the crease runs around its left face), edges_assignment (B, M, V, F),
// edges_foldAngle (degrees, a valley positive, a mountain negative, 0 for B and F) and
// faces_vertices (counter-clockwise from +z). With `hinges` (indexed by their crease), per edge
// edges_flatmorph:actuatorWidth (W, mm), edges_flatmorph:radius (r, mm), edges_flatmorph:speed
// (the active PLA's, mm/s) and edges_flatmorph:case ("A": PLA on the bed, "B"), null on edges
// without a hinge. With `folded` (per face its corners folded, in face order, mm, as fold_net
// gives them), a second frame in file_frames: frame_classes ["foldedForm"], frame_attributes
// ["3D"], frame_parent 0 with frame_inherit, and the sheet's vertices at their folded places.
// Throws std::invalid_argument for a hinge on no crease or twice, or `folded` not matching the
// faces.
std::string fold_json(const CreasePattern& pattern,
                      const std::vector<HingeDesign>* hinges = nullptr,
                      const std::vector<Eigen::MatrixX3d>* folded = nullptr);

}  // namespace flatmorph
