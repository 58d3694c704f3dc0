// The built-in tile layouts of `flatmorph tiles --example` (Geodesy, CHI 2019), generated so that
// the method runs without files. Millimetres.
#pragma once

#include <string>
#include <vector>

#include "examples/examples.h"
#include "methods/tiles/tile_layout.h"

namespace flatmorph {

// "dome", "spin-top", "coaster", "bracelet", in that order, with a line each.
std::vector<ExampleInfo> tile_example_list();
std::vector<std::string> tile_example_names();

// The built-in layouts: dome (one 40 mm disc rising into a spherical cap 12 mm high), spin-top
// (one 60 mm disc rising into a cone, CHI 2019 Fig. 11a), coaster (3 x 3 squares of 25 mm joined
// edge to edge, rising into 5 mm cones to alternate sides so that the sheet stays flat, Fig. 15),
// bracelet (a strip of six 20 mm hexagons joined by a lattice, Fig. 16). Throws UserError (kOption)
// for an unknown name, listing the names.
TileLayout tile_layout_example(const std::string& name);

}  // namespace flatmorph
