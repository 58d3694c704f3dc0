// flatmorph materials: the shipped material presets, or one of them as JSON to start a custom one.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common/embedded_profiles.h"
#include "common/error.h"
#include "material/material.h"

namespace flatmorph::cli {
namespace {

struct MaterialsOptions {
  std::string name;
  bool json = false;
};

int run_materials(const MaterialsOptions& options) {
  if (!options.name.empty()) {
    for (const EmbeddedProfile& p : embedded_profiles()) {
      if (p.kind == "materials" && p.name == options.name) {
        fmt::print("{}", p.text);
        return 0;
      }
    }
    load_material(options.name);  // throws the usual "unknown material" error
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("\"{}\" is a file, not a preset: open it to read it", options.name));
  }
  std::vector<Material> materials;
  for (const std::string& name : material_preset_names()) materials.push_back(load_material(name));
  if (options.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const Material& m : materials) {
      list.push_back({{"name", m.name},
                      {"description", m.description},
                      {"lambda1", m.lambda1},
                      {"lambda2", m.lambda2},
                      {"lambda3", m.lambda3},
                      {"delta_lambda1", m.delta_lambda1},
                      {"layer_height", m.layer_height},
                      {"nozzle_temperature", m.nozzle_temperature},
                      {"bed_temperature", m.bed_temperature},
                      {"print_speed", m.print_speed},
                      {"first_layer_speed", m.first_layer_speed}});
    }
    fmt::print("{}\n", list.dump(2));
    return 0;
  }
  fmt::print("{:<14} {:<24} {:<16} {:<9} {}\n", "NAME", "LAMBDA 1 / 2 / 3", "NOZZLE / BED", "LAYER",
             "DESCRIPTION");
  for (const Material& m : materials) {
    fmt::print("{:<14} {:<24} {:<16} {:<9} {}\n", m.name,
               fmt::format("{:g} / {:g} / {:g}", m.lambda1, m.lambda2, m.lambda3),
               fmt::format("{:g} / {:g} C", m.nozzle_temperature, m.bed_temperature),
               fmt::format("{:g} mm", m.layer_height), m.description);
  }
  fmt::print(
      "\nUse one with --material NAME, or a JSON file of your own: 'flatmorph materials "
      "NAME' prints a preset to start from (docs/gcode.md).\n");
  return 0;
}

}  // namespace

Command make_materials_command(CLI::App& app, const GlobalOptions&) {
  auto options = std::make_shared<MaterialsOptions>();
  CLI::App* sub = app.add_subcommand(
      "materials",
      "List the material presets flatmorph ships (shrink ratios, temperatures), or print one as "
      "JSON to start a material file of your own.");
  sub->add_option("name", options->name, "A preset to print as JSON");
  sub->add_flag("--json", options->json, "Print the list as JSON");
  return {sub, [options] { return run_materials(*options); }};
}

}  // namespace flatmorph::cli
