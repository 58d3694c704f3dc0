#include "material/monotone_curve.h"

#include <fmt/core.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"

namespace flatmorph {
namespace {

// Points at which monotonicity is checked on the calibrated range.
constexpr int kMonotoneSamples = 400;
// Slack at the ends of the range (in x's unit), for values read back from text.
constexpr double kRangeSlack = 1e-9;

}  // namespace

double polynomial_value(std::span<const double> c, double x) {
  double value = 0;
  for (size_t i = c.size(); i-- > 0;) value = value * x + c[i];
  return value;
}

std::string monotone_curve_problem(const MonotoneCurve& c, const CurveParameter& p) {
  if (c.coefficients.empty() || c.coefficients.size() > kMaxCurveCoefficients) {
    return fmt::format("it has {} coefficients; give 1 to {} (degree at most {})",
                       c.coefficients.size(), kMaxCurveCoefficients, kMaxCurveCoefficients - 1);
  }
  for (double x : c.coefficients) {
    if (!std::isfinite(x)) return "a coefficient is not a finite number";
  }
  if (!(c.min_x > 0) || !(c.max_x > c.min_x) || !std::isfinite(c.max_x)) {
    return fmt::format("its range [{}, {}] {} is not an interval of positive {}s", c.min_x, c.max_x,
                       p.unit, p.quantity);
  }
  double previous = 0;
  int sign = 0;
  for (int i = 0; i <= kMonotoneSamples; ++i) {
    const double x = c.min_x + (c.max_x - c.min_x) * i / kMonotoneSamples;
    const double value = polynomial_value(c.coefficients, x);
    if (!(value > 0 && value <= 2)) {
      return fmt::format("lambda1 is {:g} at {:g} {}; a shrink ratio lies in (0, 2]", value, x,
                         p.unit);
    }
    if (i > 0) {
      const int s = value > previous ? 1 : (value < previous ? -1 : 0);
      if (s == 0 || (sign != 0 && s != sign)) {
        return fmt::format(
            "lambda1 is not strictly monotone on [{:g}, {:g}] {} (it turns near {:g} {}), so a "
            "shrinkage would have several {}s",
            c.min_x, c.max_x, p.unit, x, p.unit, p.quantity);
      }
      sign = s;
    }
    previous = value;
  }
  return "";
}

double monotone_curve_value(const MonotoneCurve& c, double x, const CurveParameter& p) {
  if (!(x >= c.min_x - kRangeSlack && x <= c.max_x + kRangeSlack)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("{} {:g} {} is outside the calibrated range [{:g}, {:g}] {} of the "
                    "material's {}: stay inside it or calibrate a wider range "
                    "('flatmorph {}')",
                    p.quantity, x, p.unit, c.min_x, c.max_x, p.unit, p.curve, p.ramp_command));
  }
  return polynomial_value(c.coefficients, std::clamp(x, c.min_x, c.max_x));
}

double monotone_curve_inverse(const MonotoneCurve& c, double lambda1, const CurveParameter& p) {
  double lo = c.min_x, hi = c.max_x;
  const double at_lo = polynomial_value(c.coefficients, lo);
  const double at_hi = polynomial_value(c.coefficients, hi);
  const double low_value = std::min(at_lo, at_hi), high_value = std::max(at_lo, at_hi);
  const double slack = 1e-12;
  if (!(lambda1 >= low_value - slack && lambda1 <= high_value + slack)) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("a shrink ratio lambda1 = {:g} (shrinkage {:.1f} %) is outside what the "
                    "material's {} reaches: lambda1 in [{:.4f}, {:.4f}] (shrinkage {:.1f} to "
                    "{:.1f} %) for {}s {:g} to {:g} {}; ask for a shrinkage in that range or "
                    "calibrate a wider one",
                    lambda1, 100 * (1 - lambda1), p.curve, low_value, high_value,
                    100 * (1 - high_value), 100 * (1 - low_value), p.quantity, c.min_x, c.max_x,
                    p.unit));
  }
  // 100 halvings reach the resolution of a double.
  const bool increasing = at_hi > at_lo;
  for (int i = 0; i < 100 && hi - lo > 0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const bool below = polynomial_value(c.coefficients, mid) < lambda1;
    if (below == increasing) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

std::vector<double> fit_monotone_curve(std::span<const double> x, std::span<const double> lambda1,
                                       int max_degree, const CurveParameter& p) {
  if (x.size() != lambda1.size() || x.empty()) {
    throw std::invalid_argument("fit_monotone_curve: x and lambda1 differ in number or are empty");
  }
  std::vector<double> distinct(x.begin(), x.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (distinct.size() < 2) {
    throw UserError(
        ErrorCategory::kFormat,
        fmt::format("the {} needs samples at two or more {}s, the measurements have "
                    "{}: print '{}' with several {}",
                    p.curve, p.quantity, distinct.size(), p.ramp_command, p.values_option));
  }
  const double lo = distinct.front(), hi = distinct.back();
  // Least squares in u = (x - c) / s in [-1, 1]: a Vandermonde matrix in x itself would be badly
  // conditioned (speeds up to 150 mm/s to the 4th power); the result is expanded in powers of x.
  const double c = (lo + hi) / 2, s = (hi - lo) / 2;
  const int top =
      std::min({max_degree, kMaxCurveCoefficients - 1, static_cast<int>(distinct.size()) - 1});
  const Eigen::Index n = static_cast<Eigen::Index>(x.size());
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y(i) = lambda1[static_cast<size_t>(i)];
  std::string last_problem;
  for (int degree = top; degree >= 1; --degree) {
    Eigen::MatrixXd a(n, degree + 1);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = (x[static_cast<size_t>(i)] - c) / s;
      double power = 1;
      for (int k = 0; k <= degree; ++k, power *= u) a(i, k) = power;
    }
    const Eigen::VectorXd b = a.colPivHouseholderQr().solve(y);
    std::vector<double> coefficients(static_cast<size_t>(degree) + 1, 0.0);
    for (int k = 0; k <= degree; ++k) {
      // b_k ((x - c) / s)^k = b_k s^-k sum_j C(k, j) x^j (-c)^(k - j)
      double binomial = 1;
      for (int j = 0; j <= k; ++j) {
        coefficients[static_cast<size_t>(j)] +=
            b(k) / std::pow(s, k) * binomial * std::pow(-c, k - j);
        binomial = binomial * (k - j) / (j + 1);
      }
    }
    last_problem = monotone_curve_problem({coefficients, lo, hi}, p);
    if (last_problem.empty()) return coefficients;
  }
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("no monotone {} fits the measurements ({}): lambda1 should change "
                              "steadily with the {}; check the samples, or calibrate a wider range "
                              "of {}s",
                              p.curve, last_problem, p.quantity, p.quantity));
}

}  // namespace flatmorph
