// A designed plate, as every design method ends and every later stage starts (DESIGN.md): the flat
// mesh, its layer stack and the materials it uses. On disk it is one file set: the plate mesh
// (flat.ply: z = 0, mm; per-face properties for what varies over the plate) and a small stack file
// beside it (flat.stack.json: layer count, thicknesses, materials, and each layer's per-face
// quantities either as one value or as the name of a per-face property of the PLY). docs/plate.md
// describes the format.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "mesh/mesh.h"
#include "plate/layer_stack.h"

namespace flatmorph {

struct PlateDesign {
  Eigen::MatrixXd plate;  // #V x 2, mm, counter-clockwise faces
  Eigen::MatrixXi F;      // #F x 3
  LayerStack stack;       // what is printed: one Layer per printed layer, bed first
  // The design method that made it ("shrink_morph", ...) and its own design variables, kept for
  // the record and for pictures (Shrink & Morph: per-face theta1, per-vertex theta2, rad); later
  // stages read only the stack.
  std::string method;
  MeshProperties design_fields;
};

// The stack file that goes with a plate mesh: `flat.ply` -> `flat.stack.json`.
std::filesystem::path stack_file_path(const std::filesystem::path& plate_mesh_path);

// Writes the plate mesh (PLY, atomically) and its stack file. Throws UserError (kFile) naming the
// file when it cannot write, and check_layer_stack's errors for an inconsistent stack.
void write_plate_design(const std::filesystem::path& plate_mesh_path, const PlateDesign& design);

// Reads a plate mesh and its stack file. A mesh without a stack file (written by an older version,
// or by hand) is read as a Shrink & Morph design from its per-face `theta1` and per-vertex `theta2`
// (0 when absent) with `fallback_layers` layers of `fallback_material`, and `from_stack_file` is
// false so that the caller can say so. Throws UserError naming the file for a mesh that is not a
// flat plate, a stack file that does not match it (face count, missing property, bad value) and
// what to do.
struct PlateDesignFile {
  PlateDesign design;
  bool from_stack_file = false;
};
PlateDesignFile read_plate_design(const std::filesystem::path& plate_mesh_path,
                                  const Material& fallback_material, int fallback_layers);

}  // namespace flatmorph
