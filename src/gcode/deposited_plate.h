// What a G-code file printed, as a plate to simulate: the beads read from the file
// (gcode_reader.h) rasterized onto the faces of a flat plate mesh, one Layer of the stack per layer
// of the file (docs/plate.md, docs/gcode.md "From G-code to a plate"). Per face and layer: the
// covered fraction, the axial mean direction of the beads over it (the angle of Σ v e^{2iθ} / 2,
// v the bead volume there), the thickness (the beads' tops above what lies below them), the
// material (the tool that printed most of it) and the print speed. Lengths in mm (bed
// coordinates unless said otherwise), angles in radians from +x, speeds in mm/min.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "gcode/gcode_reader.h"
#include "material/material.h"
#include "plate/plate_design.h"

namespace flatmorph {

struct DepositedPlateOptions {
  // Edge length of the plate mesh built from the first layer's footprint (footprint_plate), mm.
  double resolution_mm = 1.0;
  // A layer covers a face where its beads cover at least this fraction of the face's area; less
  // is treated as stray material (its volume is dropped).
  double min_coverage = 0.25;
  // Beads the file marks as not part of the plate (";TYPE:" skirt, brim, wipe tower, prime pad)
  // are left out.
  bool skip_non_part = true;
};

// Per face of the plate and per layer of the file, what was deposited there.
struct DepositedLayer {
  Eigen::VectorXd coverage;   // fraction of the face's area under a bead, [0, 1]
  Eigen::VectorXd theta;      // axial mean bead direction, rad in (−π/2, π/2]
  Eigen::VectorXd thickness;  // deposited volume over the face's area, mm (smeared)
  Eigen::VectorXi tool;       // the tool with the most covered area (−1 where nothing is)
  Eigen::VectorXd feed_rate;  // mean over the covered area, mm/min
};

// Rasterizes the part's beads onto the plate (V: #V x 2 bed coordinates, mm; F: #F x 3). Each
// face is sampled at the centroids of its m x m equal sub-triangles, m such that they are about a
// third of the typical bead width apart; a sample is under a bead when it lies within half the
// bead's width of its axis.
std::vector<DepositedLayer> rasterize_deposition(const GcodeDeposition& deposition,
                                                 const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                 const DepositedPlateOptions& options = {});

// The bounding box (bed coordinates, mm) of the part's beads in the lowest layer that has any,
// each widened by half its width: what a plate mesh is placed by. Empty when the file has no part
// bead.
Eigen::AlignedBox2d first_layer_bounds(const GcodeDeposition& deposition,
                                       const DepositedPlateOptions& options = {});

// The part's own frame on the bed: the centroid of its first layer's beads (each bead as its
// length × width rectangle) and their principal axis of greatest extent, pointing to the side their
// area is skewed to (for a part symmetric about its centre, toward the bed's +x, or +y when
// across it). It turns and moves with the file, so a plate meshed in it does too. Origin in bed
// coordinates, mm; angle of the part's x axis from the bed's +x, rad. The bed's frame when the
// file has no part bead.
struct PartFrame {
  Eigen::Vector2d origin{0, 0};
  double angle = 0;
};
PartFrame first_layer_frame(const GcodeDeposition& deposition,
                            const DepositedPlateOptions& options = {});

// The plate mesh of a file printed without one, the first layer's footprint: a lattice laid in
// the part's frame over the extent of its first layer's beads (each widened by half its width),
// with as many cells along each axis as make them about `options.resolution_mm` (so the cells of
// a rectangular part fit it exactly); the cells the first layer covers at least half of, each
// split into two triangles (diagonals alternating), the largest edge-connected piece kept. #V x 2
// bed coordinates. Throws UserError when the file has no part bead, or when the first layer
// covers no cell by half (beads sparser than the resolution, a lattice's lines far apart).
struct FootprintMesh {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  PartFrame frame;  // the frame the lattice was laid in
};
FootprintMesh footprint_plate(const GcodeDeposition& deposition, const std::string& source,
                              const DepositedPlateOptions& options = {});

// The stack of what was deposited (one Layer per layer of the file that covers any face), as a
// PlateDesign with method "gcode" on the plate V (#V x 2, bed coordinates; the caller moves it to
// plate coordinates). tool_materials[t] is tool t's material. Each face's layer is as thick as
// its beads are high (the deposited thickness over the coverage) and covers the share of the face
// under them (Layer::cover). The shrink ratios follow each
// material: lambda1 from its thickness curve at the beads' height when it has one (clamped
// to the calibrated range), and the bilayer gradient delta_lambda1 spread over each face's
// thickness of that material as the Shrink & Morph stack builder does (shrink_morph_layer_stack),
// so a file printed from a Shrink & Morph design gives back that design's stack. Faces no layer
// covers are removed (and the vertices only they used), and so are those outside the largest
// edge-connected piece of the rest (it would float free); `removed_faces` counts both. Throws
// UserError naming `source` when a tool has no material or nothing covers the plate.
struct DepositedPlate {
  PlateDesign design;
  std::vector<DepositedLayer> layers;  // on the kept faces
  int removed_faces = 0;
  // Of those, the faces printed on but not joined to the largest piece (a plate of loose pieces).
  int loose_faces = 0;
  Eigen::VectorXi kept_faces;     // index of each kept face in the F given
  Eigen::VectorXi kept_vertices;  // index of each kept vertex in the V given
};
DepositedPlate deposited_plate(const GcodeDeposition& deposition, const Eigen::MatrixXd& V,
                               const Eigen::MatrixXi& F,
                               const std::vector<Material>& tool_materials,
                               const std::string& source,
                               const DepositedPlateOptions& options = {});

}  // namespace flatmorph
