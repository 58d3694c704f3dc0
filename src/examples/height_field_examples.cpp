#include "examples/height_field_examples.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "examples/ring_mesh.h"

namespace flatmorph {
namespace {

// A Gaussian bump in coordinates scaled to the footprint's radius (the footprint is the unit
// disk): centre (x, y), amplitude and standard deviation.
struct Bump {
  double x, y, amplitude, sigma;
};

struct Shape {
  std::string name;
  std::string description;  // at the default size
  std::vector<Bump> bumps;
  double ridge_sigma = 0.0;  // > 0: a crest along x instead of bumps, exp(-y^2 / (2 sigma^2))
};

// Tuned on a fine grid (every peak is a separate maximum, the only other critical points are
// saddles) and checked by the tests at several sizes and resolutions.
std::vector<Shape> shapes() {
  return {
      {"hill", "one round peak at the centre; 160 mm disk, 35 mm high", {{0.0, 0.0, 1.0, 0.5}}},
      {"saddle",
       "two equal peaks with a saddle between them; 160 mm disk, 35 mm high",
       {{-0.45, 0.0, 1.0, 0.25}, {0.45, 0.0, 1.0, 0.25}}},
      // A chain, not a ring, of peaks: three peaks around a point would risk a crater there.
      {"island",
       "three peaks in a chain, the middle one highest; 160 mm disk, 35 mm high",
       // Peaks as wide as a chain of three allows while each stands more than 2.5 mm above its
       // saddle at the default size: narrower ones (0.15) reach 58 degree slopes and ask more
       // shrink than PLA gives (SCF 2020 §8).
       {{-0.65, -0.05, 0.85, 0.18},
        {0.0, 0.15, 1.0, 0.18},
        {0.65, -0.08, 0.7, 0.18},
        {0.0, 0.0, 0.3, 0.5}}},
      {"ridge", "a crest four times as long as it is wide; 160 mm disk, 35 mm high", {}, 0.25},
  };
}

// The shape before scaling, at (x, y) in the unit disk; zero where r = 1 and positive inside.
double unscaled_height(const Shape& shape, double x, double y, bool on_boundary) {
  if (on_boundary) return 0.0;  // exactly, whatever the rounding of cos^2 + sin^2
  const double taper = 1.0 - (x * x + y * y);
  if (shape.ridge_sigma > 0.0) {
    return taper * std::exp(-y * y / (2.0 * shape.ridge_sigma * shape.ridge_sigma));
  }
  double sum = 0.0;
  for (const Bump& b : shape.bumps) {
    const double d2 = (x - b.x) * (x - b.x) + (y - b.y) * (y - b.y);
    sum += b.amplitude * std::exp(-d2 / (2.0 * b.sigma * b.sigma));
  }
  return taper * sum;
}

}  // namespace

std::vector<ExampleInfo> height_field_example_list() {
  std::vector<ExampleInfo> list;
  for (const Shape& shape : shapes()) list.push_back({shape.name, shape.description});
  return list;
}

std::vector<std::string> height_field_example_names() {
  std::vector<std::string> names;
  for (const Shape& shape : shapes()) names.push_back(shape.name);
  return names;
}

HeightField height_field_example(const std::string& name,
                                 const HeightFieldExampleOptions& options) {
  const std::vector<Shape> all = shapes();
  const auto shape =
      std::find_if(all.begin(), all.end(), [&](const Shape& s) { return s.name == name; });
  if (shape == all.end()) {
    std::string names;
    for (const Shape& s : all) names += (names.empty() ? "" : ", ") + s.name;
    throw UserError(ErrorCategory::kOption,
                    "unknown height-field example '" + name + "': choose one of " + names);
  }
  for (const auto& [what, value] : {std::pair<const char*, double>{"diameter", options.diameter_mm},
                                    {"height", options.height_mm},
                                    {"resolution", options.resolution_mm}}) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("example '{}': the {} must be a positive number of millimetres, "
                                  "not {}",
                                  name, what, value));
    }
  }
  const double radius = 0.5 * options.diameter_mm;
  const double rings = std::ceil(radius / options.resolution_mm);
  // Four rings resolve a bump at all; 3 rings^2 vertices must stay a mesh the machine can hold.
  if (rings < 4.0 || 3.0 * rings * (rings + 1.0) + 1.0 > kMaxHeightFieldVertices) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("example '{}': a resolution of {} mm over a {} mm disk makes {} "
                                "rings: choose a resolution between {:.2f} and {:.2f} mm",
                                name, options.resolution_mm, options.diameter_mm, rings,
                                radius / std::sqrt(kMaxHeightFieldVertices / 3.0), radius / 4.0));
  }
  const int n = static_cast<int>(rings);
  std::vector<double> radii(n + 1);
  for (int i = 0; i <= n; ++i) radii[i] = radius * i / n;
  Mesh mesh = ring_disk(radii);
  const int first_outer = 1 + 3 * (n - 1) * n;  // the outer ring's vertices come last
  Eigen::VectorXd z(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    z[v] = unscaled_height(*shape, mesh.V(v, 0) / radius, mesh.V(v, 1) / radius, v >= first_outer);
  }
  // Divided first, so that the highest vertex is exactly height_mm.
  mesh.V.col(2) = (z / z.maxCoeff()) * options.height_mm;
  return HeightField{std::move(mesh.V), std::move(mesh.F), {}};
}

}  // namespace flatmorph
