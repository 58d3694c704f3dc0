#include "calibration/fit.h"

#include <fmt/core.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.h"

namespace flatmorph {
namespace {

MeanStd mean_std(const std::vector<double>& v) {
  MeanStd r;
  if (v.empty()) return r;
  for (double x : v) r.mean += x;
  r.mean /= static_cast<double>(v.size());
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - r.mean) * (x - r.mean);
    r.std = std::sqrt(ss / static_cast<double>(v.size() - 1));
  }
  return r;
}

// A tick step of 1, 2 or 5 times a power of ten giving about five ticks over `range`.
double tick_step(double range) {
  const double raw = range / 5;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double f : {1.0, 2.0, 5.0, 10.0}) {
    if (f * magnitude >= raw) return f * magnitude;
  }
  return 10 * magnitude;
}

}  // namespace

std::vector<SetFit> fit_sets(const MeasurementSheet& sheet) {
  const std::vector<SampleRatios> ratios = sample_ratios(sheet);
  std::vector<SetFit> out;
  std::vector<int> order;
  for (const SampleMeasurement& m : sheet.rows) {
    if (std::find(order.begin(), order.end(), m.set) == order.end()) order.push_back(m.set);
  }
  for (int id : order) {
    std::vector<double> l1, l2, l3, c, kappa, dl, t;
    bool all_curved = true;
    for (const SampleRatios& r : ratios) {
      if (r.set != id) continue;
      l1.push_back(r.lambda1);
      l2.push_back(r.lambda2);
      l3.push_back(r.lambda3);
      c.push_back(r.contraction_pct);
      if (r.curvature) {
        kappa.push_back(*r.curvature);
        dl.push_back(*r.delta_lambda1);
      } else {
        all_curved = false;
      }
    }
    if (l1.empty()) continue;
    SetFit f;
    f.set = id;
    f.thickness_ramp = sheet.thickness_ramp;
    for (const SampleMeasurement& m : sheet.rows) {
      if (m.set != id) continue;
      f.nozzle_temperature = m.nozzle_temperature;
      f.layer_height = m.layer_height;
      f.layers = m.layers;
      if (!m.skipped) t.push_back(m.thickness_before);
    }
    f.thickness = mean_std(t).mean;
    f.samples = static_cast<int>(l1.size());
    f.lambda1 = mean_std(l1);
    f.lambda2 = mean_std(l2);
    f.lambda3 = mean_std(l3);
    f.contraction_pct = mean_std(c);
    if (all_curved) {
      f.curvature = mean_std(kappa);
      f.delta_lambda1 = mean_std(dl);
    }
    out.push_back(f);
  }
  return out;
}

void rank_sets(std::vector<SetFit>& sets) {
  std::stable_sort(sets.begin(), sets.end(), [](const SetFit& a, const SetFit& b) {
    if (a.contraction_pct.mean != b.contraction_pct.mean) {
      return a.contraction_pct.mean > b.contraction_pct.mean;
    }
    if (a.contraction_pct.std != b.contraction_pct.std) {
      return a.contraction_pct.std < b.contraction_pct.std;
    }
    return a.set < b.set;
  });
}

Material fitted_material(const Material& base, const SetFit& set, const std::string& name,
                         const std::string& description) {
  Material m = base;
  m.name = name;
  m.description = description;
  m.lambda1 = set.lambda1.mean;
  m.lambda2 = set.lambda2.mean;
  m.lambda3 = set.lambda3.mean;
  if (set.delta_lambda1) m.delta_lambda1 = set.delta_lambda1->mean;
  m.layer_height = set.layer_height;
  m.nozzle_temperature = set.nozzle_temperature;
  m.min_nozzle_temperature = std::min(m.min_nozzle_temperature, set.nozzle_temperature);
  m.max_nozzle_temperature = std::max(m.max_nozzle_temperature, set.nozzle_temperature);
  // The material file's own checks, so that what is written can be read back.
  try {
    return parse_material_json(material_json(m), "fitted");
  } catch (const UserError& e) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("set {} gives a material no file can hold ({}); check its "
                                "measurements",
                                set.set, e.what()));
  }
}

