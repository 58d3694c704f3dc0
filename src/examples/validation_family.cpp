#include "examples/validation_family.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "common/angles.h"
#include "examples/ring_mesh.h"

namespace flatmorph {
namespace {

// A star-shaped footprint: its outline's distance from the origin in the direction psi (mm).
using Outline = std::function<double(double psi)>;
using Height = std::function<double(double x, double y)>;

// |x / a|^p + |y / b|^p = 1: an ellipse for p = 2, a rounded rectangle for larger p.
Outline superellipse(double a, double b, double p) {
  return [=](double psi) {
    return std::pow(
        std::pow(std::abs(std::cos(psi) / a), p) + std::pow(std::abs(std::sin(psi) / b), p),
        -1.0 / p);
  };
}

// A regular n-gon of the given inradius, one side facing +x, its corners rounded: the p-norm (over
// the sides) of the support of each side, which tends to the polygon as p grows.
Outline rounded_polygon(int n, double inradius, double p) {
  return [=](double psi) {
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      const double c = std::cos(psi - 2 * kPi * k / n);
      if (c > 0) sum += std::pow(c, p);
    }
    return inradius / std::pow(sum, 1.0 / p);
  };
}

// Meshes the footprint in rings that follow its outline: ring i of N is the outline scaled by i /
// N, its vertices evenly spaced along it, about `target_faces` triangles in all; z from `height`.
// Near-equilateral where the outline is round; where it is elongated (an ellipse of aspect 3) the
// rings are closer together across its short axis than along its long one.
Mesh outline_mesh(const Outline& outline, const Height& height, int target_faces) {
  constexpr int kSamples = 4096;  // of the outline, for its arc length
  std::vector<Eigen::Vector2d> outline_points(kSamples + 1);
  std::vector<double> arc(kSamples + 1, 0.0);
  double area = 0, mean_radius = 0;
  for (int k = 0; k <= kSamples; ++k) {
    const double psi = 2 * kPi * k / kSamples;
    const double r = outline(psi);
    outline_points[k] = r * Eigen::Vector2d(std::cos(psi), std::sin(psi));
    if (k > 0) {
      arc[k] = arc[k - 1] + (outline_points[k] - outline_points[k - 1]).norm();
      area += 0.5 * r * r * 2 * kPi / kSamples;
      mean_radius += r / kSamples;
    }
  }
  const double length = arc.back();
  // A strip between rings holds about twice as many triangles as the outer ring has vertices,
  // so the mesh has about 2 * area / h^2 triangles for an edge length h.
  const double h = std::sqrt(2 * area / target_faces);
  const int rings = std::max(2, static_cast<int>(std::lround(mean_radius / h)));
  std::vector<int> sizes;
  for (int i = 1; i <= rings; ++i) {
    const int n = static_cast<int>(std::lround(length * i / rings / h));
    sizes.push_back(std::max({6, n, sizes.empty() ? 0 : sizes.back()}));
  }
  Mesh mesh;
  mesh.F = ring_mesh_faces(sizes);
  mesh.V.setZero(mesh.F.maxCoeff() + 1, 3);
  int v = 1;
  for (int i = 1; i <= rings; ++i) {
    const double scale = static_cast<double>(i) / rings;
    const int n = sizes[static_cast<size_t>(i - 1)];
    for (int j = 0; j < n; ++j) {
      // The point a fraction j / n of the way along the outline, by the arc-length table.
      const double s = length * j / n;
      const size_t k =
          static_cast<size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
      const size_t hi = std::clamp<size_t>(k, 1, kSamples);
      const double t = (s - arc[hi - 1]) / (arc[hi] - arc[hi - 1]);
      const Eigen::Vector2d p =
          scale * (outline_points[hi - 1] + t * (outline_points[hi] - outline_points[hi - 1]));
      mesh.V.row(v++) << p.x(), p.y(), 0.0;
    }
  }
  for (int w = 0; w < mesh.num_vertices(); ++w) mesh.V(w, 2) = height(mesh.V(w, 0), mesh.V(w, 1));
  return mesh;
}

ValidationTarget target(std::string name, std::string description, const Outline& outline,
                        const Height& height, int faces) {
  ValidationTarget t{std::move(name), std::move(description), outline_mesh(outline, height, faces),
                     0};
  const Eigen::Vector2d extent =
      t.mesh.V.leftCols<2>().colwise().maxCoeff() - t.mesh.V.leftCols<2>().colwise().minCoeff();
  t.width_mm = extent.maxCoeff();
  return t;
}

// A paraboloid cap with radii of curvature rx and ry at its apex (mm), curving down.
Height cap(double rx, double ry) {
  return [=](double x, double y) { return -(x * x / (2 * rx) + y * y / (2 * ry)); };
}

}  // namespace

