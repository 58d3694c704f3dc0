// A tile's side profile as an SVG plot (CHI 2019 Fig. 17 draws the same comparison on photos):
// the profile asked, the one its printed (clamped) shrink gives geometrically, and the simulated
// one, radius against height at one scale. Millimetres.
#pragma once

#include <string>

#include "methods/tiles/design_tiles.h"

namespace flatmorph {

// A standalone SVG document (any browser or vector editor opens it).
std::string profile_plot_svg(const TileMeasure& measure, const std::string& title);

}  // namespace flatmorph
