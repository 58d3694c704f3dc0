#include "examples/tile_examples.h"

#include <fmt/core.h>

#include <cmath>
#include <numbers>

#include "common/error.h"

namespace flatmorph {

std::vector<ExampleInfo> tile_example_list() {
  return {{"dome", "one 40 mm disc rising into a spherical cap 12 mm high"},
          {"spin-top", "one 60 mm disc rising into an 18 mm cone (CHI 2019 Fig. 11a)"},
          {"coaster", "3 x 3 squares of 25 mm rising into 5 mm cones to alternate sides (Fig. 15)"},
          {"bracelet", "a strip of six 20 mm hexagons joined by a lattice (Fig. 16)"}};
}

std::vector<std::string> tile_example_names() {
  std::vector<std::string> names;
  for (const ExampleInfo& info : tile_example_list()) names.push_back(info.name);
  return names;
}

TileLayout tile_layout_example(const std::string& name) {
  TileLayout layout;
  layout.source = "example " + name;
  auto add = [&](Eigen::MatrixX2d boundary, const std::string& profile, double height, int side) {
    TileSpec tile;
    tile.outline.boundary = std::move(boundary);
    tile.outline.source = fmt::format("{}: tile {}", layout.source, layout.tiles.size());
    tile.profile = profile;
    tile.height_mm = height;
    tile.side = side;
    layout.tiles.push_back(tile);
  };
  if (name == "dome") {
    add(circle_polygon({0, 0}, 20), "spherical-cap", 12, +1);
  } else if (name == "spin-top") {
    add(circle_polygon({0, 0}, 30), "cone", 18, +1);
  } else if (name == "coaster") {
    const double side = 25;
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) {
        Eigen::MatrixX2d square(4, 2);
        const double x = (col - 1.5) * side, y = (row - 1.5) * side;
        square << x, y, x + side, y, x + side, y + side, x, y + side;
        // Alternate sides, as the paper's coaster does, so that the sheet as a whole stays flat.
        add(square, "cone", 5, (row + col) % 2 == 0 ? +1 : -1);
      }
    }
  } else if (name == "bracelet") {
    const double radius = 10, gap = 4;  // hexagons 20 mm across their corners
    const double pitch = 2 * radius * std::cos(std::numbers::pi / 6) + gap;
    for (int i = 0; i < 6; ++i) {
      Eigen::MatrixX2d hexagon(6, 2);
      for (int k = 0; k < 6; ++k) {
        const double a = std::numbers::pi / 6 + k * std::numbers::pi / 3;
        hexagon.row(k) << (i - 2.5) * pitch + radius * std::cos(a), radius * std::sin(a);
      }
      add(hexagon, "cone", 4, +1);
    }
    layout.has_lattice = true;
    layout.lattice.margin_mm = 3;
    layout.lattice.spacing_mm = 2.5;
  } else {
    std::string names;
    for (const std::string& n : tile_example_names()) names += (names.empty() ? "" : ", ") + n;
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown tile example '{}': choose one of {}", name, names));
  }
  return layout;
}

}  // namespace flatmorph
