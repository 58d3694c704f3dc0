#include "plate/layer_stack.h"

#include <fmt/core.h>

#include "common/error.h"

namespace flatmorph {

LayerStack shrink_morph_layer_stack(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                    const Material& material, int num_layers, double layer_height) {
  if (theta1.size() != theta2.size()) {
    throw UserError(ErrorCategory::kOption,
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
  const Eigen::Index num_faces = theta1.size();
  LayerStack stack;
  for (int k = 1; k <= n; ++k) {
    Layer layer;
    layer.printed_thickness = layer_height;
    layer.material = material.name;
    // Paper §3.2.3: the outer layers print theta1 -/+ theta2/2.
    const double theta2_weight = n == 1 ? 0.0 : double(k - 1) / (n - 1) - 0.5;
    layer.theta = theta1 + theta2_weight * theta2;
    // Eq. 15 sampled exactly: the layer spans z/h in [(k-1)/n - 1/2, k/n - 1/2].
    const double mid = (k - 0.5) / n - 0.5;
    layer.lambda1 =
        Eigen::VectorXd::Constant(num_faces, material.lambda1 + mid * material.delta_lambda1);
    layer.delta_lambda1 = Eigen::VectorXd::Constant(num_faces, material.delta_lambda1 / n);
    layer.lambda2 = Eigen::VectorXd::Constant(num_faces, material.lambda2);
    layer.lambda3 = Eigen::VectorXd::Constant(num_faces, material.lambda3);
    layer.covered.assign(num_faces, true);
    stack.layers.push_back(std::move(layer));
  }
  return stack;
}

Eigen::VectorXd vertex_to_face_average(const Eigen::MatrixXi& F, const Eigen::VectorXd& values) {
  Eigen::VectorXd out(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out(f) = (values(F(f, 0)) + values(F(f, 1)) + values(F(f, 2))) / 3.0;
  }
  return out;
}

}  // namespace flatmorph
