#include "plate_input.h"

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "common/error.h"
#include "material/material.h"

namespace flatmorph::cli {

void add_plate_input_options(CLI::App* command, PlateInputOptions& options) {
  command->add_option("--material", options.material,
                      "Only for a flat.ply without a stack file: material preset name or JSON "
                      "file (default pla-paper); a plate with one prints what its stack says. For "
                      "a G-code file: one per tool, A[,B] (default: the materials its header "
                      "names)");
  command->add_option("--layers", options.layers,
                      "Only for a flat.ply without a stack file: number of printed layers of the "
                      "material's layer height (default 10)");
}

PlateDesign load_plate_input(const std::string& path, const PlateInputOptions& options,
                             std::string& warning) {
  std::error_code error;
  const std::filesystem::path stack = stack_file_path(path);
  const bool has_stack = std::filesystem::exists(stack, error);
  if (has_stack && (options.material || options.layers)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: the plate's stack file {} sets its layers and materials, so "
                                "--material and --layers do not apply; design the plate again "
                                "with the ones you want (flatmorph design/flatten --layers N "
                                "--material M), or delete {} to give them here",
                                path, stack.filename().string(), stack.filename().string()));
  }
  const int layers = options.layers.value_or(10);
  if (layers < 1 || layers > 1000) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--layers {} is out of range: give 1 to 1000 layers", layers));
  }
  const Material material = load_material(options.material.value_or("pla-paper"));
  PlateDesignFile file = read_plate_design(path, material, layers);
  warning.clear();
  if (!file.from_stack_file) {
    warning = fmt::format(
        "{} has no stack file ({}): read as {} layers of {} along its theta1 "
        "and theta2 (--layers and --material, or their defaults)",
        path, stack.filename().string(), layers, material.name);
  }
  return std::move(file.design);
}

std::string describe_stack(const LayerStack& stack) {
  const auto [thinnest, thickest] = printed_thickness_range(stack);
  std::string materials;
  for (const Material& m : stack.materials) {
    materials += (materials.empty() ? "" : ", ") + m.name;
  }
  const std::string thickness = thickest - thinnest < 0.005
                                    ? fmt::format("{:.3g} mm", thickest)
                                    : fmt::format("{:.3g} to {:.3g} mm", thinnest, thickest);
  return fmt::format("{} layers ({} printed) of {}", stack.num_layers(), thickness, materials);
}

}  // namespace flatmorph::cli
