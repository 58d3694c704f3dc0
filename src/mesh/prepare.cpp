#include "mesh/prepare.h"

#include <fmt/core.h>

#include <cmath>

#include "common/error.h"
#include "mesh/subdivide.h"
#include "mesh/validate.h"

namespace flatmorph {

BoundingBox bounding_box(const Eigen::MatrixXd& V) {
  if (V.rows() == 0) return {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  return {V.colwise().minCoeff().transpose(), V.colwise().maxCoeff().transpose()};
}

double scale_to_size(Mesh& mesh, double size_mm) {
  if (!std::isfinite(size_mm) || size_mm <= 0.0) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("size: {} mm is not a positive size; give the plate's largest "
                                "extent in millimetres, e.g. 100",
                                size_mm));
  }
  const BoundingBox box = bounding_box(mesh.V);
  const double extent = box.extent().maxCoeff();
  if (!std::isfinite(extent) || !(extent > 0.0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("mesh: the bounding box has largest extent {}, so it cannot be "
                                "scaled; check the vertices' coordinates",
                                extent));
  }
  const double scale = size_mm / extent;
  const Eigen::RowVector3d centre = 0.5 * (box.min + box.max).transpose();
  mesh.V = ((mesh.V.rowwise() - centre) * scale).rowwise() + centre;
  return scale;
}

PreparedTarget prepare_target(Mesh mesh, const std::string& source, int min_faces) {
  repair_mesh(mesh);
  require_disk(mesh, source);
  PreparedTarget out;
  out.input_faces = mesh.num_faces();
  out.mesh = loop_subdivide_to(mesh, min_faces).mesh;
  return out;
}

}  // namespace flatmorph
