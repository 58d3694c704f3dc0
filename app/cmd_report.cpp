// flatmorph report: the report of an existing run folder (report.html and PNG pictures).
#include <fmt/core.h>

#include "commands.h"
#include "report/report.h"

namespace flatmorph::cli {

Command make_report_command(CLI::App& app, const GlobalOptions& global) {
  auto dir = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "report",
      "Write DIR/report.html, one self-contained page that works offline (target and predicted "
      "shape in 3D, the plate coloured by theta1 or theta2, the print paths layer by layer, every "
      "metric and parameter), and the pictures DIR/plate_theta1.png, plate_theta2.png, "
      "predicted.png and layers.png, from the files of a run folder (flat.ply, target.ply, "
      "simulated.ply, design.json, plate.gcode: whichever exist).");
  sub->add_option("dir", *dir,
                  "Run folder: the -o DIR of flatmorph design (or of flatten, "
                  "simulate and toolpaths)")
      ->required();
  return {sub, [dir, &global] {
            const auto written = write_report(*dir);
            if (!global.quiet) {
              for (const auto& path : written) fmt::print("wrote {}\n", path.string());
            }
            return 0;
          }};
}

}  // namespace flatmorph::cli
