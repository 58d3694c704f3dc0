#include "examples/examples.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "common/error.h"
#include "examples/ring_mesh.h"

namespace flatmorph {

namespace {

// Every example is a height field z = height(x, y) (mm) over a disk footprint of radius
// `footprint_radius` centred on the origin. A height field seen from above has its normals up as
// long as the footprint triangles are counter-clockwise.
struct ExampleSurface {
  double footprint_radius;
  std::function<double(double, double)> height;
  std::function<Eigen::Vector2d(double, double)> gradient;
};

struct Example {
  ExampleInfo info;
  std::function<ExampleSurface()> field;
};

// 22 rings give 6 * 22^2 = 2904 faces: fine enough to resolve the curvature, small enough for the
// README's quick design run.
constexpr int kRings = 22;

std::vector<Example> examples() {
  return {
      {{"dome",
        "spherical cap, radius of curvature 60 mm, 80 mm footprint, 15.3 mm tall; positive "
        "Gaussian "
        "curvature"},
       [] {
         constexpr double kRadius = 60.0;
         return ExampleSurface{40.0,
                               [](double x, double y) {
                                 return std::sqrt(kRadius * kRadius - x * x - y * y) - kRadius;
                               },
                               [](double x, double y) {
                                 const double scale =
                                     -1.0 / std::sqrt(kRadius * kRadius - x * x - y * y);
                                 return Eigen::Vector2d(scale * x, scale * y);
                               }};
       }},
      {{"saddle",
        "z = (x^2 - y^2) / 160 mm over an 80 mm disk, +-10 mm; negative Gaussian curvature"},
       [] {
         constexpr double kScale = 2.0 * 80.0;
         return ExampleSurface{40.0, [](double x, double y) { return (x * x - y * y) / kScale; },
                               [](double x, double y) {
                                 return Eigen::Vector2d(2.0 * x / kScale, -2.0 * y / kScale);
                               }};
       }},
      {{"paraboloid",
        "elliptic paraboloid cap, radii of curvature 70 mm (x) and 110 mm (y) at the apex, 90 mm "
        "footprint; positive, anisotropic Gaussian curvature"},
       [] {
         constexpr double kRadiusX = 70.0, kRadiusY = 110.0;
         return ExampleSurface{
             45.0,
             [](double x, double y) {
               return -(x * x / (2.0 * kRadiusX) + y * y / (2.0 * kRadiusY));
             },
             [](double x, double y) { return Eigen::Vector2d(-x / kRadiusX, -y / kRadiusY); }};
       }},
      {{"bump",
        "Gaussian bump 12 mm tall, z = 12 exp(-r^2 / 36^2) mm, over a 100 mm disk; positive "
        "curvature on top, negative on the flank"},
       [] {
         constexpr double kAmplitude = 12.0, kWidth = 2.0 * 18.0;
         auto height = [](double x, double y) {
           return kAmplitude * std::exp(-(x * x + y * y) / (kWidth * kWidth));
         };
         return ExampleSurface{50.0, height, [height](double x, double y) {
                                 const double scale = -2.0 * height(x, y) / (kWidth * kWidth);
                                 return Eigen::Vector2d(scale * x, scale * y);
                               }};
       }},
  };
}

// Footprint radii of rings 0..rings such that consecutive rings are equally far apart along the
// surface. The radial arc length is averaged over the direction, s(r) = int_0^r mean_psi
// sqrt(1 + (dz/dr)^2), which is the geodesic arc length for surfaces of revolution (the dome).
std::vector<double> even_ring_radii(const ExampleSurface& field, int rings) {
  constexpr int kSamples = 2000;  // along the radius, trapezoid rule
  constexpr int kDirections = 64;
  auto slope_factor = [&](double r) {
    double sum = 0.0;
    for (int d = 0; d < kDirections; ++d) {
      const double psi = 2.0 * std::numbers::pi * d / kDirections;
      const Eigen::Vector2d radial(std::cos(psi), std::sin(psi));
      const double dzdr = field.gradient(r * radial.x(), r * radial.y()).dot(radial);
      sum += std::sqrt(1.0 + dzdr * dzdr);
    }
    return sum / kDirections;
  };
  const double dr = field.footprint_radius / kSamples;
  std::vector<double> arc(kSamples + 1, 0.0);
  double previous = slope_factor(0.0);
  for (int k = 1; k <= kSamples; ++k) {
    const double current = slope_factor(k * dr);
    arc[k] = arc[k - 1] + 0.5 * dr * (previous + current);
    previous = current;
  }
  std::vector<double> radii(rings + 1, 0.0);
  int k = 0;
  for (int i = 1; i < rings; ++i) {
    const double target = arc[kSamples] * i / rings;
    while (arc[k + 1] < target) ++k;
    radii[i] = (k + (target - arc[k]) / (arc[k + 1] - arc[k])) * dr;
  }
  radii[rings] = field.footprint_radius;  // exact, so the footprint diameter is as documented
  return radii;
}

}  // namespace

std::vector<ExampleInfo> example_list() {
  std::vector<ExampleInfo> list;
  for (const Example& example : examples()) list.push_back(example.info);
  return list;
}

Mesh make_example(const std::string& name) {
  for (const Example& example : examples()) {
    if (example.info.name != name) continue;
    const ExampleSurface field = example.field();
    Mesh mesh = ring_disk(even_ring_radii(field, kRings));
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      mesh.V(v, 2) = field.height(mesh.V(v, 0), mesh.V(v, 1));
    }
    return mesh;
  }
  std::string names;
  for (const Example& example : examples()) {
    names += (names.empty() ? "" : ", ") + example.info.name;
  }
  throw UserError(ErrorCategory::kOption, "unknown example '" + name + "': choose one of " + names);
}

}  // namespace flatmorph
