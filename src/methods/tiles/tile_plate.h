// The printed sheet of Geodesy tiles as the shared simulator reads it (notes §7.2): a triangle mesh
// conforming to every tile (sheet_mesh.h), and per face the layers its ring prints: the ring
// tangent as the deposition direction, the bilayer's layer heights and counts (tile_levels.h),
// λ1 from the thickness curve at each layer height. Faces of the lattice print its lines: layers
// of the lattice's material at their full height covering `fill` of the area (Layer::cover).
// Millimetres and radians.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "material/material.h"
#include "mesh/sheet_mesh.h"
#include "methods/tiles/tile_levels.h"
#include "methods/tiles/tile_outline.h"
#include "plate/plate_design.h"

namespace flatmorph {

struct TilePlateLattice {
  Material material;
  double layer_height = 0.2;  // mm
  int layers = 3;
  double fill = 0.25;  // the share of the area its lines cover (path width / spacing per family)
};

struct TilePlate {
  PlateDesign design;          // method "tiles"; design_fields: tile, level, shrinkage, direction
  Eigen::VectorXi face_tile;   // per face: the tile it lies in, −1 on the lattice
  Eigen::VectorXi face_level;  // per face: its ring level, −1 on the lattice
  Eigen::VectorXd
      vertex_depth;             // per vertex: distance to its tile's outline, mm (0 on the lattice)
  Eigen::VectorXi vertex_tile;  // per vertex: a tile it belongs to (−1: lattice only)
};

// `mesh` faces labelled by region: regions 0..#tiles−1 are the tiles (outlines[i] with levels[i]),
// a region beyond them the lattice. `pitch` is the ring spacing (mm). Throws UserError for a
// material without a thickness curve.
TilePlate tile_plate(const SheetMesh& mesh, const std::vector<TileOutline>& outlines,
                     const std::vector<TileLevels>& levels, double pitch, const Material& material,
                     const TilePlateLattice* lattice);

// The simulation's start: the flat sheet with each tile bulged a little toward its side
// (z = side · 0.02 · depth), so that every tile leaves the flat, unstable state on the side its
// bilayer programs (in the paper's water, a trigger force; CHI 2019 §7).
Eigen::MatrixXd tile_start(const TilePlate& plate, const std::vector<TileLevels>& levels);

}  // namespace flatmorph
