#include "material/thickness_curve.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace flatmorph {
namespace {

// Points at which monotonicity is checked on the calibrated range.
constexpr int kMonotoneSamples = 400;
// Slack (mm) at the ends of the range, for heights read back from text.
constexpr double kRangeSlack = 1e-9;

double evaluate(const std::vector<double>& c, double h) {
  double value = 0;
  for (size_t i = c.size(); i-- > 0;) value = value * h + c[i];  // Horner
  return value;
}

void require_range(const ThicknessCurve& curve, double h) {
  if (!(h >= curve.min_layer_height - kRangeSlack && h <= curve.max_layer_height + kRangeSlack)) {
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("layer height {:g} mm is outside the calibrated range [{:g}, {:g}] "
                                "mm of the material's thickness curve: stay inside it or "
                                "calibrate a wider range ('flatmorph calibrate print "
                                "--thickness-ramp')",
                                h, curve.min_layer_height, curve.max_layer_height));
  }
}

}  // namespace

std::string thickness_curve_problem(const ThicknessCurve& c) {
  if (c.lambda1_coefficients.empty() || c.lambda1_coefficients.size() > 5) {
    return fmt::format("it has {} coefficients; give 1 to 5 (degree at most 4)",
                       c.lambda1_coefficients.size());
  }
  for (double x : c.lambda1_coefficients) {
    if (!std::isfinite(x)) return "a coefficient is not a finite number";
  }
  if (!(c.min_layer_height > 0) || !(c.max_layer_height > c.min_layer_height) ||
      !std::isfinite(c.max_layer_height)) {
    return fmt::format("its range [{}, {}] mm is not an interval of positive layer heights",
                       c.min_layer_height, c.max_layer_height);
  }
  if (c.layers < 1) return fmt::format("it was measured on {} layers; give 1 or more", c.layers);
  double previous = 0;
  int sign = 0;
  for (int i = 0; i <= kMonotoneSamples; ++i) {
    const double h =
        c.min_layer_height + (c.max_layer_height - c.min_layer_height) * i / kMonotoneSamples;
    const double value = evaluate(c.lambda1_coefficients, h);
    if (!(value > 0 && value <= 2)) {
      return fmt::format("lambda1 is {:g} at {:g} mm; a shrink ratio lies in (0, 2]", value, h);
    }
    if (i > 0) {
      const int s = value > previous ? 1 : (value < previous ? -1 : 0);
      if (s == 0 || (sign != 0 && s != sign)) {
        return fmt::format(
            "lambda1 is not strictly monotone on [{:g}, {:g}] mm (it turns near "
            "{:g} mm), so a shrinkage would have several layer heights",
            c.min_layer_height, c.max_layer_height, h);
      }
      sign = s;
    }
    previous = value;
  }
  return "";
}

double lambda1_at_layer_height(const ThicknessCurve& curve, double h) {
  require_range(curve, h);
  return evaluate(curve.lambda1_coefficients,
                  std::clamp(h, curve.min_layer_height, curve.max_layer_height));
}

double layer_height_for_lambda1(const ThicknessCurve& curve, double lambda1) {
  double lo = curve.min_layer_height, hi = curve.max_layer_height;
  const double at_lo = evaluate(curve.lambda1_coefficients, lo);
  const double at_hi = evaluate(curve.lambda1_coefficients, hi);
  const double low_value = std::min(at_lo, at_hi), high_value = std::max(at_lo, at_hi);
  const double slack = 1e-12;
  if (!(lambda1 >= low_value - slack && lambda1 <= high_value + slack)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("a shrink ratio lambda1 = {:g} (shrinkage {:.1f} %) is outside what the "
                    "material's thickness curve reaches: lambda1 in [{:.4f}, {:.4f}] (shrinkage "
                    "{:.1f} to {:.1f} %) for layer heights {:g} to {:g} mm; ask for a shrinkage "
                    "in that range or calibrate a wider one",
                    lambda1, 100 * (1 - lambda1), low_value, high_value, 100 * (1 - high_value),
                    100 * (1 - low_value), curve.min_layer_height, curve.max_layer_height));
  }
  // Bisection keeps the answer in the range and is deterministic; 100 halvings reach the
  // resolution of a double.
  const bool increasing = at_hi > at_lo;
  for (int i = 0; i < 100 && hi - lo > 0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const bool below = evaluate(curve.lambda1_coefficients, mid) < lambda1;
    if (below == increasing) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

double layer_height_for_shrinkage(const ThicknessCurve& curve, double shrinkage) {
  return layer_height_for_lambda1(curve, 1 - shrinkage);
}

}  // namespace flatmorph