ThicknessCurve fit_thickness_curve(const std::vector<double>& h, const std::vector<double>& lambda1,
                                   int layers, double nozzle_temperature, int max_degree) {
  if (h.size() != lambda1.size() || h.empty()) {
    throw std::invalid_argument("fit_thickness_curve: heights and ratios differ in number");
  }
  std::vector<double> distinct = h;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (distinct.size() < 2) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("the thickness curve needs samples at two or more layer heights, "
                                "the measurements have {}: print 'calibrate print "
                                "--thickness-ramp' with several --layer-heights",
                                distinct.size()));
  }
  const double lo = distinct.front(), hi = distinct.back();
  // Least squares in u = (h - c) / s in [-1, 1], which keeps the Vandermonde matrix well
  // conditioned; the coefficients are then expanded in powers of h.
  const double c = (lo + hi) / 2, s = (hi - lo) / 2;
  const int top = std::min({max_degree, 4, static_cast<int>(distinct.size()) - 1});
  const Eigen::Index n = static_cast<Eigen::Index>(h.size());
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y(i) = lambda1[static_cast<size_t>(i)];
  std::string last_problem;
  for (int degree = top; degree >= 1; --degree) {
    Eigen::MatrixXd a(n, degree + 1);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = (h[static_cast<size_t>(i)] - c) / s;
      double power = 1;
      for (int k = 0; k <= degree; ++k, power *= u) a(i, k) = power;
    }
    const Eigen::VectorXd b = a.colPivHouseholderQr().solve(y);
    ThicknessCurve curve;
    curve.lambda1_coefficients.assign(static_cast<size_t>(degree) + 1, 0.0);
    for (int k = 0; k <= degree; ++k) {
      // b_k ((h - c) / s)^k = b_k s^-k sum_j C(k, j) h^j (-c)^(k - j)
      double binomial = 1;
      for (int j = 0; j <= k; ++j) {
        curve.lambda1_coefficients[static_cast<size_t>(j)] +=
            b(k) / std::pow(s, k) * binomial * std::pow(-c, k - j);
        binomial = binomial * (k - j) / (j + 1);
      }
    }
    curve.min_layer_height = lo;
    curve.max_layer_height = hi;
    curve.layers = layers;
    curve.nozzle_temperature = nozzle_temperature;
    last_problem = thickness_curve_problem(curve);
    if (last_problem.empty()) return curve;
  }
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("no monotone thickness curve fits the measurements ({}): lambda1 "
                              "should change steadily with the layer height; check the samples, "
                              "or calibrate a wider range of layer heights",
                              last_problem));
}

ThicknessCurve fit_thickness_curve(const MeasurementSheet& sheet, int max_degree) {
  std::vector<double> h, l1;
  int layers = 0;
  double temperature = 0;
  for (const SampleMeasurement& m : sheet.rows) {
    if (m.skipped) continue;
    h.push_back(m.layer_height);
    l1.push_back(m.length_after / m.length_before);
    layers = m.layers;
    temperature = m.nozzle_temperature;
  }
  if (h.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: every sample is skipped; nothing to fit", sheet.source));
  }
  return fit_thickness_curve(h, l1, layers, temperature, max_degree);
}

