// Preparing a target surface for design: repair, disk check, refinement, scaling to millimetres.
#pragma once

#include <Eigen/Core>
#include <string>

#include "mesh/mesh.h"

namespace flatmorph {

struct BoundingBox {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
  Eigen::Vector3d extent() const { return max - min; }
  double diagonal() const { return extent().norm(); }
};

BoundingBox bounding_box(const Eigen::MatrixXd& V);

// Uniformly scales V about its bounding-box centre, then translates so the centre stays put, so
// that the largest bounding-box extent equals `size_mm`. Returns the scale factor applied.
double scale_to_size(Mesh& mesh, double size_mm);

// A target surface made ready for flattening: repaired (repair_mesh), checked to be a disk
// (require_disk; `source` names it in the error) and Loop-subdivided until it has at least
// `min_faces` faces. Units are left as they are.
struct PreparedTarget {
  Mesh mesh;
  int input_faces = 0;  // after repair, before subdivision
};
PreparedTarget prepare_target(Mesh mesh, const std::string& source, int min_faces);

}  // namespace flatmorph
