#include "material/thickness_curve.h"

#include <fmt/core.h>

#include <algorithm>

namespace flatmorph {
namespace {

MonotoneCurve view(const ThicknessCurve& c) {
  return {c.lambda1_coefficients, c.min_layer_height, c.max_layer_height};
}

}  // namespace

std::string thickness_curve_problem(const ThicknessCurve& c) {
  if (std::string problem = monotone_curve_problem(view(c), kThicknessCurveParameter);
      !problem.empty()) {
    return problem;
  }
  if (c.layers < 1) return fmt::format("it was measured on {} layers; give 1 or more", c.layers);
  return "";
}

double lambda1_at_layer_height(const ThicknessCurve& curve, double h) {
  return monotone_curve_value(view(curve), h, kThicknessCurveParameter);
}

double layer_height_for_lambda1(const ThicknessCurve& curve, double lambda1) {
  return monotone_curve_inverse(view(curve), lambda1, kThicknessCurveParameter);
}

double layer_height_for_shrinkage(const ThicknessCurve& curve, double shrinkage) {
  return layer_height_for_lambda1(curve, 1 - shrinkage);
}

std::pair<double, double> reachable_shrinkage(const ThicknessCurve& curve) {
  const double at_min = 1 - lambda1_at_layer_height(curve, curve.min_layer_height);
  const double at_max = 1 - lambda1_at_layer_height(curve, curve.max_layer_height);
  return std::minmax(at_min, at_max);
}

PrintedShrinkage printed_shrinkage(const ThicknessCurve& curve, double shrinkage) {
  const auto [least, most] = reachable_shrinkage(curve);
  PrintedShrinkage out;
  out.shrinkage = shrinkage;
  if (shrinkage < least || shrinkage > most) {
    out.clamped = shrinkage < least ? -1 : 1;
    out.shrinkage = std::clamp(shrinkage, least, most);
  }
  out.layer_height = layer_height_for_shrinkage(curve, out.shrinkage);
  return out;
}

}  // namespace flatmorph
