#include "methods/tiles/outline_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cstdint>

#include "common/error.h"
#include "common/file_text.h"
#include "methods/tiles/dxf_outlines.h"
#include "methods/tiles/svg_outlines.h"

namespace flatmorph {

std::vector<TileOutline> read_tile_outlines(const std::filesystem::path& path,
                                            const OutlineReadOptions& options,
                                            std::vector<std::string>* warnings) {
  const std::string source = path.string();
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".dxf" && extension != ".svg") {
    throw UserError(
        ErrorCategory::kFormat,
        fmt::format("{}: tile outlines are read from .dxf (ASCII DXF) and .svg files, not {}: "
                    "export the outlines from the drawing program as DXF or SVG{}",
                    source, extension.empty() ? "a file without extension" : "'" + extension + "'",
                    extension == ".svgz" ? " (plain, not compressed)" : ""));
  }
  const std::string text = read_file_text(path, "file", [&](std::uintmax_t size) {
    outline_loops::check_size(static_cast<size_t>(size), options, source);
  });
  if (extension == ".dxf") return read_dxf_outlines(text, source, options, warnings);
  return read_svg_outlines(text, source, options, warnings);
}

}  // namespace flatmorph
