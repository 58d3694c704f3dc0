#include "run/run_input.h"

#include "common/error.h"
#include "examples/examples.h"

namespace flatmorph {

std::string describe(const RunInput& input) {
  return input.example.empty() ? input.path : "example " + input.example;
}

MeshFile read_target_mesh(const RunInput& input) {
  if (input.path.empty() && input.example.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "no target surface given: pass a mesh file or --example NAME");
  }
  if (!input.example.empty()) return MeshFile{make_example(input.example), {}};
  return read_mesh(input.path);
}

}  // namespace flatmorph
