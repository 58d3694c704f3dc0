#include "gcode/preview.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "raster/raster.h"

namespace flatmorph {
namespace {

std::string hex(const Rgb& c) { return fmt::format("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]); }

struct Box {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
  void add(double x, double y) {
    lo = lo.cwiseMin(Eigen::Vector2d(x, y));
    hi = hi.cwiseMax(Eigen::Vector2d(x, y));
  }
};

// The drawing area shared by every layer: all paths and the outline, plus a margin (mm).
Box drawing_box(const Toolpath& toolpath, const PreviewOptions& options) {
  Box box;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (Eigen::Index i = 0; i < path.points.rows(); ++i)
        box.add(path.points(i, 0), path.points(i, 1));
    }
  }
  for (const Eigen::MatrixX2d& loop : options.outline) {
    for (Eigen::Index i = 0; i < loop.rows(); ++i) box.add(loop(i, 0), loop(i, 1));
  }
  if (!box.lo.allFinite()) {
    box.lo.setZero();
    box.hi.setOnes();
  }
  const double margin = std::max(1.0, 0.03 * (box.hi - box.lo).maxCoeff());
  box.lo.array() -= margin;
  box.hi.array() += margin;
  return box;
}

std::string num(double v) {
  std::string s = fmt::format("{:.3f}", v);
  return s == "-0.000" ? "0.000" : s;
}

double mean_width(const PathPolyline& path) {
  double sum = 0;
  int n = 0;
  for (const SegmentStyle& s : path.segments) {
    if (!s.travel) {
      sum += s.width;
      ++n;
    }
  }
  return n ? sum / n : 0.4;
}

}  // namespace

std::string layer_svg(const Toolpath& toolpath, size_t layer_index, const PreviewOptions& options) {
  if (layer_index >= toolpath.layers.size()) {
    throw std::out_of_range(fmt::format("layer_svg: no layer {}", layer_index));
  }
  const ToolpathLayer& layer = toolpath.layers[layer_index];
  const Box box = drawing_box(toolpath, options);
  const Eigen::Vector2d size = box.hi - box.lo;
  const double legend = std::max(4.0, 0.05 * size.y());  // mm of room for the caption
  std::string svg;
  svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}mm\" height=\"{1}mm\" viewBox=\"{2} "
      "{3} {4} {1}\">\n",
      num(size.x()), num(size.y() + legend), num(box.lo.x()), num(-box.hi.y() - legend),
      num(size.x()));
  svg += fmt::format(
      "<title>layer {} of {}: z = {:.3f} mm, height {:.3f} mm, {} paths, {:.1f} mm extruded, "
      "{:.1f} mm of travel</title>\n",
      layer_index + 1, toolpath.layers.size(), layer.z, layer.height, layer.paths.size(),
      extrusion_length(layer), travel_length(layer));
  const LayerSingularities* marks =
      layer_index < options.singularities.size() ? &options.singularities[layer_index] : nullptr;
  const std::string marks_caption =
      marks ? fmt::format(
                  "; {} direction singularities (red circles), {} stripe forks (orange "
                  "squares)",
                  marks->field.size(), marks->forks.size())
            : "";
  svg += fmt::format(
      "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"{}\" fill=\"#000\">layer {} "
      "of {}, z = {:.3f} mm: {} paths coloured by print order (dark first, yellow last), "
      "travels dashed{}</text>\n",
      num(box.lo.x() + 0.02 * size.x()), num(-box.hi.y() - 0.3 * legend), num(0.45 * legend),
      layer_index + 1, toolpath.layers.size(), layer.z, layer.paths.size(), marks_caption);
  // Plate coordinates have y up, SVG y down: mirror y.
  svg +=
      "<g transform=\"scale(1,-1)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">\n";
  for (const Eigen::MatrixX2d& loop : options.outline) {
    if (loop.rows() < 2) continue;
    svg += "<path fill=\"#eeeeee\" stroke=\"#999999\" stroke-width=\"0.1\" d=\"";
    for (Eigen::Index i = 0; i < loop.rows(); ++i) {
      svg += fmt::format("{}{} {} ", i == 0 ? "M" : "L", num(loop(i, 0)), num(loop(i, 1)));
    }
    svg += "Z\"/>\n";
  }
  const size_t n = layer.paths.size();
  for (size_t p = 0; p < n; ++p) {
    const PathPolyline& path = layer.paths[p];
    svg += fmt::format("<polyline stroke=\"{}\" stroke-width=\"{}\" points=\"",
                       hex(order_color(p, n)), num(mean_width(path)));
    for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
      svg +=
          fmt::format("{}{},{}", i == 0 ? "" : " ", num(path.points(i, 0)), num(path.points(i, 1)));
    }
    svg += "\"/>\n";
  }
  if (options.travels) {
    svg += "<g stroke=\"#888888\" stroke-width=\"0.1\" stroke-dasharray=\"0.6 0.4\">\n";
    for (size_t p = 0; p < n; ++p) {
      const PathPolyline& path = layer.paths[p];
      for (size_t i = 0; i < path.segments.size(); ++i) {
        if (path.segments[i].travel) {
          svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>\n",
                             num(path.points(i, 0)), num(path.points(i, 1)),
                             num(path.points(i + 1, 0)), num(path.points(i + 1, 1)));
        }
      }
      if (p + 1 < n && path.points.rows() > 0 && layer.paths[p + 1].points.rows() > 0) {
        const Eigen::Index last = path.points.rows() - 1;
        svg +=
            fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>\n",
                        num(path.points(last, 0)), num(path.points(last, 1)),
                        num(layer.paths[p + 1].points(0, 0)), num(layer.paths[p + 1].points(0, 1)));
      }
    }
    svg += "</g>\n";
  }
  if (marks) {
    // Sized by the path width, so that a mark covers about the paths it concerns.
    const double r = 2 * (layer.paths.empty() ? 0.4 : mean_width(layer.paths.front()));
    svg += fmt::format("<g stroke-width=\"{}\">\n", num(0.4 * r));
    for (const Eigen::Vector2d& q : marks->field) {
      svg += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" stroke=\"#d62728\"/>\n", num(q.x()),
                         num(q.y()), num(r));
    }
    for (const Eigen::Vector2d& q : marks->forks) {
      svg +=
          fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" stroke=\"#ff7f0e\"/>\n",
                      num(q.x() - 0.7 * r), num(q.y() - 0.7 * r), num(1.4 * r), num(1.4 * r));
    }
    svg += "</g>\n";
  }
  svg += "</g>\n</svg>\n";
  return svg;
}

