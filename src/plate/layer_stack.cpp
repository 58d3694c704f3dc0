#include "plate/layer_stack.h"

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "material/thickness_curve.h"

namespace flatmorph {
namespace {

// Where the middle of layer k (1 on the bed) of n equal layers sits in the plate's thickness, as a
// fraction z/h from -1/2 (bed) to +1/2 (top): Eq. 15 of Shrink & Morph sampled exactly, layer k
// spanning z/h in [(k-1)/n - 1/2, k/n - 1/2], so its mean lambda1 is lambda1 + offset
// delta_lambda1 and it changes by delta_lambda1 / n through it.
double bilayer_offset(int k, int n) { return (k - 0.5) / n - 0.5; }

}  // namespace

Layer uniform_layer(int num_faces, int material, const Material& properties,
                    double printed_thickness) {
  Layer layer;
  layer.printed_thickness = Eigen::VectorXd::Constant(num_faces, printed_thickness);
  layer.material = Eigen::VectorXi::Constant(num_faces, material);
  layer.theta = Eigen::VectorXd::Zero(num_faces);
  layer.lambda1 = Eigen::VectorXd::Constant(num_faces, properties.lambda1);
  layer.delta_lambda1 = Eigen::VectorXd::Zero(num_faces);
  layer.lambda2 = Eigen::VectorXd::Constant(num_faces, properties.lambda2);
  layer.lambda3 = Eigen::VectorXd::Constant(num_faces, properties.lambda3);
  layer.cover = Eigen::VectorXd::Ones(num_faces);
  return layer;
}

void check_layer_stack(const LayerStack& stack) {
  const Eigen::Index n = stack.num_faces();
  const int num_materials = static_cast<int>(stack.materials.size());
  for (int k = 0; k < stack.num_layers(); ++k) {
    const Layer& l = stack.layers[k];
    if (l.printed_thickness.size() != n || l.material.size() != n || l.theta.size() != n ||
        l.lambda1.size() != n || l.delta_lambda1.size() != n || l.lambda2.size() != n ||
        l.lambda3.size() != n || l.cover.size() != n) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("layer {} of the stack does not give one value per face ({} "
                                  "faces): fill printed_thickness, material, theta, lambda1..3, "
                                  "delta_lambda1 and cover for every face",
                                  k + 1, n));
    }
    for (Eigen::Index f = 0; f < n; ++f) {
      if (!l.covers(f)) continue;
      if (l.material(f) < 0 || l.material(f) >= num_materials) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("layer {}, face {}: material index {} but the stack has {} "
                                    "material(s): use 0 to {} or {} for a face the layer does "
                                    "not cover",
                                    k + 1, f, l.material(f), num_materials, num_materials - 1,
                                    Layer::kNotCovered));
      }
      if (!(l.printed_thickness(f) > 0) || !std::isfinite(l.printed_thickness(f))) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("layer {}, face {}: printed thickness {} mm; use a positive "
                                    "thickness",
                                    k + 1, f, l.printed_thickness(f)));
      }
      if (!(l.cover(f) > 0 && l.cover(f) <= 1)) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("layer {}, face {}: cover {}; the share of the face under "
                                    "the layer's beads lies in (0, 1]",
                                    k + 1, f, l.cover(f)));
      }
      if (!std::isfinite(l.theta(f)) || !(l.lambda1(f) > 0) || !(l.lambda2(f) > 0) ||
          !(l.lambda3(f) > 0) || !std::isfinite(l.delta_lambda1(f)) ||
          !std::isfinite(l.lambda1(f) + l.lambda2(f) + l.lambda3(f))) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("layer {}, face {}: the direction must be finite and the "
                                    "shrink ratios positive",
                                    k + 1, f));
      }
    }
  }
  for (Eigen::Index f = 0; f < n; ++f) {
    bool covered = false;
    for (const Layer& l : stack.layers) covered = covered || l.covers(f);
    if (!covered) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("face {} is covered by no layer: every face of the plate needs "
                                  "material in at least one layer",
                                  f));
    }
  }
}

