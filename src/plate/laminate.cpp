#include "plate/laminate.h"

#include <fmt/core.h>

#include <cmath>

#include "common/error.h"

namespace flatmorph {
namespace {

}  // namespace

Eigen::Matrix2d rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

RestForms laminate(const LayerStack& stack) {
  check_layer_stack(stack);
  const int num_faces = stack.num_faces();
  RestForms out;
  out.rest_first_fundamental_form.resize(num_faces);
  out.rest_second_fundamental_form.resize(num_faces);
  out.thickness.resize(num_faces);
  out.material_angle.resize(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    double t = 0;
    for (const Layer& l : stack.layers) {
      if (l.covers(f)) t += l.lambda3(f) * l.printed_thickness(f);
    }
    if (!(t > 0)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("face {} is covered by no layer: every face of the plate needs "
                                  "material in at least one layer",
                                  f));
    }
    Eigen::Matrix2d integral = Eigen::Matrix2d::Zero();      // ∫ C̄ dz'
    Eigen::Matrix2d first_moment = Eigen::Matrix2d::Zero();  // ∫ z' C̄ dz'
    double axial_cos = 0, axial_sin = 0;
    double bottom = -0.5 * t;
    for (const Layer& l : stack.layers) {
      if (!l.covers(f)) continue;
      const double tau = l.lambda3(f) * l.printed_thickness(f);
      const double mid = bottom + 0.5 * tau;
      const double lambda1 = l.lambda1(f), delta = l.delta_lambda1(f);
      const double lambda2_sq = l.lambda2(f) * l.lambda2(f);
      // λ1(z') = λ1 + δ u/τ with u = z' − mid in [−τ/2, τ/2]:
      //   ∫ λ1² dz' = τ (λ1² + δ²/12),  ∫ z' λ1² dz' = mid τ (λ1² + δ²/12) + λ1 δ τ²/6.
      const double along = tau * (lambda1 * lambda1 + delta * delta / 12.0);
      const double along_moment = mid * along + lambda1 * delta * tau * tau / 6.0;
      const Eigen::Matrix2d r = rotation(l.theta(f));
      integral += r * Eigen::Vector2d(along, tau * lambda2_sq).asDiagonal() * r.transpose();
      first_moment +=
          r * Eigen::Vector2d(along_moment, mid * tau * lambda2_sq).asDiagonal() * r.transpose();
      axial_cos += tau * std::cos(2 * l.theta(f));
      axial_sin += tau * std::sin(2 * l.theta(f));
      bottom += tau;
    }
    out.thickness(f) = t;
    out.rest_first_fundamental_form[f] = integral / t;
    out.rest_second_fundamental_form[f] = -6.0 / (t * t * t) * first_moment;
    out.material_angle(f) = 0.5 * std::atan2(axial_sin, axial_cos);
  }
  return out;
}

RestForms shrink_morph_rest_forms(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                  const Material& material, double printed_thickness) {
  if (theta1.size() != theta2.size()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("theta1 has {} faces but theta2 has {}: give one value per face "
                                "for both",
                                theta1.size(), theta2.size()));
  }
  if (!(printed_thickness > 0)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("printed thickness {} mm: use a positive thickness", printed_thickness));
  }
  const int num_faces = static_cast<int>(theta1.size());
  const double l1 = material.lambda1, l2 = material.lambda2;
  const double t = material.lambda3 * printed_thickness;
  RestForms out;
  out.rest_first_fundamental_form.resize(num_faces);
  out.rest_second_fundamental_form.resize(num_faces);
  out.thickness = Eigen::VectorXd::Constant(num_faces, t);
  out.material_angle = theta1;
  Eigen::Matrix2d swap, along;
  swap << 0, 1, 1, 0;
  along << 1, 0, 0, 0;
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::Matrix2d r = rotation(theta1(f));
    out.rest_first_fundamental_form[f] =
        r * Eigen::Vector2d(l1 * l1, l2 * l2).asDiagonal() * r.transpose();  // Eq. 6
    // Eq. 7 and 16-17 with z/h = z'/t: C̄ = ā − 2 z' b̄.
    const Eigen::Matrix2d material_frame =
        theta2(f) * (l2 * l2 - l1 * l1) / (2 * t) * swap - material.delta_lambda1 * l1 / t * along;
    out.rest_second_fundamental_form[f] = r * material_frame * r.transpose();
  }
  return out;
}

}  // namespace flatmorph
