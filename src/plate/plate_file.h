// The flat.ply file every design method writes and every later stage reads: the plate (2D, z = 0,
// mm) with its print directions.
#pragma once

#include <Eigen/Core>
#include <filesystem>

namespace flatmorph {

struct PlateFile {
  Eigen::MatrixXd plate;   // #V x 2, mm, counter-clockwise triangles
  Eigen::MatrixXi F;       // #F x 3
  Eigen::VectorXd theta1;  // per face, rad: the mean print direction
  Eigen::VectorXd theta2;  // per vertex, rad: its change through the thickness (0 when absent)
};

// Reads flat.ply: per-face property `theta1` is required, per-vertex `theta2` optional. Throws
// UserError naming the file when it is not a flat plate with these properties.
PlateFile read_plate_file(const std::filesystem::path& path);

}  // namespace flatmorph