std::pair<double, double> printed_thickness_range(const LayerStack& stack) {
  if (stack.num_layers() == 0 || stack.num_faces() == 0) return {0.0, 0.0};
  Eigen::VectorXd total = Eigen::VectorXd::Zero(stack.num_faces());
  for (const Layer& l : stack.layers) {
    for (Eigen::Index f = 0; f < total.size(); ++f) {
      if (l.covers(f)) total(f) += l.printed_thickness(f);
    }
  }
  return {total.minCoeff(), total.maxCoeff()};
}

double shrink_morph_layer_weight(int k, int num_layers) {
  return num_layers == 1 ? 0.0 : double(k - 1) / (num_layers - 1) - 0.5;
}

LayerStack shrink_morph_layer_stack(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                    const Material& material, int num_layers, double layer_height) {
  if (theta1.size() != theta2.size()) {
    throw std::invalid_argument(
        fmt::format("theta1 has {} faces but theta2 has {}: give one value per face "
                    "for both",
                    theta1.size(), theta2.size()));
  }
  if (num_layers < 1) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} layers requested: print at least 1 layer", num_layers));
  }
  if (!(layer_height > 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("layer height {} mm: use a positive layer height", layer_height));
  }
  const int n = num_layers;
  const int num_faces = static_cast<int>(theta1.size());
  LayerStack stack;
  stack.materials = {material};
  for (int k = 1; k <= n; ++k) {
    Layer layer = uniform_layer(num_faces, 0, material, layer_height);
    // Paper §3.2.3: the outer layers print theta1 -/+ theta2/2.
    layer.theta = theta1 + shrink_morph_layer_weight(k, n) * theta2;
    layer.lambda1.array() += bilayer_offset(k, n) * material.delta_lambda1;
    layer.delta_lambda1.setConstant(material.delta_lambda1 / n);
    stack.layers.push_back(std::move(layer));
  }
  return stack;
}

ThicknessControlledStack thickness_controlled_layer_stack(const Eigen::VectorXd& direction,
                                                          const Eigen::VectorXd& shrinkage,
                                                          const Material& material,
                                                          std::optional<int> num_layers) {
  if (direction.size() != shrinkage.size()) {
    throw std::invalid_argument(
        fmt::format("direction has {} faces but shrinkage has {}: give one value per face for both",
                    direction.size(), shrinkage.size()));
  }
  const ThicknessCurve& curve = require_thickness_curve(material);
  const int n = num_layers.value_or(curve.layers);
  if (n < 1) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} layers requested: print at least 1 layer", n));
  }
  const Eigen::Index num_faces = direction.size();
  ThicknessControlledStack out;
  out.shrinkage.resize(num_faces);
  out.clamped = Eigen::VectorXi::Zero(num_faces);
  Eigen::VectorXd height(num_faces), lambda1(num_faces);
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    if (!std::isfinite(shrinkage(f))) {
      throw std::invalid_argument(
          fmt::format("face {}: the wanted shrinkage is {}", f, shrinkage(f)));
    }
    const PrintedShrinkage printed = printed_shrinkage(curve, shrinkage(f));
    out.shrinkage(f) = printed.shrinkage;
    out.clamped(f) = printed.clamped;
    height(f) = printed.layer_height;
    lambda1(f) = lambda1_at_layer_height(curve, height(f));
  }
  out.stack.materials = {material};
  for (int k = 1; k <= n; ++k) {
    Layer layer = uniform_layer(static_cast<int>(num_faces), 0, material, 0.0);
    layer.printed_thickness = height;
    layer.theta = direction;
    layer.lambda1 = lambda1.array() + bilayer_offset(k, n) * material.delta_lambda1;
    layer.delta_lambda1.setConstant(material.delta_lambda1 / n);
    out.stack.layers.push_back(std::move(layer));
  }
  return out;
}

Eigen::VectorXd vertex_to_face_average(const Eigen::MatrixXi& F, const Eigen::VectorXd& values) {
  Eigen::VectorXd out(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out(f) = (values(F(f, 0)) + values(F(f, 1)) + values(F(f, 2))) / 3.0;
  }
  return out;
}

}  // namespace flatmorph