std::string contraction_plot_svg(const std::vector<SetFit>& sets,
                                 const std::optional<ThicknessCurve>& curve) {
  // Plot area in SVG units (1 unit = 1 px), margins for the axes and the legend.
  const double w = 520, hgt = 340, left = 60, right = 150, top = 30, bottom = 50;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const SetFit& s : sets) {
    x0 = std::min(x0, s.layer_height);
    x1 = std::max(x1, s.layer_height);
    y0 = std::min(y0, s.contraction_pct.mean - s.contraction_pct.std);
    y1 = std::max(y1, s.contraction_pct.mean + s.contraction_pct.std);
  }
  std::vector<std::pair<double, double>> curve_points;
  if (curve) {
    for (int i = 0; i <= 100; ++i) {
      const double h =
          curve->min_layer_height + (curve->max_layer_height - curve->min_layer_height) * i / 100;
      const double c = 100 * (1 - lambda1_at_layer_height(*curve, h));
      curve_points.emplace_back(h, c);
      x0 = std::min(x0, h);
      x1 = std::max(x1, h);
      y0 = std::min(y0, c);
      y1 = std::max(y1, c);
    }
  }
  if (x1 - x0 < 1e-9) {
    x0 -= 0.02;
    x1 += 0.02;
  }
  if (y1 - y0 < 1e-9) {
    y0 -= 1;
    y1 += 1;
  }
  const double px = (x1 - x0) * 0.08, py = (y1 - y0) * 0.1;
  x0 -= px, x1 += px, y0 -= py, y1 += py;
  auto X = [&](double x) { return left + (x - x0) / (x1 - x0) * w; };
  auto Y = [&](double y) { return top + (y1 - y) / (y1 - y0) * hgt; };
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
      "viewBox=\"0 0 {0:.0f} {1:.0f}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      left + w + right, top + hgt + bottom);
  svg += fmt::format(
      "<text x=\"{:.1f}\" y=\"18\" text-anchor=\"middle\">Contraction along the paths vs layer "
      "height (mean, error bars 1 std)</text>\n",
      left + w / 2);
  svg += fmt::format(
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" "
      "stroke=\"black\"/>\n",
      left, top, w, hgt);
  const double sx = tick_step(x1 - x0), sy = tick_step(y1 - y0);
  for (double t = std::ceil(x0 / sx) * sx; t <= x1 + 1e-12; t += sx) {
    svg += fmt::format(
        "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" "
        "stroke=\"#ddd\"/><text x=\"{0:.2f}\" y=\"{3:.2f}\" "
        "text-anchor=\"middle\">{4:g}</text>\n",
        X(t), top, top + hgt, top + hgt + 16, std::round(t / sx) * sx);
  }
  for (double t = std::ceil(y0 / sy) * sy; t <= y1 + 1e-12; t += sy) {
    svg += fmt::format(
        "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{2:.2f}\" y2=\"{1:.2f}\" "
        "stroke=\"#ddd\"/><text x=\"{3:.2f}\" y=\"{4:.2f}\" "
        "text-anchor=\"end\">{5:g}</text>\n",
        left, Y(t), left + w, left - 6, Y(t) + 4, std::round(t / sy) * sy);
  }
  svg += fmt::format(
      "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">layer height "
      "(mm)</text>\n",
      left + w / 2, top + hgt + 38);
  svg += fmt::format(
      "<text transform=\"translate(18 {:.1f}) rotate(-90)\" "
      "text-anchor=\"middle\">contraction (%)</text>\n",
      top + hgt / 2);
  static const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                  "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  std::map<double, std::vector<const SetFit*>> by_temperature;
  for (const SetFit& s : sets) by_temperature[s.nozzle_temperature].push_back(&s);
  int index = 0;
  double legend_y = top + 10;
  for (auto& [temperature, group] : by_temperature) {
    const char* color = kColors[index++ % 8];
    std::sort(group.begin(), group.end(),
              [](const SetFit* a, const SetFit* b) { return a->layer_height < b->layer_height; });
    std::string points;
    for (const SetFit* s : group) {
      points += fmt::format("{:.2f},{:.2f} ", X(s->layer_height), Y(s->contraction_pct.mean));
    }
    svg += fmt::format(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" "
        "stroke-width=\"1.5\"/>\n",
        points, color);
    for (const SetFit* s : group) {
      const double x = X(s->layer_height), lo = Y(s->contraction_pct.mean - s->contraction_pct.std),
                   hi = Y(s->contraction_pct.mean + s->contraction_pct.std);
      svg += fmt::format(
          "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"{3}\"/>"
          "<line x1=\"{4:.2f}\" y1=\"{1:.2f}\" x2=\"{5:.2f}\" y2=\"{1:.2f}\" stroke=\"{3}\"/>"
          "<line x1=\"{4:.2f}\" y1=\"{2:.2f}\" x2=\"{5:.2f}\" y2=\"{2:.2f}\" stroke=\"{3}\"/>"
          "<circle cx=\"{0:.2f}\" cy=\"{6:.2f}\" r=\"3\" fill=\"{3}\"/>\n",
          x, lo, hi, color, x - 4, x + 4, Y(s->contraction_pct.mean));
    }
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" "
        "stroke=\"{3}\" stroke-width=\"2\"/><text x=\"{4:.1f}\" y=\"{5:.1f}\">{6:g} "
        "C</text>\n",
        left + w + 12, legend_y, left + w + 32, color, left + w + 38, legend_y + 4, temperature);
    legend_y += 18;
  }
  if (curve) {
    std::string points;
    for (const auto& [h, c] : curve_points) points += fmt::format("{:.2f},{:.2f} ", X(h), Y(c));
    svg += fmt::format(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"#555\" "
        "stroke-dasharray=\"5 3\"/>\n",
        points);
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" "
        "stroke=\"#555\" stroke-dasharray=\"5 3\"/><text x=\"{3:.1f}\" "
        "y=\"{4:.1f}\">thickness curve</text>\n",
        left + w + 12, legend_y, left + w + 32, left + w + 38, legend_y + 4);
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace flatmorph
