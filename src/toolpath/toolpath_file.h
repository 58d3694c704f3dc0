// A run's toolpath as data (DIR/toolpath.json), so that reports and viewers read what was printed
// without parsing G-code: per layer its z and height, per path its type, tool, width and the xy
// points (mm, plate frame as in flat.ply, rounded to 1 µm), and the print's summary (the G-code
// header's key/value lines: print time, filament, printer, materials). docs/report.md.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "toolpath/toolpath.h"

namespace flatmorph {

struct ToolpathFile {
  std::vector<std::pair<std::string, std::string>> summary;
  Toolpath toolpath;  // every segment of a path carries the path's first segment's style
};

// Writes the file atomically. Deterministic.
void write_toolpath_file(const std::filesystem::path& path, const Toolpath& toolpath,
                         const std::vector<std::pair<std::string, std::string>>& summary);

// Reads it back; throws UserError naming the file (kFile when it cannot be read, kFormat when it
// is not a toolpath file or a value is missing or not finite).
ToolpathFile read_toolpath_file(const std::filesystem::path& path);

// The value of a summary key, or "" when absent.
std::string summary_value(const ToolpathFile& file, const std::string& key);

}  // namespace flatmorph
