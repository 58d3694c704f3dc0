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
namespace {

// The faces of a convex solid whose every face is a regular triangle of side `edge`: the triples of
// vertices pairwise `edge` apart.
std::vector<std::vector<int>> triangles_of_side(const Eigen::MatrixX3d& V, double edge) {
  const auto is_edge = [&](int a, int b) {
    return std::abs((V.row(a) - V.row(b)).norm() - edge) < 1e-9 * edge;
  };
  std::vector<std::vector<int>> faces;
  const int n = static_cast<int>(V.rows());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (!is_edge(a, b)) continue;
      for (int c = b + 1; c < n; ++c) {
        if (is_edge(a, c) && is_edge(b, c)) faces.push_back({a, b, c});
      }
    }
  }
  return faces;
}

// Each face of a convex solid centred at the origin ordered counter-clockwise seen from outside
// (its vertices by angle about the outward direction of its centroid).
void orient_convex_faces(const Eigen::MatrixX3d& V, std::vector<std::vector<int>>& faces) {
  for (std::vector<int>& face : faces) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int v : face) centre += V.row(v).transpose();
    centre /= static_cast<double>(face.size());
    const Eigen::Vector3d out = centre.normalized();
    const Eigen::Vector3d x = (V.row(face[0]).transpose() - centre).normalized();
    const Eigen::Vector3d y = out.cross(x);
    std::vector<std::pair<double, int>> by_angle;
    for (int v : face) {
      const Eigen::Vector3d d = V.row(v).transpose() - centre;
      by_angle.push_back({std::atan2(d.dot(y), d.dot(x)), v});
    }
    std::sort(by_angle.begin(), by_angle.end());
    for (size_t i = 0; i < face.size(); ++i) face[i] = by_angle[i].second;
  }
}

Polyhedron scaled_to_edge(Eigen::MatrixX3d V, std::vector<std::vector<int>> faces, double unit_edge,
                          double edge_mm, const std::string& name) {
  orient_convex_faces(V, faces);
  Polyhedron solid;
  solid.V = V * (edge_mm / unit_edge);
  solid.faces = std::move(faces);
  solid.source = fmt::format("example {}", name);
  return solid;
}

Eigen::MatrixX3d icosahedron_vertices() {
  const double phi = std::numbers::phi;
  Eigen::MatrixX3d V(12, 3);
  int i = 0;
  for (double s : {-1.0, 1.0}) {
    for (double t : {-phi, phi}) {
      V.row(i++) << 0, s, t;
      V.row(i++) << s, t, 0;
      V.row(i++) << t, 0, s;
    }
  }
  return V;
}

}  // namespace

std::vector<std::string> polyhedron_example_names() {
  return {"tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron", "pyramid"};
}

Polyhedron polyhedron_example(const std::string& name, double edge_mm) {
  if (!(edge_mm > 0) || !std::isfinite(edge_mm)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("example {}: edge length {} mm; give a positive length", name, edge_mm));
  }
  if (name == "tetrahedron") {
    Eigen::MatrixX3d V(4, 3);
    V << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
    return scaled_to_edge(V, triangles_of_side(V, 2 * std::numbers::sqrt2), 2 * std::numbers::sqrt2,
                          edge_mm, name);
  }
  if (name == "octahedron") {
    Eigen::MatrixX3d V(6, 3);
    V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
    return scaled_to_edge(V, triangles_of_side(V, std::numbers::sqrt2), std::numbers::sqrt2,
                          edge_mm, name);
  }
  if (name == "icosahedron") {
    const Eigen::MatrixX3d V = icosahedron_vertices();
    return scaled_to_edge(V, triangles_of_side(V, 2), 2, edge_mm, name);
  }
  if (name == "cube") {
    Eigen::MatrixX3d V(8, 3);
    for (int i = 0; i < 8; ++i) V.row(i) << (i & 1 ? 1 : -1), (i & 2 ? 1 : -1), (i & 4 ? 1 : -1);
    std::vector<std::vector<int>> faces;
    for (int axis = 0; axis < 3; ++axis) {
      for (double side : {-1.0, 1.0}) {
        std::vector<int> face;
        for (int i = 0; i < 8; ++i) {
          if (V(i, axis) == side) face.push_back(i);
        }
        faces.push_back(face);
      }
    }
    return scaled_to_edge(V, faces, 2, edge_mm, name);
  }
  if (name == "dodecahedron") {
    // The icosahedron's dual: a vertex at each of its faces' centroids, a face around each of its
    // vertices.
    const Eigen::MatrixX3d I = icosahedron_vertices();
    const std::vector<std::vector<int>> triangles = triangles_of_side(I, 2);
    Eigen::MatrixX3d V(static_cast<Eigen::Index>(triangles.size()), 3);
    std::vector<std::vector<int>> faces(I.rows());
    for (size_t t = 0; t < triangles.size(); ++t) {
      V.row(static_cast<Eigen::Index>(t)) =
          (I.row(triangles[t][0]) + I.row(triangles[t][1]) + I.row(triangles[t][2])) / 3;
      for (int v : triangles[t]) faces[v].push_back(static_cast<int>(t));
    }
    Polyhedron solid = scaled_to_edge(V, faces, 1, 1, name);
    // Its edge: two consecutive vertices of a face, now that each face is ordered.
    const std::vector<int>& first = solid.faces[0];
    solid.V *= edge_mm / (solid.V.row(first[0]) - solid.V.row(first[1])).norm();
    return solid;
  }
  if (name == "pyramid") {
    Eigen::MatrixX3d V(5, 3);
    V << 1, 1, 0, -1, 1, 0, -1, -1, 0, 1, -1, 0, 0, 0, std::numbers::sqrt2;
    // Centred so that the faces' outward directions point away from the origin.
    V.col(2).array() -= std::numbers::sqrt2 / 4;
    return scaled_to_edge(V, {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}, 2, edge_mm,
                          name);
  }
  throw UserError(ErrorCategory::kOption,
                  fmt::format("no example solid '{}'; the examples are {}", name,
                              fmt::join(polyhedron_example_names(), ", ")));
}

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

}  // namespace flatmorph
