#include "plate/laminate.h"

#include <fmt/core.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "common/error.h"

namespace flatmorph {
namespace {

Eigen::Vector3d components(const Eigen::Matrix2d& m) { return {m(0, 0), m(1, 1), m(0, 1)}; }

Eigen::Matrix2d from_components(const Eigen::Vector3d& c) {
  Eigen::Matrix2d m;
  m << c(0), c(2), c(2), c(1);
  return m;
}

// S(θ): the components of R(θ) Y R(θ)ᵀ from those of a symmetric Y, and dS/dθ.
Eigen::Matrix3d turn(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix3d m;
  m << c * c, s * s, -2 * c * s, s * s, c * c, 2 * c * s, c * s, -c * s, c * c - s * s;
  return m;
}

Eigen::Matrix3d turn_derivative(double theta) {
  const double c2 = std::cos(2 * theta), s2 = std::sin(2 * theta);
  Eigen::Matrix3d m;
  m << -s2, s2, -2 * c2, s2, -s2, 2 * c2, c2, -c2, -2 * s2;
  return m;
}

// P in the layer's own frame (θ = 0, c̄ = diag(λ1², λ2²)): Voigt(c̄⁻¹ Y) = N y, P0 = λ1 λ2 Nᵀ C N.
Eigen::Matrix3d layer_frame_norm(double lambda1, double lambda2, const Eigen::Matrix3d& c) {
  const double i1 = 1 / (lambda1 * lambda1), i2 = 1 / (lambda2 * lambda2);
  const Eigen::Matrix3d n = Eigen::Vector3d(i1, i2, i1 + i2).asDiagonal();
  return lambda1 * lambda2 * n.transpose() * c * n;
}

Matrix6d block_stiffness(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b,
                         const Eigen::Matrix3d& d) {
  Matrix6d k;
  k << a, -2 * b, -2 * b, 4 * d;
  return k;
}

// One face's integrals over its covered layers; with `rates`, also their derivatives.
struct FaceIntegrals {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero(),
                  d = Eigen::Matrix3d::Zero();
  Eigen::Vector3d m_a = Eigen::Vector3d::Zero(), m_b = Eigen::Vector3d::Zero();
};

RestForms laminate_impl(const LayerStack& stack, const std::vector<double>* rates,
                        LaminateDerivative* derivative) {
  check_layer_stack(stack);
  const int num_faces = stack.num_faces();
  std::vector<Eigen::Matrix3d> elasticity;
  for (const Material& m : stack.materials) {
    elasticity.push_back(orthotropic_elasticity_tensor(stiffness_of(m)));
  }
  RestForms out;
  out.rest_first_fundamental_form.resize(num_faces);
  out.rest_second_fundamental_form.resize(num_faces);
  out.stiffness.resize(num_faces);
  out.thickness.resize(num_faces);
  out.energy_scale.resize(num_faces);
  if (derivative) {
    derivative->stiffness.resize(num_faces);
    derivative->rest.resize(num_faces);
  }
  for (int f = 0; f < num_faces; ++f) {
    double t = 0, scale = 0;
    for (const Layer& l : stack.layers) {
      if (!l.covers(f)) continue;
      const double tau = l.lambda3(f) * l.printed_thickness(f);
      t += tau;
      scale += l.cover(f) * tau * stack.materials[l.material(f)].young_modulus_along;
    }
    FaceIntegrals value, rate;
    double bottom = -0.5 * t;
    for (int k = 0; k < stack.num_layers(); ++k) {
      const Layer& l = stack.layers[k];
      if (!l.covers(f)) continue;
      const double tau = l.lambda3(f) * l.printed_thickness(f);
      const double mid = bottom + 0.5 * tau;
      bottom += tau;
      const double lambda1 = l.lambda1(f), delta = l.delta_lambda1(f), lambda2 = l.lambda2(f);
      // λ1(z) = λ1 + δ u/τ with u = z − mid in [−τ/2, τ/2]:
      //   ∫ λ1² dz = τ (λ1² + δ²/12),  ∫ z λ1² dz = mid τ (λ1² + δ²/12) + λ1 δ τ²/6.
      const double along = tau * (lambda1 * lambda1 + delta * delta / 12.0);
      const double along_moment = mid * along + lambda1 * delta * tau * tau / 6.0;
      const Eigen::Vector3d metric(along, tau * lambda2 * lambda2, 0);
      const Eigen::Vector3d metric_moment(along_moment, mid * tau * lambda2 * lambda2, 0);
      // Both the rest metric and the stiff direction turn with θ: P = S(−θ)ᵀ P0 S(−θ).
      // A partly covered layer (Layer::cover) is that much less stiff, at its full height.
      const Eigen::Matrix3d p0 =
          l.cover(f) * layer_frame_norm(lambda1, lambda2, elasticity[l.material(f)]);
      const double theta = l.theta(f);
      const Eigen::Matrix3d to_layer = turn(-theta), to_plate = turn(theta);
      const Eigen::Matrix3d p = to_layer.transpose() * p0 * to_layer;
      const Eigen::Vector3d c = to_plate * metric, zc = to_plate * metric_moment;
      value.a += tau * p;
      value.b += tau * mid * p;
      value.d += (tau * mid * mid + tau * tau * tau / 12) * p;
      value.m_a += p * c;
      value.m_b += p * zc;
      if (!rates) continue;
      const double rate_k = (*rates)[k];
      if (rate_k == 0) continue;
      // d/dθ S(−θ) = −S'(−θ); d/dθ S(θ) = S'(θ).
      const Eigen::Matrix3d d_to_layer = -turn_derivative(-theta);
      const Eigen::Matrix3d dp = rate_k * (d_to_layer.transpose() * p0 * to_layer +
                                           to_layer.transpose() * p0 * d_to_layer);
      const Eigen::Matrix3d d_to_plate = rate_k * turn_derivative(theta);
      rate.a += tau * dp;
      rate.b += tau * mid * dp;
      rate.d += (tau * mid * mid + tau * tau * tau / 12) * dp;
      rate.m_a += dp * c + p * (d_to_plate * metric);
      rate.m_b += dp * zc + p * (d_to_plate * metric_moment);
    }
    const Matrix6d k = block_stiffness(value.a, value.b, value.d);
    Vector6d m;
    m << value.m_a, -2 * value.m_b;
    const Eigen::LLT<Matrix6d> llt(k);
    const Vector6d rest = llt.solve(m);
    out.rest_first_fundamental_form[f] = from_components(rest.head<3>());
    out.rest_second_fundamental_form[f] = from_components(rest.tail<3>());
    out.stiffness[f] = k;
    out.thickness(f) = t;
    out.energy_scale(f) = scale;
    if (derivative) {
      const Matrix6d dk = block_stiffness(rate.a, rate.b, rate.d);
      Vector6d dm;
      dm << rate.m_a, -2 * rate.m_b;
      derivative->stiffness[f] = dk;
      derivative->rest[f] = llt.solve(dm - dk * rest);  // K s̄ = m differentiated
    }
  }
  return out;
}

}  // namespace

Stiffness stiffness_of(const Material& material) {
  return {material.young_modulus_along, material.young_modulus_across, material.poisson_ratio};
}

Eigen::Matrix3d orthotropic_elasticity_tensor(const Stiffness& s) {
  const double e1 = s.young_modulus_along, e2 = s.young_modulus_across, nu = s.poisson_ratio;
  const double g = std::sqrt(e1 * e2);
  Eigen::Matrix3d c;
  c << e1, nu * g, 0, nu * g, e2, 0, 0, 0, 0.5 * (1 - nu) * g;
  return c / (1 - nu * nu);  // Eq. 4
}

Eigen::Matrix3d material_norm(const Eigen::Matrix2d& rest_metric, double material_angle,
                              const Stiffness& stiffness) {
  const Eigen::Matrix2d inverse = rest_metric.inverse();
  const Eigen::Matrix2d r = rotation(material_angle);
  const Eigen::Matrix2d unit[3] = {(Eigen::Matrix2d() << 1, 0, 0, 0).finished(),
                                   (Eigen::Matrix2d() << 0, 0, 0, 1).finished(),
                                   (Eigen::Matrix2d() << 0, 1, 1, 0).finished()};
  Eigen::Matrix3d strain;  // X's components -> Voigt(Rᵀ c̄⁻¹ X R)
  for (int j = 0; j < 3; ++j) {
    const Eigen::Matrix2d e = r.transpose() * inverse * unit[j] * r;
    strain.col(j) = Eigen::Vector3d(e(0, 0), e(1, 1), e(0, 1) + e(1, 0));
  }
  return std::sqrt(rest_metric.determinant()) * strain.transpose() *
         orthotropic_elasticity_tensor(stiffness) * strain;
}

Vector6d rest_vector(const Eigen::Matrix2d& a_bar, const Eigen::Matrix2d& b_bar) {
  Vector6d s;
  s << components(a_bar), components(b_bar);
  return s;
}

Eigen::Matrix2d rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

RestForms laminate(const LayerStack& stack) { return laminate_impl(stack, nullptr, nullptr); }

RestForms laminate(const LayerStack& stack, const std::vector<double>& angle_rates,
                   LaminateDerivative& derivative) {
  if (static_cast<int>(angle_rates.size()) != stack.num_layers()) {
    throw std::invalid_argument(
        fmt::format("{} angle rates for a stack of {} layers: give one per layer",
                    angle_rates.size(), stack.num_layers()));
  }
  return laminate_impl(stack, &angle_rates, &derivative);
}

RestForms single_material_rest_forms(const std::vector<Eigen::Matrix2d>& a_bar,
                                     const std::vector<Eigen::Matrix2d>& b_bar,
                                     const Eigen::VectorXd& thickness,
                                     const Eigen::VectorXd& material_angle,
                                     const Stiffness& stiffness) {
  const int num_faces = static_cast<int>(thickness.size());
  if (static_cast<int>(a_bar.size()) != num_faces || static_cast<int>(b_bar.size()) != num_faces ||
      material_angle.size() != num_faces) {
    throw std::invalid_argument(
        fmt::format("rest forms: {} first and {} second forms, {} material angles for "
                    "{} faces: give one of each per face",
                    a_bar.size(), b_bar.size(), material_angle.size(), num_faces));
  }
  RestForms out;
  out.rest_first_fundamental_form = a_bar;
  out.rest_second_fundamental_form = b_bar;
  out.thickness = thickness;
  out.energy_scale = stiffness.young_modulus_along * thickness;
  out.stiffness.resize(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    if (!(a_bar[f].determinant() > 0) || !(a_bar[f](0, 0) > 0)) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("face {}: the rest first fundamental form is not positive "
                                  "definite (determinant {}): check the rest forms given for "
                                  "this face",
                                  f, a_bar[f].determinant()));
    }
    const double t = thickness(f);
    const Eigen::Matrix3d p = material_norm(a_bar[f], material_angle(f), stiffness);
    out.stiffness[f] = block_stiffness(t * p, Eigen::Matrix3d::Zero(), t * t * t / 12 * p);
  }
  return out;
}

