// flatmorph example: write a built-in target surface to a file.
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "common/error.h"
#include "examples/example_catalog.h"
#include "examples/examples.h"
#include "mesh/io.h"

namespace flatmorph::cli {
namespace {

struct ExampleOptions {
  std::string name;
  std::string output;
  bool list = false;
};

int run_example(const ExampleOptions& options, const GlobalOptions& global) {
  if (options.list) {
    // The target surfaces this command writes, then the other methods' inputs.
    for (const ExampleEntry& entry : example_catalog()) {
      if (entry.method == "shrink_morph") fmt::print("{:<12} {}\n", entry.name, entry.description);
    }
    std::string command;
    for (const ExampleEntry& entry : example_catalog()) {
      if (entry.method == "shrink_morph") continue;
      if (entry.command != command) {
        command = entry.command;
        fmt::print("\nflatmorph {} --example NAME:\n", command);
      }
      fmt::print("{:<12} {}\n", entry.name, entry.description);
    }
    return 0;
  }
  if (options.name.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "name the example to write (see 'flatmorph example --list')");
  }
  if (options.output.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "flatmorph example needs an output file: -o FILE.obj or -o FILE.ply");
  }
  const Mesh mesh = make_example(options.name);
  write_mesh(options.output, mesh);
  if (!global.quiet) {
    fmt::print("wrote {} ({} vertices, {} faces, millimetres)\n", options.output,
               mesh.num_vertices(), mesh.num_faces());
  }
  return 0;
}

}  // namespace

Command make_example_command(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<ExampleOptions>();
  CLI::App* sub = app.add_subcommand(
      "example",
      "Write a built-in target surface (sizes in mm, normals on the side that becomes the top of "
      "the plate). Every command that takes a mesh also accepts --example NAME directly.");
  sub->add_option("name", options->name, "Example name (see --list)");
  sub->add_option("-o,--output", options->output, "Output mesh file (.obj or .ply)");
  sub->add_flag("--list", options->list,
                "List the built-in target surfaces, and the other commands' built-in inputs");
  return {sub, [options, &global] { return run_example(*options, global); }};
}

}  // namespace flatmorph::cli
