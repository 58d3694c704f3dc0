#include "mesh_input.h"

#include <fmt/core.h>

#include "common/error.h"
#include "examples/examples.h"

namespace flatmorph::cli {

void add_mesh_input(CLI::App* command, MeshInput& input) {
  auto* path = command->add_option("mesh", input.path,
                                   "Target surface: an OBJ, PLY, STL or OFF file (units are taken "
                                   "as they are; commands that need a size scale it)");
  auto* example = command->add_option("--example", input.example,
                                      "Use a built-in target instead of a file (see 'flatmorph "
                                      "example --list')");
  path->excludes(example);
  example->excludes(path);
}

std::string describe(const MeshInput& input) {
  return input.example.empty() ? input.path : "example " + input.example;
}

MeshFile load_mesh_input(const MeshInput& input) {
  if (input.path.empty() && input.example.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "no target surface given: pass a mesh file or --example NAME");
  }
  if (!input.example.empty()) return MeshFile{make_example(input.example), {}};
  return read_mesh(input.path);
}

}  // namespace flatmorph::cli
