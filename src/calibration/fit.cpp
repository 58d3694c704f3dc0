#include "calibration/fit.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.h"
#include "material/monotone_curve.h"

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

// What a contraction plot puts along x.
struct PlotAxis {
  double (*x)(const SetFit&);  // the set's value (layer height, print speed)
  const char* quantity;        // "layer height"
  const char* unit;            // "mm"
  const char* curve;           // legend of the dashed curve
  double flat_pad;             // half-width of the x range when every set has the same x
};

// Contraction (%) of `sets` versus axis.x, one polyline per nozzle temperature with error bars,
// and `curve` (when it has coefficients) dashed over its range.
std::string contraction_plot(const std::vector<SetFit>& sets, const MonotoneCurve& curve,
                             const PlotAxis& axis) {
  // Plot area in SVG units (1 unit = 1 px), margins for the axes and the legend.
  const double w = 520, hgt = 340, left = 60, right = 150, top = 30, bottom = 50;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const SetFit& s : sets) {
    x0 = std::min(x0, axis.x(s));
    x1 = std::max(x1, axis.x(s));
    y0 = std::min(y0, s.contraction_pct.mean - s.contraction_pct.std);
    y1 = std::max(y1, s.contraction_pct.mean + s.contraction_pct.std);
  }
  std::vector<std::pair<double, double>> curve_points;
  if (!curve.coefficients.empty()) {
    for (int i = 0; i <= 100; ++i) {
      const double x = curve.min_x + (curve.max_x - curve.min_x) * i / 100;
      const double c = 100 * (1 - polynomial_value(curve.coefficients, x));
      curve_points.emplace_back(x, c);
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, c);
      y1 = std::max(y1, c);
    }
  }
  if (x0 > x1) {  // nothing to plot: empty axes
    x0 = y0 = 0;
    x1 = y1 = 1;
  }
  if (x1 - x0 < 1e-9) {
    x0 -= axis.flat_pad;
    x1 += axis.flat_pad;
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
      "<text x=\"{:.1f}\" y=\"18\" text-anchor=\"middle\">Contraction along the paths vs {} "
      "(mean, error bars 1 std)</text>\n",
      left + w / 2, axis.quantity);
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
  svg += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{} ({})</text>\n",
                     left + w / 2, top + hgt + 38, axis.quantity, axis.unit);
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
              [&axis](const SetFit* a, const SetFit* b) { return axis.x(*a) < axis.x(*b); });
    std::string points;
    for (const SetFit* s : group) {
      points += fmt::format("{:.2f},{:.2f} ", X(axis.x(*s)), Y(s->contraction_pct.mean));
    }
    svg += fmt::format(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" "
        "stroke-width=\"1.5\"/>\n",
        points, color);
    for (const SetFit* s : group) {
      const double x = X(axis.x(*s)), lo = Y(s->contraction_pct.mean - s->contraction_pct.std),
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
  if (!curve_points.empty()) {
    std::string points;
    for (const auto& [x, c] : curve_points) points += fmt::format("{:.2f},{:.2f} ", X(x), Y(c));
    svg += fmt::format(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"#555\" "
        "stroke-dasharray=\"5 3\"/>\n",
        points);
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" "
        "stroke=\"#555\" stroke-dasharray=\"5 3\"/><text x=\"{3:.1f}\" "
        "y=\"{4:.1f}\">{5}</text>\n",
        left + w + 12, legend_y, left + w + 32, left + w + 38, legend_y + 4, axis.curve);
  }
  svg += "</svg>\n";
  return svg;
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
    f.speed_ramp = sheet.speed_ramp;
    for (const SampleMeasurement& m : sheet.rows) {
      if (m.set != id) continue;
      f.nozzle_temperature = m.nozzle_temperature;
      f.layer_height = m.layer_height;
      f.layers = m.layers;
      f.print_speed = m.print_speed;
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
  if (set.print_speed > 0) m.print_speed = set.print_speed;
  // The base's curves were measured against its own ratios and speed: the caller adds those of the
  // ramps measured with this set (and a base speed curve might not cover the set's speed).
  m.thickness_curve.reset();
  m.speed_curve.reset();
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
  ThicknessCurve curve;
  curve.lambda1_coefficients = fit_monotone_curve(h, lambda1, max_degree, kThicknessCurveParameter);
  curve.min_layer_height = *std::min_element(h.begin(), h.end());
  curve.max_layer_height = *std::max_element(h.begin(), h.end());
  curve.layers = layers;
  curve.nozzle_temperature = nozzle_temperature;
  if (const std::string problem = thickness_curve_problem(curve); !problem.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("the thickness curve of the measurements is unusable ({}); check "
                                "the layers column",
                                problem));
  }
  return curve;
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

SpeedCurve fit_speed_curve(const std::vector<double>& v, const std::vector<double>& lambda1,
                           double layer_height, double nozzle_temperature, int max_degree) {
  SpeedCurve curve;
  curve.lambda1_coefficients = fit_monotone_curve(v, lambda1, max_degree, kSpeedCurveParameter);
  curve.min_print_speed = *std::min_element(v.begin(), v.end());
  curve.max_print_speed = *std::max_element(v.begin(), v.end());
  curve.layer_height = layer_height;
  curve.nozzle_temperature = nozzle_temperature;
  if (const std::string problem = speed_curve_problem(curve); !problem.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("the speed curve of the measurements is unusable ({}); check the "
                                "print_speed column",
                                problem));
  }
  return curve;
}

SpeedCurve fit_speed_curve(const MeasurementSheet& sheet, int max_degree) {
  std::vector<double> v, l1;
  double layer_height = 0, temperature = 0;
  for (const SampleMeasurement& m : sheet.rows) {
    if (m.skipped) continue;
    v.push_back(m.print_speed);
    l1.push_back(m.length_after / m.length_before);
    layer_height = m.layer_height;
    temperature = m.nozzle_temperature;
  }
  if (v.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: every sample is skipped; nothing to fit", sheet.source));
  }
  return fit_speed_curve(v, l1, layer_height, temperature, max_degree);
}

std::string contraction_plot_svg(const std::vector<SetFit>& sets,
                                 const std::optional<ThicknessCurve>& curve) {
  std::vector<SetFit> shown;
  for (const SetFit& s : sets) {
    if (!s.speed_ramp) shown.push_back(s);  // they all share one layer height
  }
  const PlotAxis axis = {[](const SetFit& s) { return s.layer_height; }, "layer height", "mm",
                         "thickness curve", 0.02};
  return contraction_plot(shown,
                          curve ? MonotoneCurve{curve->lambda1_coefficients,
                                                curve->min_layer_height, curve->max_layer_height}
                                : MonotoneCurve{},
                          axis);
}

std::string speed_contraction_plot_svg(const std::vector<SetFit>& sets,
                                       const std::optional<SpeedCurve>& curve) {
  std::vector<SetFit> shown;
  for (const SetFit& s : sets) {
    if (s.speed_ramp) shown.push_back(s);
  }
  const PlotAxis axis = {[](const SetFit& s) { return s.print_speed; }, "print speed", "mm/s",
                         "speed curve", 5.0};
  return contraction_plot(shown,
                          curve ? MonotoneCurve{curve->lambda1_coefficients, curve->min_print_speed,
                                                curve->max_print_speed}
                                : MonotoneCurve{},
                          axis);
}

}  // namespace flatmorph
