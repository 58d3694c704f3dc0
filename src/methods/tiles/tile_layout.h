// What a user asks of a sheet of Geodesy tiles (CHI 2019 §4, §6, Fig. 7): each tile's outline,
// side profile, height, rising side and hole, and the lattice ("mesh connection") that joins
// tiles printed apart. Tiles whose outlines share an edge are joined directly (printed edge to
// edge). Read from a JSON layout, from a drawing (DXF, SVG) with one setting for every tile, or
// built in. Millimetres.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "methods/tiles/tile_outline.h"

namespace flatmorph {

struct TileSpec {
  TileOutline outline;
  // A profile of the library (tile_profile.h: "spherical-cap", "cone", ...) or, when
  // profile_csv is set, the user's (r, z) meridian read from that file.
  std::string profile = "spherical-cap";
  std::filesystem::path profile_csv;
  double height_mm = 0;       // of the risen tile above its rim; 0: the library profile's own
  int side = +1;              // +1 rises toward +z (away from the bed), −1 toward the bed
  double hole_radius_mm = 0;  // rings nearer the centre than this are left out (CHI 2019 Fig. 7)
};

// A printed lattice between the tiles (CHI 2019 §4 "mesh connection", Fig. 4, 5): straight lines
// in two families (0° and 90°) clipped to the sheet minus the tiles, overlapping each tile's rim
// so that it bonds.
struct LatticeSpec {
  Eigen::MatrixX2d
      outline;  // the sheet's outline (CCW, mm); empty: the tiles' hull grown by margin
  double margin_mm = 3;
  double spacing_mm = 3;                 // between the lines of a family
  double overlap_mm = -1;                // into each tile (<0: half the path width)
  std::string material = "pla-geodesy";  // preset or file; a second material prints with tool 1
  double layer_height_mm = 0.2;
  int layers = 3;
  double feed_rate = 25;  // mm/s: the paper prints its meshes at 1500 mm/min
};

struct TileLayout {
  std::vector<TileSpec> tiles;
  bool has_lattice = false;
  LatticeSpec lattice;
  std::string source;  // for messages
};

// A JSON layout (docs/tiles.md): {"outlines": "FILE.dxf|svg" (optional), "defaults": {...},
// "tiles": [{"circle": {"center": [x, y], "radius": r} | "polygon": [[x, y], ...] |
// "index": i (the drawing's i-th outline), "profile", "profile_csv", "height", "side": "up" or
// "down", "hole"}], "lattice": {...}}. Relative paths are relative to the layout's folder. Throws
// UserError naming `source` and the key for anything it cannot use.
TileLayout read_tile_layout(std::string_view json_text, const std::string& source,
                            const std::filesystem::path& base_dir);

// The layout a file gives: a .json layout, or a drawing (.dxf, .svg) whose every outline becomes
// a tile with `defaults` (its outline replaced).
TileLayout load_tile_layout(const std::filesystem::path& path, const TileSpec& defaults);


// A circle of `radius` (mm) around `center` as a polygon whose chords stray at most
// `chord_tolerance` mm from it (at least 24 sides), counter-clockwise.
Eigen::MatrixX2d circle_polygon(const Eigen::Vector2d& center, double radius,
                                double chord_tolerance = 0.01);

}  // namespace flatmorph
