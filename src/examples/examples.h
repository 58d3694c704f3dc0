// Built-in target surfaces, generated procedurally, so that every command can run without files.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace flatmorph {

struct ExampleInfo {
  std::string name;         // as used by --example NAME
  std::string description;  // one line, with its size in mm and curvature sign
};

// The list of built-in examples, in a fixed order.
std::vector<ExampleInfo> example_list();

// Generates the named example: an evenly tessellated disk-like surface in millimetres with normals
// pointing up (+z side is the one that becomes the top of the plate). Throws UserError(kOption)
// listing the valid names when `name` is unknown.
Mesh make_example(const std::string& name);

}  // namespace flatmorph
