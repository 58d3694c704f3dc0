// The flatmorph subcommands. Each make_*_command registers a subcommand with its options on the app
// and returns it with the function that runs it; main() runs the one the user chose. Commands only
// parse options, call the library and print: no algorithm lives in app/.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace flatmorph::cli {

// Options every command sees (set before the command runs).
struct GlobalOptions {
  bool quiet = false;
};

struct Command {
  CLI::App* app;
  std::function<int()> run;  // returns the exit status
};

Command make_info_command(CLI::App& app, const GlobalOptions& global);
Command make_example_command(CLI::App& app, const GlobalOptions& global);
Command make_printers_command(CLI::App& app, const GlobalOptions& global);
Command make_materials_command(CLI::App& app, const GlobalOptions& global);
Command make_check_command(CLI::App& app, const GlobalOptions& global);
Command make_flatten_command(CLI::App& app, const GlobalOptions& global);
Command make_simulate_command(CLI::App& app, const GlobalOptions& global);
Command make_toolpaths_command(CLI::App& app, const GlobalOptions& global);
Command make_design_command(CLI::App& app, const GlobalOptions& global);
Command make_heightfield_command(CLI::App& app, const GlobalOptions& global);
Command make_tiles_command(CLI::App& app, const GlobalOptions& global);
Command make_origami_command(CLI::App& app, const GlobalOptions& global);
Command make_calibrate_command(CLI::App& app, const GlobalOptions& global);
Command make_report_command(CLI::App& app, const GlobalOptions& global);
Command make_view_command(CLI::App& app, const GlobalOptions& global);
Command make_help_command(CLI::App& app, const GlobalOptions& global);

}  // namespace flatmorph::cli