RestForms laminate(const LayerStack& stack, const LayerShrinkRates& rates,
                   LaminateDerivative& derivative) {
  const int num_faces = stack.num_faces();
  const int num_layers = stack.num_layers();
  bool sizes_match = static_cast<int>(rates.lambda1.size()) == num_layers &&
                     static_cast<int>(rates.printed_thickness.size()) == num_layers;
  for (int k = 0; sizes_match && k < num_layers; ++k) {
    sizes_match =
        rates.lambda1[k].size() == num_faces && rates.printed_thickness[k].size() == num_faces;
  }
  if (!sizes_match) {
    throw std::invalid_argument(
        fmt::format("shrink rates for {} and {} layers for a stack of {} layers of {} faces: give "
                    "one rate per layer and face",
                    rates.lambda1.size(), rates.printed_thickness.size(), num_layers, num_faces));
  }
  RestForms out = laminate(stack);
  std::vector<Eigen::Matrix3d> elasticity;
  for (const Material& m : stack.materials) {
    elasticity.push_back(orthotropic_elasticity_tensor(stiffness_of(m)));
  }
  derivative.stiffness.resize(num_faces);
  derivative.rest.resize(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    // The integrals of laminate_impl differentiated by the chain rule: a layer's post-heating
    // thickness τ = λ3 h moves with h, the face's thickness t = Σ τ with it, so every layer's
    // mid-height (−t/2 + the layers below + τ/2) moves too; λ1 moves the rest metric along the
    // path and the norm P0 = λ1 λ2 Nᵀ C N (N = diag(1/λ1², 1/λ2², 1/λ1² + 1/λ2²)).
    double dt = 0;
    for (int k = 0; k < num_layers; ++k) {
      const Layer& l = stack.layers[k];
      if (l.covers(f)) dt += l.lambda3(f) * rates.printed_thickness[k](f);
    }
    FaceIntegrals rate;
    double bottom = -0.5 * out.thickness(f), d_bottom = -0.5 * dt;
    for (int k = 0; k < num_layers; ++k) {
      const Layer& l = stack.layers[k];
      if (!l.covers(f)) continue;
      const double tau = l.lambda3(f) * l.printed_thickness(f);
      const double d_tau = l.lambda3(f) * rates.printed_thickness[k](f);
      const double mid = bottom + 0.5 * tau, d_mid = d_bottom + 0.5 * d_tau;
      bottom += tau;
      d_bottom += d_tau;
      const double lambda1 = l.lambda1(f), delta = l.delta_lambda1(f), lambda2 = l.lambda2(f);
      const double d_lambda1 = rates.lambda1[k](f);
      const double mean_square = lambda1 * lambda1 + delta * delta / 12.0;
      const double along = tau * mean_square;
      const double d_along = d_tau * mean_square + tau * 2 * lambda1 * d_lambda1;
      const double along_moment = mid * along + lambda1 * delta * tau * tau / 6.0;
      const double d_along_moment = d_mid * along + mid * d_along +
                                    d_lambda1 * delta * tau * tau / 6.0 +
                                    lambda1 * delta * tau * d_tau / 3.0;
      const Eigen::Vector3d metric(along, tau * lambda2 * lambda2, 0);
      const Eigen::Vector3d d_metric(d_along, d_tau * lambda2 * lambda2, 0);
      const Eigen::Vector3d metric_moment(along_moment, mid * tau * lambda2 * lambda2, 0);
      const Eigen::Vector3d d_metric_moment(d_along_moment,
                                            (d_mid * tau + mid * d_tau) * lambda2 * lambda2, 0);
      const Eigen::Matrix3d& c = elasticity[l.material(f)];
      const Eigen::Matrix3d p0 = l.cover(f) * layer_frame_norm(lambda1, lambda2, c);
      const double i1 = 1 / (lambda1 * lambda1), i2 = 1 / (lambda2 * lambda2);
      const Eigen::Matrix3d n = Eigen::Vector3d(i1, i2, i1 + i2).asDiagonal();
      const Eigen::Matrix3d dn =
          Eigen::Vector3d(-2 * i1 / lambda1, 0, -2 * i1 / lambda1).asDiagonal();
      const Eigen::Matrix3d d_p0 =
          d_lambda1 * (p0 / lambda1 + l.cover(f) * lambda1 * lambda2 * (dn * c * n + n * c * dn));
      const Eigen::Matrix3d to_layer = turn(-l.theta(f)), to_plate = turn(l.theta(f));
      const Eigen::Matrix3d p = to_layer.transpose() * p0 * to_layer;
      const Eigen::Matrix3d dp = to_layer.transpose() * d_p0 * to_layer;
      const double depth = tau * mid * mid + tau * tau * tau / 12;
      const double d_depth = d_tau * mid * mid + 2 * tau * mid * d_mid + tau * tau * d_tau / 4;
      rate.a += d_tau * p + tau * dp;
      rate.b += (d_tau * mid + tau * d_mid) * p + tau * mid * dp;
      rate.d += d_depth * p + depth * dp;
      rate.m_a += dp * (to_plate * metric) + p * (to_plate * d_metric);
      rate.m_b += dp * (to_plate * metric_moment) + p * (to_plate * d_metric_moment);
    }
    const Matrix6d dk = block_stiffness(rate.a, rate.b, rate.d);
    Vector6d dm;
    dm << rate.m_a, -2 * rate.m_b;
    const Vector6d rest =
        rest_vector(out.rest_first_fundamental_form[f], out.rest_second_fundamental_form[f]);
    derivative.stiffness[f] = dk;
    derivative.rest[f] = Eigen::LLT<Matrix6d>(out.stiffness[f]).solve(dm - dk * rest);
  }
  return out;
}

}  // namespace flatmorph
