// The plate a command reads: flat.ply and its stack file (plate/plate_design.h), with the
// --material/--layers options that only a plate without a stack file may take.
#pragma once

#include <optional>
#include <string>

#include "plate/plate_design.h"

namespace CLI {
class App;
}

namespace flatmorph::cli {

// --material / --layers as given.
struct PlateInputOptions {
  std::optional<std::string> material;
  std::optional<int> layers;
};

// Adds `--material` and `--layers` (for a flat.ply without a stack file) to a command.
void add_plate_input_options(CLI::App* command, PlateInputOptions& options);

// Reads the plate. With a stack file, the stack decides: --material or --layers is a UserError
// (kOption) saying so. Without one, the plate is read as a Shrink & Morph design with the options
// (default pla-paper, 10 layers), and `warning` says which were used (for the command to print
// once it has succeeded: an error stays one line).
PlateDesign load_plate_input(const std::string& path, const PlateInputOptions& options,
                             std::string& warning);

// One line: "N layers (T mm) of MATERIAL[, MATERIAL2]" for the progress output.
std::string describe_stack(const LayerStack& stack);

}  // namespace flatmorph::cli
