// flatmorph printers: the shipped printer profiles, or one of them as JSON to start a custom one.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common/embedded_profiles.h"
#include "common/error.h"
#include "gcode/printer_profile.h"

namespace flatmorph::cli {
namespace {

struct PrintersOptions {
  std::string name;
  bool json = false;
};

nlohmann::json describe(const PrinterProfile& p) {
  return {{"name", p.name},
          {"description", p.description},
          {"flavor", to_string(p.flavor)},
          {"bed",
           {{"shape", p.bed_shape == BedShape::kCircular ? "circular" : "rectangular"},
            {"size", {p.bed_size.x(), p.bed_size.y()}},
            {"origin", p.origin_at_center ? "center" : "corner"},
            {"max_height", p.max_height}}},
          {"nozzle_diameter", p.nozzle_diameter},
          {"filament_diameter", p.filament_diameter},
          {"relative_e", p.relative_e}};
}

int run_printers(const PrintersOptions& options) {
  if (!options.name.empty()) {
    for (const EmbeddedProfile& p : embedded_profiles()) {
      if (p.kind == "printers" && p.name == options.name) {
        fmt::print("{}", p.text);
        return 0;
      }
    }
    load_printer(options.name);  // throws the usual "unknown printer" error
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("\"{}\" is a file, not a preset: open it to read it", options.name));
  }
  std::vector<PrinterProfile> printers;
  for (const std::string& name : printer_preset_names()) printers.push_back(load_printer(name));
  if (options.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const PrinterProfile& p : printers) list.push_back(describe(p));
    fmt::print("{}\n", list.dump(2));
    return 0;
  }
  fmt::print("{:<20} {:<42} {:<7} {:<15} {}\n", "NAME", "BED", "NOZZLE", "FLAVOR", "DESCRIPTION");
  for (const PrinterProfile& p : printers) {
    fmt::print("{:<20} {:<42} {:<7} {:<15} {}\n", p.name, describe_bed(p),
               fmt::format("{:g} mm", p.nozzle_diameter), to_string(p.flavor), p.description);
  }
  fmt::print(
      "\nUse one with --printer NAME, or a JSON file of your own: 'flatmorph printers NAME' "
      "prints a preset to start from (docs/gcode.md).\n");
  return 0;
}

}  // namespace

Command make_printers_command(CLI::App& app, const GlobalOptions&) {
  auto options = std::make_shared<PrintersOptions>();
  CLI::App* sub = app.add_subcommand(
      "printers",
      "List the printer profiles flatmorph ships (bed, nozzle, firmware), or print one as JSON to "
      "start a profile of your own.");
  sub->add_option("name", options->name, "A preset to print as JSON");
  sub->add_flag("--json", options->json, "Print the list as JSON");
  return {sub, [options] { return run_printers(*options); }};
}

}  // namespace flatmorph::cli
