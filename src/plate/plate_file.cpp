#include "plate/plate_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdint>

#include "common/error.h"
#include "common/memory.h"
#include "mesh/io.h"

namespace flatmorph {

PlateFile read_plate_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  MeshFile file = read_mesh(path);
  if (file.mesh.num_vertices() == 0 || file.mesh.num_faces() == 0) {
    throw UserError(ErrorCategory::kFormat, fmt::format("{}: the plate has no faces", name));
  }
  // Simulating or tracing a plate takes far more memory than reading it: refuse it up front.
  require_memory(
      static_cast<std::uint64_t>(file.mesh.num_faces()) * kDesignBytesPerFace,
      fmt::format("{}: simulating or printing this plate of {} faces", name, file.mesh.num_faces()),
      "design a coarser plate (flatmorph flatten/design --faces)");
  const double extent =
      (file.mesh.V.colwise().maxCoeff() - file.mesh.V.colwise().minCoeff()).head<2>().maxCoeff();
  if (!file.mesh.V.allFinite() ||
      file.mesh.V.col(2).cwiseAbs().maxCoeff() > 1e-9 * std::max(extent, 1.0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the plate is not flat (z != 0); pass the flat.ply written by "
                                "'flatmorph flatten' or 'flatmorph design'",
                                name));
  }
  const Eigen::VectorXd* theta1 = file.properties.find_face("theta1");
  if (theta1 == nullptr) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no per-face property 'theta1' (the print direction in "
                                "radians); pass the flat.ply written by 'flatmorph flatten' or "
                                "'flatmorph design'",
                                name));
  }
  PlateFile p;
  p.F = file.mesh.F;
  p.plate = file.mesh.V.leftCols(2);
  p.theta1 = *theta1;
  const Eigen::VectorXd* theta2 = file.properties.find_vertex("theta2");
  p.theta2 = theta2 ? *theta2 : Eigen::VectorXd::Zero(p.plate.rows());
  if (!p.theta1.allFinite() || !p.theta2.allFinite()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: theta1 or theta2 holds NaN or infinite values", name));
  }
  return p;
}

}  // namespace flatmorph
