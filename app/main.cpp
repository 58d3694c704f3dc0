// flatmorph: turn a target surface into a flat printable plate that self-shapes in hot water.
// This file only dispatches; every algorithm lives in src/.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <vector>

#include "commands.h"
#include "common/error.h"

int main(int argc, char** argv) {
  using namespace flatmorph;
  CLI::App app{
      "flatmorph: turns a target 3D surface into a flat plate for an ordinary FFF printer that "
      "morphs into that surface when dipped in hot water (Shrink & Morph, TOG 2023).\n"
      "Units are millimetres and radians everywhere.",
      "flatmorph"};
  app.set_version_flag("--version", std::string("flatmorph ") + FLATMORPH_VERSION);
  app.require_subcommand(1);
  app.fallthrough();
  cli::GlobalOptions global;
  app.add_flag("-q,--quiet", global.quiet, "Print only errors");

  // Add new commands here, one line each, in the order `flatmorph --help` lists them.
  std::vector<cli::Command> commands = {
      cli::make_info_command(app, global),
      cli::make_example_command(app, global),
      cli::make_printers_command(app, global),
      cli::make_materials_command(app, global),
      cli::make_check_command(app, global),
      cli::make_flatten_command(app, global),
      cli::make_simulate_command(app, global),
      cli::make_toolpaths_command(app, global),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    fmt::print(stderr, "flatmorph: {}\nRun 'flatmorph --help' (or 'flatmorph COMMAND --help').\n",
               e.what());
    return 2;
  }
  try {
    for (auto& command : commands) {
      if (command.app->parsed()) return command.run();
    }
    return 2;
  } catch (const UserError& e) {
    fmt::print(stderr, "flatmorph: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "flatmorph: internal error: {}\n", e.what());
    return 1;
  }
}
