#include "gcode_input.h"

#include <fmt/core.h>

#include <algorithm>

#include "common/error.h"

namespace flatmorph::cli {

std::vector<Material> load_tool_materials(const std::string& list) {
  std::vector<Material> materials;
  size_t begin = 0;
  while (true) {
    const size_t comma = list.find(',', begin);
    const std::string name = list.substr(begin, comma - begin);
    if (name.empty()) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("--material \"{}\" has an empty name: give one material per "
                                  "tool, comma-separated, e.g. pla-paper,tpu-generic",
                                  list));
    }
    materials.push_back(load_material(name));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return materials;
}

std::vector<Material> header_tool_materials(const GcodeHeaderInfo& header,
                                            const std::string& file) {
  std::vector<Material> materials;
  for (const std::string& name : header.tool_materials) {
    try {
      materials.push_back(load_material(name));
      // The shrink model the file was designed with, when its header gives it (an origami
      // print's PLA is the hinge model's, not the preset's Shrink & Morph ratios).
      const size_t tool = materials.size() - 1;
      if (tool < header.tool_shrink.size() && header.tool_shrink[tool]) {
        const HeaderShrinkModel& said = *header.tool_shrink[tool];
        Material& m = materials.back();
        m.lambda1 = said.lambda1;
        m.lambda2 = said.lambda2;
        m.lambda3 = said.lambda3;
        m.delta_lambda1 = said.delta_lambda1;
        m.speed_curve = said.speed_curve;
        m.thickness_curve = said.thickness_curve;
        if (m.speed_curve) {  // the ratios stand for a speed within the curve's range
          m.print_speed = std::clamp(m.print_speed, m.speed_curve->min_print_speed,
                                     m.speed_curve->max_print_speed);
        }
      }
    } catch (const UserError&) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: the file was printed with the material \"{}\", which is "
                                  "no preset of flatmorph: give --material (flatmorph materials "
                                  "lists them)",
                                  file, name));
    }
  }
  return materials;
}

PrinterProfile header_printer(const GcodeHeaderInfo& header, const std::string& file) {
  if (header.printer.empty()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: the file does not name its printer: give --printer (a "
                                "preset name, see flatmorph printers, or a profile JSON file)",
                                file));
  }
  try {
    return load_printer(header.printer);
  } catch (const UserError&) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: the file was made for the printer \"{}\", which is no "
                                "preset of flatmorph: give --printer (a preset or a profile "
                                "JSON file)",
                                file, header.printer));
  }
}

}  // namespace flatmorph::cli
