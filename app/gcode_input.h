// The materials and the printer a G-code file is read with (check, simulate): given as options or
// named by the file's header.
#pragma once

#include <string>
#include <vector>

#include "gcode/gcode_reader.h"
#include "gcode/printer_profile.h"
#include "material/material.h"

namespace flatmorph::cli {

// "pla-paper,tpu-generic": one material per tool, T0 first (--material). UserError (kOption) for
// an empty name, load_material's for an unknown one.
std::vector<Material> load_tool_materials(const std::string& list);

// The materials the header names, one per tool, each with the shrink model the header gives for
// its tool when it gives one (GcodeHeaderInfo::tool_shrink: the ratios and curves the file was
// designed with); empty when it names none. UserError (kOption) naming `file` for a name that is
// no preset.
std::vector<Material> header_tool_materials(const GcodeHeaderInfo& header, const std::string& file);

// The printer the header names. UserError (kOption) naming `file` when it names none or one that
// is no preset: the user then gives --printer.
PrinterProfile header_printer(const GcodeHeaderInfo& header, const std::string& file);

}  // namespace flatmorph::cli
