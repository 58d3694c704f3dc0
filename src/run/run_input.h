// What a run designs from: a file or a built-in example (examples/example_catalog.h).
#pragma once

#include <string>

#include "mesh/io.h"

namespace flatmorph {

// Exactly one of the two is given.
struct RunInput {
  std::string path;
  std::string example;
};

// "example NAME" or the path, for messages and design.json's "input".
std::string describe(const RunInput& input);

// A target surface: the mesh file (OBJ, PLY, STL, OFF; units as they are) or the built-in example
// (examples/examples.h, mm). Throws UserError (kOption) when neither is given, and the reader's
// or the example's UserErrors.
MeshFile read_target_mesh(const RunInput& input);

}  // namespace flatmorph