std::vector<ValidationTarget> validation_family() {
  std::vector<ValidationTarget> family;
  family.push_back(target("elliptic-cap-1",
                          "paraboloid cap, radius of curvature 80 mm, on a 100 mm disk",
                          superellipse(50, 50, 2), cap(80, 80), 4000));
  family.push_back(target("elliptic-cap-2",
                          "paraboloid cap, radii of curvature 90 x 60 mm, on a 120 x 60 mm ellipse",
                          superellipse(60, 30, 2), cap(90, 60), 5000));
  family.push_back(target(
      "elliptic-cap-3", "paraboloid cap, radii of curvature 120 x 50 mm, on a 150 x 50 mm ellipse",
      superellipse(75, 25, 2), cap(120, 50), 6000));
  family.push_back(target("rounded-triangle-cap",
                          "paraboloid cap, radius of curvature 70 mm, on a rounded triangle of "
                          "inradius 27 mm",
                          rounded_polygon(3, 27, 10), cap(70, 70), 4000));
  family.push_back(target("rounded-square-cap",
                          "paraboloid cap, radius of curvature 80 mm, on a 90 mm rounded square",
                          rounded_polygon(4, 45, 10), cap(80, 80), 5000));
  family.push_back(target(
      "saddle", "z = (x^2 - y^2) / 140 on a 90 mm disk", superellipse(45, 45, 2),
      [](double x, double y) { return (x * x - y * y) / 140; }, 3000));
  family.push_back(target(
      "elliptic-saddle", "z = x^2 / 200 - y^2 / 120 on a 140 x 80 mm ellipse",
      superellipse(70, 40, 2), [](double x, double y) { return x * x / 200 - y * y / 120; }, 6000));
  family.push_back(target(
      "monkey-saddle", "z = (x^3 - 3 x y^2) / 12500 on a 100 mm disk, +-10 mm",
      superellipse(50, 50, 2),
      [](double x, double y) { return (x * x * x - 3 * x * y * y) / 12500; }, 5000));
  family.push_back(target(
      "twisted-strip",
      "z = x y / 200 on a 150 x 50 mm rounded rectangle (|x/75|^6 + |y/25|^6 "
      "= 1), its ends turned 41 degrees against each other",
      superellipse(75, 25, 6), [](double x, double y) { return x * y / 200; }, 6000));
  family.push_back(target(
      "wave", "z = 5 sin(2 pi x / 90) on a 110 mm disk", superellipse(55, 55, 2),
      [](double x, double) { return 5 * std::sin(2 * kPi * x / 90); }, 8000));
  family.push_back(target(
      "off-centre-bump", "z = 12 exp(-((x - 15)^2 + (y - 10)^2) / 30^2) on a 100 mm disk",
      superellipse(50, 50, 2),
      [](double x, double y) {
        const double dx = x - 15, dy = y - 10;
        return 12 * std::exp(-(dx * dx + dy * dy) / 900);
      },
      8000));
  return family;
}

std::vector<ValidationTarget> validation_family_variants() {
  const auto monkey = [](double scale) {
    return [=](double x, double y) { return (x * x * x - 3 * x * y * y) / scale; };
  };
  std::vector<ValidationTarget> variants;
  variants.push_back(target("monkey-saddle-10k",
                            "the family's monkey saddle, z = (x^3 - 3 x y^2) / 12500 on a 100 mm "
                            "disk, at 10k faces",
                            superellipse(50, 50, 2), monkey(12500), 10000));
  variants.push_back(target("monkey-saddle-80",
                            "z = (x^3 - 3 x y^2) / 8000 on an 80 mm disk, +-8 mm",
                            superellipse(40, 40, 2), monkey(8000), 4000));
  variants.push_back(target("monkey-saddle-shallow",
                            "z = (x^3 - 3 x y^2) / 20000 on a 100 mm disk, +-6 mm",
                            superellipse(50, 50, 2), monkey(20000), 5000));
  variants.push_back(target("elliptic-cap-small",
                            "paraboloid cap, radius of curvature 60 mm, on a 70 mm disk",
                            superellipse(35, 35, 2), cap(60, 60), 3000));
  variants.push_back(target("elliptic-cap-deep",
                            "paraboloid cap, radius of curvature 60 mm, on a 100 mm disk",
                            superellipse(50, 50, 2), cap(60, 60), 5000));
  variants.push_back(
      target("elliptic-cap-1.5",
             "paraboloid cap, radii of curvature 100 x 70 mm, on a 120 x 80 mm ellipse",
             superellipse(60, 40, 2), cap(100, 70), 5000));
  variants.push_back(
      target("elliptic-cap-2.5",
             "paraboloid cap, radii of curvature 110 x 55 mm, on a 130 x 52 mm ellipse",
             superellipse(65, 26, 2), cap(110, 55), 5000));
  return variants;
}

}  // namespace flatmorph
