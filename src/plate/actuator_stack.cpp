#include "plate/actuator_stack.h"

#include <fmt/core.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/error.h"
#include "material/speed_curve.h"
#include "plate/laminate.h"

namespace flatmorph {
namespace {

// Notes §5: ε(3000 mm/min) = 0.118 (Geodesy Fig. 2a, 0.2 mm layers), growing to 0.25 at
// 9000 mm/min, linearly in between: the guess that puts the paper's reference sample (20 mm wide,
// 5000 mm/min, case A) near 90 degrees with a PLA 7 times as stiff as the TPU.
constexpr double kSlowShrink = 0.118;
constexpr double kFastShrink = 0.25;

// Speeds at which the default curve is fitted to the laminate.
constexpr int kDefaultCurveSamples = 17;
constexpr int kDefaultCurveDegree = 4;

void require_usable(const HingeStack& stack) {
  if (std::string problem = hinge_stack_problem(stack); !problem.empty()) {
    throw UserError(ErrorCategory::kOption, "the actuator's layer stack is unusable: " + problem);
  }
}

}  // namespace

std::pair<double, double> active_speed_range(const Material& pla) {
  if (pla.speed_curve) return {pla.speed_curve->min_print_speed, pla.speed_curve->max_print_speed};
  return {kDefaultActiveMinSpeed, kDefaultActiveMaxSpeed};
}

double active_lambda1(const Material& pla, const HingeStack& stack, double speed) {
  const auto [lo, hi] = active_speed_range(pla);
  if (!(speed >= lo - 1e-9 && speed <= hi + 1e-9)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("active PLA printed at {:g} mm/s: material {} knows its shrink from {:g} to "
                    "{:g} mm/s ({}); choose a speed in that range",
                    speed, pla.name, lo, hi,
                    pla.speed_curve ? "its calibrated speed curve"
                                    : "Thermorph's 3000-9000 mm/min, uncalibrated"));
  }
  if (pla.speed_curve) return printed_lambda1(pla, stack.layer_height, speed);
  const double t =
      (speed - kDefaultActiveMinSpeed) / (kDefaultActiveMaxSpeed - kDefaultActiveMinSpeed);
  return 1 - (kSlowShrink + t * (kFastShrink - kSlowShrink));
}

Material thermorph_pla(const Material& pla, const HingeStack& stack) {
  Material out = pla;
  const bool calibrated = pla.speed_curve.has_value();
  if (!calibrated) {
    SpeedCurve curve;
    const double slope =
        -(kFastShrink - kSlowShrink) / (kDefaultActiveMaxSpeed - kDefaultActiveMinSpeed);
    curve.lambda1_coefficients = {1 - kSlowShrink - slope * kDefaultActiveMinSpeed, slope};
    curve.min_print_speed = kDefaultActiveMinSpeed;
    curve.max_print_speed = kDefaultActiveMaxSpeed;
    curve.layer_height = stack.layer_height;
    out.speed_curve = curve;
  }
  // λ1 at the print speed the ratios stand for, so that printed_lambda1 scales from there (a
  // material's print speed lies in its speed curve's range).
  if (calibrated) {
    out.lambda1 = printed_lambda1(pla, stack.layer_height, pla.print_speed);
  } else {
    out.print_speed = std::clamp(pla.print_speed, kDefaultActiveMinSpeed, kDefaultActiveMaxSpeed);
    out.lambda1 = lambda1_at_print_speed(*out.speed_curve, out.print_speed);
  }
  out.thickness_curve.reset();
  out.lambda2 = 1;
  out.lambda3 = 1;
  out.delta_lambda1 = std::abs(pla.delta_lambda1);
  return out;
}

