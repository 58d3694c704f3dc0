// The "MESH | --example NAME" input that every command taking a target surface accepts.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "mesh/io.h"

namespace flatmorph::cli {

struct MeshInput {
  std::string path;     // a mesh file (OBJ, PLY, STL, OFF)
  std::string example;  // or the name of a built-in example
};

// Adds the positional MESH argument and the --example option, exactly one of which is required.
void add_mesh_input(CLI::App* command, MeshInput& input);

// What the input names, for messages: the file path or "example NAME".
std::string describe(const MeshInput& input);

// Reads the file or generates the example. Throws UserError when neither or both are given.
MeshFile load_mesh_input(const MeshInput& input);

}  // namespace flatmorph::cli
