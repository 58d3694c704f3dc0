// The frozen validation family of issue 21: parametric disk-like targets off the paper's six models
// (elliptic caps of aspect 1 to 3, rounded polygonal caps, saddles, a monkey saddle, a twisted
// strip, a wave, an off-centre bump), 3k to 10k faces, 80 to 150 mm wide. Settings are chosen on
// the paper's six and only reported on these: never tuned on (docs/design.md). Generated, so that
// they need no files and are the same on every machine.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace flatmorph {

struct ValidationTarget {
  std::string name;
  std::string description;  // the surface and its footprint, sizes in mm
  Mesh mesh;                // mm, normals up (+z is the side that becomes the top of the plate)
  double width_mm = 0;      // the footprint's larger side: the width to design the plate at
};

// The family, in a fixed order. Each is a height field z = f(x, y) over a star-shaped footprint
// centred on the origin, meshed in rings that follow the footprint's outline.
std::vector<ValidationTarget> validation_family();

// Targets of the family's kinds at other sizes, aspects and resolutions (monkey saddles, elliptic
// caps), measured like the family and never tuned on either.
std::vector<ValidationTarget> validation_family_variants();

}  // namespace flatmorph
