#include "run_command.h"

#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "progress_display.h"

namespace flatmorph::cli {

void add_run_options(CLI::App* command, RunCommandOptions& options) {
  command->add_flag("!--no-gcode", options.request.gcode, "Skip the paths and the G-code");
  command->add_flag("--json", options.json,
                    "Print design.json (parameters and metrics) on stdout at the end instead of "
                    "the human-readable summary and progress");
  command->add_option("-o,--output", options.request.output, "Output folder (created if needed)")
      ->required();
}

int run_and_print(const RunCommandOptions& options, const GlobalOptions& global) {
  const bool silent = global.quiet || options.json;
  RunControl control;
  control.progress = make_progress_display(silent);
  const RunResult result = run_design(options.request, control);
  finish_progress_line();
  for (const std::string& warning : result.warnings) {
    fmt::print(stderr, "flatmorph: warning: {}\n", warning);
  }
  for (const std::string& note : result.notes) fmt::print(stderr, "flatmorph: note: {}\n", note);
  if (options.json) fmt::print("{}\n", result.record.dump(2));
  if (silent) return 0;
  for (const std::string& line : result.summary) fmt::print("{}\n", line);
  return 0;
}

}  // namespace flatmorph::cli
