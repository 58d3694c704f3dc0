// A design method's command: its options fill a RunRequest (run/run.h), the library runs it, and
// this prints what the run says: progress on stdout (none with --quiet or --json), warnings and
// notes on stderr, then design.json (--json) or the summary.
#pragma once

#include "commands.h"
#include "run/run.h"

namespace flatmorph::cli {

// The options every design command takes besides its method's.
struct RunCommandOptions {
  RunRequest request;
  bool json = false;  // print design.json instead of the summary
};

// Adds --no-gcode, --json and -o/--output to a design command.
void add_run_options(CLI::App* command, RunCommandOptions& options);

// Runs the request and prints; returns the exit status.
int run_and_print(const RunCommandOptions& options, const GlobalOptions& global);

}  // namespace flatmorph::cli
