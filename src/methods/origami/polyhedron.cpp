#include "methods/origami/polyhedron.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "common/error.h"

namespace flatmorph {

std::vector<PolyhedronEdge> polyhedron_edges(const Polyhedron& solid) {
  const int num_vertices = static_cast<int>(solid.V.rows());
  std::map<std::pair<int, int>, int> index;  // (min, max) vertex → edge
  std::vector<PolyhedronEdge> edges;
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    const std::vector<int>& face = solid.faces[f];
    if (face.size() < 3) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: face {} has {} vertices; a face needs at least three",
                                  solid.source, f, face.size()));
    }
    for (size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (a < 0 || a >= num_vertices || b < 0 || b >= num_vertices || a == b) {
        throw UserError(
            ErrorCategory::kGeometry,
            fmt::format("{}: face {} names vertex {} of {} (or one twice in a row)", solid.source,
                        f, a < 0 || a >= num_vertices ? a : b, num_vertices));
      }
      const auto key = std::minmax(a, b);
      const auto found = index.find(key);
      if (found == index.end()) {
        index.emplace(key, static_cast<int>(edges.size()));
        edges.push_back({a, b, static_cast<int>(f), -1});
        continue;
      }
      PolyhedronEdge& edge = edges[found->second];
      if (edge.right >= 0) {
        throw UserError(ErrorCategory::kTopology,
                        fmt::format("{}: the edge between vertices {} and {} has three or more "
                                    "faces ({}, {} and {}); a folded sheet needs at most two",
                                    solid.source, key.first, key.second, edge.left, edge.right, f));
      }
      if (edge.v0 == a) {
        throw UserError(ErrorCategory::kTopology,
                        fmt::format("{}: faces {} and {} run their shared edge ({}, {}) the same "
                                    "way; orient every face counter-clockwise seen from outside",
                                    solid.source, edge.left, f, a, b));
      }
      edge.right = static_cast<int>(f);
    }
  }
  return edges;
}

Eigen::Vector3d face_normal(const Polyhedron& solid, int f) {
  const std::vector<int>& face = solid.faces[f];
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < face.size(); ++i) {
    const Eigen::Vector3d a = solid.V.row(face[i]).transpose();
    const Eigen::Vector3d b = solid.V.row(face[(i + 1) % face.size()]).transpose();
    n += a.cross(b);
  }
  return n.normalized();
}

double fold_angle(const Polyhedron& solid, const PolyhedronEdge& edge) {
  if (edge.right < 0) return 0;
  const Eigen::Vector3d na = face_normal(solid, edge.left), nb = face_normal(solid, edge.right);
  const double magnitude = std::atan2(na.cross(nb).norm(), na.dot(nb));
  // Convex where face right bends away from face left's outward side (notes §3).
  const Eigen::Vector3d p = solid.V.row(edge.v0).transpose();
  double offset = 0;
  for (int v : solid.faces[edge.right]) offset += (solid.V.row(v).transpose() - p).dot(na);
  return offset < 0 ? -magnitude : magnitude;
}

std::string polyhedron_obj(const Polyhedron& solid) {
  std::string out = "# flatmorph origami: the solid the sheets fold into, mm\n";
  for (Eigen::Index v = 0; v < solid.V.rows(); ++v) {
    out += fmt::format("v {} {} {}\n", solid.V(v, 0), solid.V(v, 1), solid.V(v, 2));
  }
  for (const std::vector<int>& face : solid.faces) {
    out += "f";
    for (int v : face) out += fmt::format(" {}", v + 1);
    out += "\n";
  }
  return out;
}

}  // namespace flatmorph
