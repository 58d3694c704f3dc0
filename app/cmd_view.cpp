// flatmorph view: serve the report viewer of a run folder on 127.0.0.1 (opens nothing by itself).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.h"
#include "report/server.h"

namespace flatmorph::cli {

Command make_view_command(CLI::App& app, const GlobalOptions&) {
  auto dir = std::make_shared<std::string>();
  auto options = std::make_shared<ViewServerOptions>();
  CLI::App* sub = app.add_subcommand(
      "view",
      "Serve the report viewer of a run folder on http://127.0.0.1:PORT/ (read afresh at every "
      "page load) until stopped with Ctrl-C. Prints the URL; opens no browser.");
  sub->add_option("dir", *dir, "Run folder: the -o DIR of flatmorph design")->required();
  sub->add_option("--port", options->port, "TCP port on 127.0.0.1 (0: any free port)")
      ->capture_default_str();
  return {sub, [dir, options] {
            serve_run_folder(*dir, *options, [](const std::string& url) {
              // Printed even with --quiet: it is what the command is for.
              fmt::print("flatmorph view: serving {} (Ctrl-C stops)\n", url);
              std::fflush(stdout);
            });
            return 0;
          }};
}

}  // namespace flatmorph::cli
