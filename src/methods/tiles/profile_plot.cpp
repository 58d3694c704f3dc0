#include "methods/tiles/profile_plot.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "common/markup.h"

namespace flatmorph {
namespace {

struct Frame {
  double x0, y0, scale, left, top;
  double x(double rho) const { return left + (rho - x0) * scale; }
  double y(double z) const { return top - (z - y0) * scale; }
};

std::string polyline(const Eigen::MatrixX2d& points, const Frame& frame, const std::string& style) {
  if (points.rows() == 0) return {};
  std::string d;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    d += fmt::format("{}{:.2f},{:.2f}", i == 0 ? "" : " ", frame.x(points(i, 0)),
                     frame.y(points(i, 1)));
  }
  return fmt::format("<polyline points=\"{}\" fill=\"none\" {}/>\n", d, style);
}

}  // namespace

std::string profile_plot_svg(const TileMeasure& measure, const std::string& title) {
  double max_rho = 1, max_z = 0.5, min_z = 0;
  for (const Eigen::MatrixX2d* curve : {&measure.target, &measure.geometric, &measure.simulated}) {
    if (curve->rows() == 0) continue;
    max_rho = std::max(max_rho, curve->col(0).maxCoeff());
    max_z = std::max(max_z, curve->col(1).maxCoeff());
    min_z = std::min(min_z, curve->col(1).minCoeff());
  }
  const double width = 640, plot_width = 540;
  const double scale = plot_width / max_rho;
  const double plot_height = (max_z - min_z) * scale;
  const double height = plot_height + 120;
  const Frame frame{0, min_z, scale, 60, 50 + plot_height};
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
      "viewBox=\"0 0 {:.0f} {:.0f}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      "<text x=\"60\" y=\"24\" font-size=\"14\">{}</text>\n",
      width, height, width, height, xml_escape(title));
  // Axes with a tick every 5 or 10 mm.
  const double tick = max_rho > 40 ? 10 : 5;
  svg += fmt::format(
      "<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" stroke=\"#888\"/>\n",
      frame.x(0), frame.y(0), frame.x(max_rho));
  for (double r = 0; r <= max_rho + 1e-9; r += tick) {
    svg += fmt::format(
        "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\" fill=\"#555\">{:g}</text>\n",
        frame.x(r), frame.y(min_z) + 18, r);
  }
  svg += fmt::format(
      "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\" fill=\"#555\">distance to the axis "
      "(mm); height above the rim (mm), one scale</text>\n",
      frame.x(max_rho / 2), frame.y(min_z) + 36);
  for (double z = std::ceil(min_z / tick) * tick; z <= max_z + 1e-9; z += tick) {
    svg += fmt::format(
        "<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"end\" fill=\"#555\">{:g}</text>\n",
        frame.x(0) - 6, frame.y(z) + 4, z);
  }
  svg += polyline(measure.target, frame,
                  "stroke=\"#999\" stroke-width=\"2\" stroke-dasharray=\"6 4\"");
  svg += polyline(measure.geometric, frame, "stroke=\"#1f6fb4\" stroke-width=\"1.5\"");
  for (Eigen::Index i = 0; i < measure.simulated.rows(); ++i) {
    svg += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"1.6\" fill=\"#d62728\"/>\n",
                       frame.x(measure.simulated(i, 0)), frame.y(measure.simulated(i, 1)));
  }
  const double legend_y = height - 40;
  svg += fmt::format(
      "<line x1=\"60\" y1=\"{0:.0f}\" x2=\"90\" y2=\"{0:.0f}\" stroke=\"#999\" stroke-width=\"2\" "
      "stroke-dasharray=\"6 4\"/><text x=\"96\" y=\"{1:.0f}\">asked</text>\n"
      "<line x1=\"160\" y1=\"{0:.0f}\" x2=\"190\" y2=\"{0:.0f}\" stroke=\"#1f6fb4\" "
      "stroke-width=\"1.5\"/><text x=\"196\" y=\"{1:.0f}\">the printed shrink, "
      "geometrically</text>\n"
      "<circle cx=\"395\" cy=\"{0:.0f}\" r=\"3\" fill=\"#d62728\"/><text x=\"404\" "
      "y=\"{1:.0f}\">simulated ({2:+.1f} % depth, {3:.2f} mm rms)</text>\n",
      legend_y, legend_y + 4, measure.depth_error_pct, measure.profile_rms_mm);
  svg += "</svg>\n";
  return svg;
}

}  // namespace flatmorph