LayerStack actuator_layer_stack(const Material& pla, const Material& tpu, const HingeStack& stack,
                                double lambda1, bool pla_on_bed, double line_direction,
                                int num_faces) {
  require_usable(stack);
  if (num_faces < 1 || !(lambda1 > 0 && lambda1 <= 2)) {
    throw std::invalid_argument(fmt::format(
        "actuator_layer_stack: {} faces, lambda1 {}; give faces and a shrink ratio in (0, 2]",
        num_faces, lambda1));
  }
  LayerStack out;
  out.materials = {pla, tpu};
  // λ1 rises through the PLA from the bed side up by |Δλ1| whatever the sign the material was
  // measured with (Fig. 5 text: the bed side shrinks more), the same at every speed: layer j of n
  // has its mean at the height (j + 1/2)/n − 1/2 of the PLA and a share 1/n of the rise. (Scaling
  // the rise with the shrink instead makes case B's curvature turn back above 6000 mm/min, as the
  // laminate's bilayer term grows less than linearly: no speed could be solved for.)
  const double rise = std::abs(pla.delta_lambda1);
  std::vector<Layer> active;
  for (int j = 0; j < stack.pla_layers; ++j) {
    Layer l = uniform_layer(num_faces, 0, pla, stack.layer_height);
    l.theta.setConstant(line_direction);
    l.lambda1.setConstant(lambda1 + ((j + 0.5) / stack.pla_layers - 0.5) * rise);
    l.delta_lambda1.setConstant(rise / stack.pla_layers);
    l.lambda2.setOnes();
    l.lambda3.setOnes();
    active.push_back(std::move(l));
  }
  std::vector<Layer> constraint;
  for (int j = 0; j < stack.tpu_layers; ++j) {
    Layer l = uniform_layer(num_faces, 1, tpu, stack.layer_height);
    l.theta.setConstant(line_direction + std::numbers::pi / 2);  // along the hinge (notes §8)
    constraint.push_back(std::move(l));
  }
  const std::vector<Layer>& first = pla_on_bed ? active : constraint;
  const std::vector<Layer>& second = pla_on_bed ? constraint : active;
  out.layers = first;
  out.layers.insert(out.layers.end(), second.begin(), second.end());
  return out;
}

double actuator_curvature(const Material& pla, const Material& tpu, const HingeStack& stack,
                          double lambda1, bool pla_on_bed) {
  const RestForms forms =
      laminate(actuator_layer_stack(pla, tpu, stack, lambda1, pla_on_bed, 0, 1));
  // The rest forms curl the strip along the hinge (y) as well: the TPU's Poisson expansion and the
  // PLA's orthotropic coupling (Eq. 4) leave b̄_yy as large as b̄_xx. The faces on both sides hold
  // the actuator straight along the hinge, so it takes the cheapest state with b_yy = b_xy = 0
  // (cylindrical bending): the minimum of ¼ (s − s̄)ᵀ K (s − s̄) over a and b_xx.
  const Matrix6d& k = forms.stiffness[0];
  const Vector6d rest =
      rest_vector(forms.rest_first_fundamental_form[0], forms.rest_second_fundamental_form[0]);
  const Eigen::Matrix4d free_block = k.topLeftCorner<4, 4>();
  const Eigen::Vector4d shift = free_block.ldlt().solve(k.topRightCorner<4, 2>() * rest.tail<2>());
  const Eigen::Vector4d held = rest.head<4>() + shift;  // (a_xx, a_yy, a_xy, b_xx)
  return held(3) / std::sqrt(held(0));
}

HingeCurve default_hinge_curve(const Material& pla, const Material& tpu, const HingeStack& stack) {
  require_usable(stack);
  HingeCurve curve;
  curve.stack = stack;
  std::tie(curve.min_speed, curve.max_speed) = active_speed_range(pla);
  for (bool pla_on_bed : {true, false}) {
    std::vector<double> speeds, curvatures;
    for (int i = 0; i < kDefaultCurveSamples; ++i) {
      const double v =
          curve.min_speed + (curve.max_speed - curve.min_speed) * i / (kDefaultCurveSamples - 1);
      // Case A folds toward the bed (b̄ < 0), case B away from it.
      const double kappa =
          (pla_on_bed ? -1 : 1) *
          actuator_curvature(pla, tpu, stack, active_lambda1(pla, stack, v), pla_on_bed);
      if (!(kappa > 0)) {
        throw UserError(
            ErrorCategory::kProfile,
            fmt::format("with PLA {} (delta_lambda1 {:g}) on TPU {}, a {} actuator printed at "
                        "{:g} mm/s would fold {}: the PLA's shrink gradient outweighs the TPU's "
                        "constraint, and the default hinge model has no answer; calibrate the "
                        "hinges ('flatmorph calibrate print --hinge-sheet')",
                        pla.name, pla.delta_lambda1, tpu.name, hinge_case_name(pla_on_bed), v,
                        kappa == 0 ? "not at all" : "the wrong way"));
      }
      speeds.push_back(v);
      curvatures.push_back(kappa);
    }
    try {
      (pla_on_bed ? curve.case_a_coefficients : curve.case_b_coefficients) =
          fit_monotone_curve(speeds, curvatures, kDefaultCurveDegree, kHingeCurveParameter);
    } catch (const UserError&) {
      throw UserError(ErrorCategory::kProfile,
                      fmt::format("with PLA {} on TPU {}, a {} actuator's fold does not change "
                                  "steadily with the speed ({:.4f} to {:.4f} /mm), and the "
                                  "default hinge model has no answer; calibrate the hinges "
                                  "('flatmorph calibrate print --hinge-sheet')",
                                  pla.name, tpu.name, hinge_case_name(pla_on_bed),
                                  curvatures.front(), curvatures.back()));
    }
  }
  return curve;
}

}  // namespace flatmorph
