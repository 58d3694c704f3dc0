// The lattice that joins tiles printed apart (CHI 2019 §4 "mesh connection", Fig. 4, 5, 16; notes
// §6.2): the sheet's outline (given, or the tiles' convex hull grown by a margin) minus the tiles,
// filled with straight lines of two families (along x on odd layers, along y on even ones) that
// run a little into each tile's rim so that the tile bonds. Millimetres, mm/s.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "methods/tiles/tile_layout.h"
#include "methods/tiles/tile_passes.h"

namespace flatmorph {

struct TileLattice {
  // The lattice's area between the tiles, as regions for the sheet's mesh: the sheet outline with
  // the tiles as holes (one or more pieces).
  std::vector<TileOutline> regions;
  std::vector<LatticePass> passes;  // layer l at z = l · layer height
  double fill = 0;                  // the share of the area one family's lines cover (w / spacing)
  int lines = 0;                    // printed lines over all layers
};

// The lattice of `spec` around `tiles` (their outlines), printed `pitch` mm wide with tool
// `tool`. Throws UserError (kGeometry) when the sheet outline leaves no room between the tiles,
// kOption for a spacing below the pitch.
TileLattice tile_lattice(const std::vector<TileOutline>& tiles, const LatticeSpec& spec,
                         double pitch, int tool);

}  // namespace flatmorph
