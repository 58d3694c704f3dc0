#include "examples/origami_examples.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "common/error.h"
#include "examples/bunny.h"
#include "methods/origami/design_origami.h"

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

std::vector<ExampleInfo> origami_example_list() {
  return {{"tetrahedron", "regular tetrahedron, 70 mm"},
          {"cube", "cube, 45 mm"},
          {"octahedron", "regular octahedron, 64 mm"},
          {"dodecahedron", "regular dodecahedron, 56 mm"},
          {"icosahedron", "regular icosahedron, 66 mm"},
          {"pyramid", "square pyramid of equilateral triangles, 70 mm"},
          {"bunny", "a low-poly sitting bunny of at most --faces planar faces (Fig. 15), 160 mm"}};
}

std::vector<std::string> origami_example_names() {
  std::vector<std::string> names;
  for (const ExampleInfo& info : origami_example_list()) names.push_back(info.name);
  return names;
}

Polyhedron origami_example(const std::string& name, int max_faces) {
  static const std::map<std::string, double> sizes = {
      {"tetrahedron", 70}, {"cube", 45},    {"octahedron", 64}, {"dodecahedron", 56},
      {"icosahedron", 66}, {"pyramid", 70}, {"bunny", 160}};
  const auto size = sizes.find(name);
  if (size == sizes.end()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("no built-in solid '{}': choose one of {}", name,
                                fmt::join(origami_example_names(), ", ")));
  }
  const Polyhedron solid =
      name == "bunny" ? low_poly_bunny_solid(max_faces) : polyhedron_example(name, 1.0);
  return scaled_to_size(solid, size->second);
}

}  // namespace flatmorph
