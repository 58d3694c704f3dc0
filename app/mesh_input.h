// The "MESH | --example NAME" input that every command taking a target surface accepts.
#pragma once

#include "run/run_input.h"

namespace CLI {
class App;
}

namespace flatmorph::cli {

// Adds the positional MESH argument and the --example option, exclusive of each other.
void add_mesh_input(CLI::App* command, RunInput& input);

}  // namespace flatmorph::cli
