// Scaling a target surface to millimetres.
#pragma once

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace flatmorph {

struct BoundingBox {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
  Eigen::Vector3d extent() const { return max - min; }
  double diagonal() const { return extent().norm(); }
};

BoundingBox bounding_box(const Eigen::MatrixXd& V);

// Uniformly scales V about its bounding-box centre, then translates so the centre stays put, so that
// the largest bounding-box extent equals `size_mm`. Returns the scale factor applied.
double scale_to_size(Mesh& mesh, double size_mm);

}  // namespace flatmorph
