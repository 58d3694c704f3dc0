#include "methods/tiles/outline_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <system_error>

#include "common/error.h"
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
  std::error_code error;
  // A folder opens as a stream on Linux, with a nonsense size.
  if (std::filesystem::is_directory(path, error)) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: a folder, not a file: give the path of the drawing", source));
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: cannot open the file: check the path and its permissions", source));
  }
  const std::streamoff size = in.tellg();
  if (size < 0) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: cannot read the file: check that it is a regular file", source));
  }
  outline_loops::check_size(static_cast<size_t>(size), options, source);
  std::string text(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size()))) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: cannot read the file: check that it is a regular file", source));
  }
  if (extension == ".dxf") return read_dxf_outlines(text, source, options, warnings);
  return read_svg_outlines(text, source, options, warnings);
}

}  // namespace flatmorph
