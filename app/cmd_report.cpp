// flatmorph report: the report of an existing run folder (report.html and PNG pictures).
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "report/report.h"

namespace flatmorph::cli {

Command make_report_command(CLI::App& app, const GlobalOptions& global) {
  struct ReportOptions {
    std::string dir;
    int pixels = kReportPicturePixels;
  };
  auto o = std::make_shared<ReportOptions>();
  CLI::App* sub = app.add_subcommand(
      "report",
      "Write DIR/report.html, one self-contained page that works offline (target and predicted "
      "shape in 3D, the plate coloured by theta1 or theta2, the print paths layer by layer, every "
      "metric and parameter), and the pictures DIR/plate_theta1.png, plate_theta2.png, "
      "predicted.png and layers.png, from the files of a run folder (flat.ply, target.ply, "
      "simulated.ply, design.json, plate.gcode: whichever exist).");
  sub->add_option("dir", o->dir,
                  "Run folder: the -o DIR of flatmorph design (or of flatten, "
                  "simulate and toolpaths)")
      ->required();
  sub->add_option("--pixels", o->pixels, "Width of the plate and shape pictures, pixels")
      ->capture_default_str()
      ->check(CLI::Range(100, 4000));
  return {sub, [o, &global] {
            const auto written = write_report(o->dir, "", o->pixels);
            if (!global.quiet) {
              for (const auto& path : written) fmt::print("wrote {}\n", path.string());
            }
            return 0;
          }};
}

}  // namespace flatmorph::cli
