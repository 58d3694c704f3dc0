// Tile outlines from a drawing file (Geodesy CHI 2019 §6: outlines drawn in CAD): ASCII DXF or
// SVG, chosen by the file's extension. Millimetres, plate coordinates (y up).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "methods/tiles/outline_loops.h"
#include "methods/tiles/tile_outline.h"

namespace flatmorph {

// read_dxf_outlines for a .dxf file, read_svg_outlines for a .svg file (the extension in any
// case); the path names the file in messages. Throws UserError: kFormat for another extension
// (naming the two read), kFile when the file cannot be opened or read (or is a folder), kResource
// when it is larger than options.max_bytes, and whatever the reader throws.
std::vector<TileOutline> read_tile_outlines(const std::filesystem::path& path,
                                            const OutlineReadOptions& options = {},
                                            std::vector<std::string>* warnings = nullptr);

}  // namespace flatmorph
