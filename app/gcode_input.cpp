#include "gcode_input.h"

#include <fmt/core.h>

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