void write_layer_svgs(const std::filesystem::path& folder, const Toolpath& toolpath,
                      const PreviewOptions& options) {
  const int digits =
      std::max<int>(3, static_cast<int>(std::to_string(toolpath.layers.size()).size()));
  // The folder appears complete or not at all (an interrupted run leaves no half of it).
  write_folder_atomically(folder, [&](const std::filesystem::path& tmp) {
    for (size_t k = 0; k < toolpath.layers.size(); ++k) {
      const std::string svg = layer_svg(toolpath, k, options);
      write_file_atomically(tmp / fmt::format("layer_{:0{}}.svg", k + 1, digits), true,
                            [&](std::ostream& out) { out << svg; });
    }
  });
}

std::vector<size_t> overview_layers(size_t layer_count, int max_panels) {
  std::vector<size_t> shown;
  const size_t panels = std::min(layer_count, static_cast<size_t>(std::max(1, max_panels)));
  for (size_t i = 0; i < panels; ++i) {
    shown.push_back(panels == 1 ? 0 : (i * (layer_count - 1) + (panels - 1) / 2) / (panels - 1));
  }
  shown.erase(std::unique(shown.begin(), shown.end()), shown.end());
  return shown;
}

std::vector<unsigned char> overview_png(const Toolpath& toolpath, const PreviewOptions& options) {
  const std::vector<size_t> shown = overview_layers(toolpath.layers.size(), options.max_panels);
  const int count = std::max<int>(1, static_cast<int>(shown.size()));
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const int rows = (count + cols - 1) / cols;
  const int side = std::max(32, options.panel_pixels);
  const int gap = 4;
  Canvas canvas(cols * side + (cols + 1) * gap, rows * side + (rows + 1) * gap);
  canvas.rect(0, 0, canvas.width, canvas.height, {200, 200, 200});

  const Box box = drawing_box(toolpath, options);
  const double scale = (side - 4) / (box.hi - box.lo).maxCoeff();  // pixels per mm
  for (int i = 0; i < static_cast<int>(shown.size()); ++i) {
    const int ox = gap + (i % cols) * (side + gap);
    const int oy = gap + (i / cols) * (side + gap);
    canvas.rect(ox, oy, ox + side, oy + side, {255, 255, 255});
    const Eigen::Vector4i clip(ox, oy, ox + side, oy + side);
    // Centre the drawing in the panel, y up.
    const Eigen::Vector2d center = (box.lo + box.hi) / 2;
    auto px = [&](double x, double y) {
      return Eigen::Vector2d(ox + side / 2.0 + (x - center.x()) * scale,
                             oy + side / 2.0 - (y - center.y()) * scale);
    };
    for (const Eigen::MatrixX2d& loop : options.outline) {
      for (Eigen::Index k = 0; k < loop.rows(); ++k) {
        const Eigen::Index next = (k + 1) % loop.rows();
        canvas.segment(px(loop(k, 0), loop(k, 1)), px(loop(next, 0), loop(next, 1)), 0.5,
                       {150, 150, 150}, clip);
      }
    }
    const ToolpathLayer& layer = toolpath.layers[shown[i]];
    const size_t n = layer.paths.size();
    for (size_t p = 0; p < n; ++p) {
      const PathPolyline& path = layer.paths[p];
      const Rgb color = order_color(p, n);
      for (size_t s = 0; s < path.segments.size(); ++s) {
        const Eigen::Vector2d a = px(path.points(s, 0), path.points(s, 1));
        const Eigen::Vector2d b = px(path.points(s + 1, 0), path.points(s + 1, 1));
        if (path.segments[s].travel) {
          if (options.travels) canvas.segment(a, b, 0.3, {150, 150, 150}, clip);
          continue;
        }
        canvas.segment(a, b, std::max(0.5, path.segments[s].width * scale / 2), color, clip);
      }
      if (options.travels && p + 1 < n && path.points.rows() > 0 &&
          layer.paths[p + 1].points.rows() > 0) {
        const Eigen::Index last = path.points.rows() - 1;
        const Eigen::Vector2d a = px(path.points(last, 0), path.points(last, 1));
        const Eigen::Vector2d b =
            px(layer.paths[p + 1].points(0, 0), layer.paths[p + 1].points(0, 1));
        // Dashes of 4 pixels every 8.
        const double len = (b - a).norm();
        for (double t = 0; t < len; t += 8) {
          canvas.segment(a + (b - a) * (t / len), a + (b - a) * (std::min(len, t + 4) / len), 0.3,
                         {150, 150, 150}, clip);
        }
      }
    }
    if (shown[i] < options.singularities.size()) {
      const LayerSingularities& marks = options.singularities[shown[i]];
      auto ring = [&](const Eigen::Vector2d& q, double radius, const Rgb& c, int corners) {
        const Eigen::Vector2d center = px(q.x(), q.y());
        for (int k = 0; k < corners; ++k) {
          const double a0 = 2 * std::numbers::pi * k / corners + std::numbers::pi / 4,
                       a1 = 2 * std::numbers::pi * (k + 1) / corners + std::numbers::pi / 4;
          canvas.segment(center + radius * Eigen::Vector2d(std::cos(a0), std::sin(a0)),
                         center + radius * Eigen::Vector2d(std::cos(a1), std::sin(a1)), 0.6, c,
                         clip);
        }
      };
      for (const Eigen::Vector2d& q : marks.field) ring(q, 4, {214, 39, 40}, 12);
      for (const Eigen::Vector2d& q : marks.forks) ring(q, 3.5, {255, 127, 14}, 4);
    }
    draw_text(canvas, ox + 4, oy + 4, std::to_string(shown[i] + 1), 2, {0, 0, 0});
  }
  return encode_png(canvas);
}

void write_overview_png(const std::filesystem::path& path, const Toolpath& toolpath,
                        const PreviewOptions& options) {
  const std::vector<unsigned char> png = overview_png(toolpath, options);
  write_file_atomically(path, true, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

}  // namespace flatmorph
