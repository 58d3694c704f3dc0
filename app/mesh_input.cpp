#include "mesh_input.h"

#include <CLI/CLI.hpp>

namespace flatmorph::cli {

void add_mesh_input(CLI::App* command, RunInput& input) {
  auto* path = command->add_option("mesh", input.path,
                                   "Target surface: an OBJ, PLY, STL or OFF file (units are taken "
                                   "as they are; commands that need a size scale it)");
  auto* example = command->add_option("--example", input.example,
                                      "Use a built-in target instead of a file (see 'flatmorph "
                                      "example --list')");
  path->excludes(example);
  example->excludes(path);
}

}  // namespace flatmorph::cli
