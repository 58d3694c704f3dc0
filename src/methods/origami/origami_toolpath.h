// The printed sheet as toolpaths in two materials (Thermorph, CHI 2018, Step 4; notes §8): rigid
// PLA faces, and per hinge an actuator whose active PLA lines run across the hinge (they store the
// stretch that bends it) over a TPU constraint layer, stacked PLA first (case A: the faces curl
// toward the bed, a mountain seen from above) or TPU first (case B: a valley). Millimetres, mm/s.
#pragma once

#include "material/hinge_curve.h"
#include "methods/origami/crease_pattern.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct OrigamiPrintSettings {
  // The actuator (notes §2): its layers, their height, the TPU's speed and how far its lines
  // reach into each face to bond (1 mm); the sheet has its pla_layers + tpu_layers layers, the
  // faces PLA in all of them.
  HingeStack stack;
  double line_width = 0.4;  // mm: the nozzle's diameter
  double face_speed = 50;   // mm/s (3000 mm/min, notes §8: faces slow, so they stay flat)
  int pla_tool = 0;
  int tpu_tool = 1;
};

// Whether layer k (0 on the bed) of a sheet of `num_layers` lays its faces' lines along y rather
// than x: crossed layers, mirrored about the middle (x, y, y, x for four), so that the faces'
// laminate is symmetric and their shrink does not warp them (an antisymmetric x, y, x, y couples
// stretch to twist: simulated faces saddled and held two of a cube's hinges at 45°).
bool face_lines_along_y(int k, int num_layers);

// The toolpath of `sheet` (plate coordinates as the sheet's, the bed at z = 0). Per layer, bottom
// up: each face solid in PLA (one loop around it, then lines along x or y as face_lines_along_y
// says) at settings.face_speed; each actuator's area, its quad grown by the stack's overlap into
// both faces, either active PLA lines along Actuator::across (perpendicular to the hinge) at
// HingeDesign::pla_speed, or TPU lines along the hinge at settings.stack.tpu_speed, case A PLA in
// the first stack.pla_layers layers and TPU above, case B the other way round. Beads touch and
// never overlap: the faces' lines stop where an actuator's area begins, and where two areas meet
// (at a corner of a face between two hinges) the earlier actuator keeps the common part. Within a
// layer one material prints, then the other, the layer starting with the material the layer below
// ended with; the first layer starts with the one that makes fewest changes over the print (ties:
// PLA). Throws std::invalid_argument for settings that are not positive, equal tools, an actuator
// without a PLA speed, or a sheet without faces.
Toolpath origami_toolpath(const ActuatedSheet& sheet, const OrigamiPrintSettings& settings = {});

}  // namespace flatmorph
