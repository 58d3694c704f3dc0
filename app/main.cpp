// flatmorph: turn a target surface into a flat printable plate that self-shapes in hot water.
// This file only dispatches; every algorithm lives in src/.
#include <fmt/core.h>
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <exception>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "numerics/linear_algebra_threads.h"

namespace {

// Ctrl-C (SIGINT) and SIGTERM: the handler only writes the signal number into a pipe (all a signal
// handler may safely do); a thread waiting on the pipe removes the outputs being written
// (abandon_temporary_outputs), prints one line and exits with 128 + the signal number (130 for
// Ctrl-C). Cleaning up in a normal thread allows it to take locks and walk folders; outputs
// already renamed into place are complete. (Blocking the signals and sigwait-ing would not do:
// threads that libraries start before main, OpenBLAS's, do not block them.)
int signal_pipe[2] = {-1, -1};

extern "C" void on_signal(int signal) {
  const unsigned char byte = static_cast<unsigned char>(signal);
  [[maybe_unused]] const auto written = ::write(signal_pipe[1], &byte, 1);
}

void exit_cleanly_on_signals() {
  if (::pipe(signal_pipe) != 0) return;
  std::thread([] {
    unsigned char signal = 0;
    while (::read(signal_pipe[0], &signal, 1) != 1) {
    }
    flatmorph::abandon_temporary_outputs();
    static const char message[] = "flatmorph: interrupted; no partial output was left\n";
    [[maybe_unused]] const auto written = ::write(2, message, sizeof message - 1);
    ::_exit(128 + signal);
  }).detach();
  struct sigaction action = {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace flatmorph;
  exit_cleanly_on_signals();
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
  std::optional<int> threads;
  app.add_option("--threads", threads,
                 "Threads for the BLAS of the sparse factorizations (default: the number measured "
                 "once on this machine and kept in ~/.cache/flatmorph/threads.json; also "
                 "FLATMORPH_THREADS)");

  // Add new commands here, one line each, in the order `flatmorph --help` lists them.
  std::vector<cli::Command> commands = {
      cli::make_info_command(app, global),      cli::make_example_command(app, global),
      cli::make_printers_command(app, global),  cli::make_materials_command(app, global),
      cli::make_check_command(app, global),     cli::make_flatten_command(app, global),
      cli::make_simulate_command(app, global),  cli::make_toolpaths_command(app, global),
      cli::make_design_command(app, global),    cli::make_heightfield_command(app, global),
      cli::make_tiles_command(app, global),     cli::make_origami_command(app, global),
      cli::make_calibrate_command(app, global), cli::make_report_command(app, global),
      cli::make_view_command(app, global),      cli::make_help_command(app, global),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, like every other error (CLI11's messages are one line).
    fmt::print(
        stderr,
        "flatmorph: error [{}]: {}; run 'flatmorph --help' (or 'flatmorph COMMAND --help')\n",
        to_string(ErrorCategory::kOption), e.what());
    return 2;
  }
  try {
    configure_linear_algebra_threads(threads);
    for (auto& command : commands) {
      if (command.app->parsed()) return command.run();
    }
    return 2;
  } catch (const UserError& e) {
    // The category in brackets lets scripts tell failures apart (common/error.h).
    std::string message = e.what();
    for (char& c : message) {
      if (c == '\n' || c == '\r') c = ' ';  // one line, whatever a message quotes
    }
    fmt::print(stderr, "flatmorph: error [{}]: {}\n", to_string(e.category()), message);
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "flatmorph: internal error: {}\n", e.what());
    return 1;
  }
}
