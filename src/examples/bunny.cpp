#include "examples/bunny.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "methods/origami/planar_faces.h"

namespace flatmorph {
namespace {

// Grid step of the marching tetrahedra, mm: a third of an ear's thickness.
constexpr double kStep = 2.0;
constexpr double kHeight = 80.0;  // mm, base to ear tips

struct Ellipsoid {
  Eigen::Vector3d centre;
  Eigen::Matrix3d axes;  // columns: the unit directions of the three radii
  Eigen::Vector3d radii;
};

Ellipsoid upright(const Eigen::Vector3d& centre, const Eigen::Vector3d& radii) {
  return {centre, Eigen::Matrix3d::Identity(), radii};
}

// An approximate signed distance, mm (Quilez's ellipsoid bound: exact on the surface, the right
// sign everywhere, close to the distance near it).
double distance(const Ellipsoid& e, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = e.axes.transpose() * (p - e.centre);
  const double k0 = q.cwiseQuotient(e.radii).norm();
  const double k1 = q.cwiseQuotient(e.radii.cwiseProduct(e.radii)).norm();
  return k1 > 0 ? k0 * (k0 - 1) / k1 : -e.radii.minCoeff();
}

// The polynomial smooth minimum: a fillet of about `k` mm where two shapes meet.
double smooth_min(double a, double b, double k) {
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return b + (a - b) * h - k * h * (1 - h);
}

// An ear: its base inside the head, leaning back and out by `lean` (rad), its flat side forward.
Ellipsoid ear(double side, double lean) {
  const Eigen::Vector3d base(14, side * 4.5, 51);
  const Eigen::Vector3d along =
      Eigen::Vector3d(-std::sin(lean), side * std::sin(lean), std::cos(lean)).normalized();
  const Eigen::Vector3d across = (Eigen::Vector3d::UnitY() - along.y() * along).normalized();
  Ellipsoid e;
  e.axes.col(0) = along.cross(across);  // thickness, about +x
  e.axes.col(1) = across;
  e.axes.col(2) = along;
  e.radii << 3.2, 6.0, 15.0;
  e.centre = base + 13.0 * along;
  return e;
}

// Negative inside the bunny, mm (before scaling to kHeight).
double bunny_field(const Eigen::Vector3d& p) {
  const double haunch = distance(upright({-5, 0, 15}, {24, 21, 20}), p);
  const double chest = distance(upright({9, 0, 25}, {15, 15, 18}), p);
  const double head = distance(upright({20, 0, 43}, {13, 11, 11}), p);
  const double muzzle = distance(upright({29, 0, 40}, {7, 8, 6.5}), p);
  const double tail = distance(upright({-29, 0, 12}, {6, 6, 6}), p);
  const double lean = 12 * std::numbers::pi / 180;
  const double ears = std::min(distance(ear(-1, lean), p), distance(ear(1, lean), p));
  double f = smooth_min(haunch, chest, 6);
  f = smooth_min(f, head, 4);
  f = smooth_min(f, muzzle, 3);
  f = smooth_min(f, tail, 2);
  f = smooth_min(f, ears, 2.5);
  return std::max(f, -p.z());  // sitting on a flat base at z = 0
}

// The zero level set of `field` sampled on a grid and split into Kuhn's six tetrahedra per cube
// (consistent across cubes, so the surface is closed and manifold); each triangle turned to face
// where the field is positive (outside).
template <class Field>
Mesh marching_tetrahedra(const Field& field, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                         double step) {
  const Eigen::Array3i n = ((hi - lo) / step).array().ceil().cast<int>() + 1;  // nodes per axis
  const auto node = [&](int i, int j, int k) {
    return (static_cast<long long>(k) * n.y() + j) * n.x() + i;
  };
  const auto position = [&](long long id) {
    const long long i = id % n.x(), j = (id / n.x()) % n.y(), k = id / (n.x() * n.y());
    return Eigen::Vector3d(lo + step * Eigen::Vector3d(double(i), double(j), double(k)));
  };
  std::vector<double> value(static_cast<size_t>(n.prod()));
  for (long long id = 0; id < n.prod(); ++id) value[id] = field(position(id));

  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::unordered_map<long long, int> crossing;  // lookups only: output order follows the grid
  const long long num_nodes = n.prod();
  const auto point_on = [&](long long inside, long long outside) {
    const long long key = std::min(inside, outside) * num_nodes + std::max(inside, outside);
    const auto found = crossing.find(key);
    if (found != crossing.end()) return found->second;
    // Kept off the grid nodes so no triangle collapses to a sliver.
    const double t = std::clamp(value[inside] / (value[inside] - value[outside]), 0.05, 0.95);
    points.push_back((1 - t) * position(inside) + t * position(outside));
    crossing.emplace(key, int(points.size()) - 1);
    return int(points.size()) - 1;
  };
  const auto emit = [&](int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d normal = (points[b] - points[a]).cross(points[c] - points[a]);
    if (normal.dot(outward) >= 0) {
      triangles.push_back({a, b, c});
    } else {
      triangles.push_back({a, c, b});
    }
  };
  constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k + 1 < n.z(); ++k) {
    for (int j = 0; j + 1 < n.y(); ++j) {
      for (int i = 0; i + 1 < n.x(); ++i) {
        for (const auto& order : kOrders) {
          std::array<long long, 4> tet;
          int c[3] = {i, j, k};
          tet[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            tet[s + 1] = node(c[0], c[1], c[2]);
          }
          std::vector<long long> in, out;
          for (long long v : tet) (value[v] < 0 ? in : out).push_back(v);
          Eigen::Vector3d outward = Eigen::Vector3d::Zero();
          for (long long v : out) outward += position(v) / double(out.size());
          for (long long v : in) outward -= position(v) / double(in.size());
          // The crossings are numbered last first, in sequenced statements: the numbering sets the
          // low-poly bunny's faces, and function arguments are evaluated in an order each compiler
          // chooses.
          if (in.size() == 1) {
            const int c = point_on(in[0], out[2]), b = point_on(in[0], out[1]);
            emit(point_on(in[0], out[0]), b, c, outward);
          } else if (in.size() == 3) {
            const int c = point_on(in[2], out[0]), b = point_on(in[1], out[0]);
            emit(point_on(in[0], out[0]), b, c, outward);
          } else if (in.size() == 2) {
            const int ac = point_on(in[0], out[0]), ad = point_on(in[0], out[1]);
            const int bd = point_on(in[1], out[1]), bc = point_on(in[1], out[0]);
            emit(ac, ad, bd, outward);
            emit(ac, bd, bc, outward);
          }
        }
      }
    }
  }
  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v) mesh.V.row(Eigen::Index(v)) = points[v].transpose();
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int s = 0; s < 3; ++s) mesh.F(Eigen::Index(t), s) = triangles[t][s];
  }
  return mesh;
}

}  // namespace

Mesh bunny_mesh() {
  // The grid starts half a step below the base, so no node lies on it.
  Mesh mesh = marching_tetrahedra(bunny_field, Eigen::Vector3d(-38, -26, -0.5 * kStep),
                                  Eigen::Vector3d(40, 26, 86), kStep);
  mesh.V *= kHeight / mesh.V.col(2).maxCoeff();
  return mesh;
}

Polyhedron low_poly_bunny_solid(int max_faces) {
  PlanarFacesOptions options;
  options.max_faces = max_faces;
  return planar_faces(bunny_mesh(), "example bunny", options);
}

}  // namespace flatmorph
