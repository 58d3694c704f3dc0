#include "report/gcode_paths.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "common/error.h"

namespace flatmorph {
namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// x_bed = x_plate + 12.345, y_bed = y_plate - 6.789, ...
bool parse_plate_to_bed(const std::string& value, double& tx, double& ty) {
  char sx = 0, sy = 0;
  double ax = 0, ay = 0;
  if (std::sscanf(value.c_str(), "x_bed = x_plate %c %lf, y_bed = y_plate %c %lf", &sx, &ax, &sy,
                  &ay) != 4) {
    return false;
  }
  tx = sx == '-' ? -ax : ax;
  ty = sy == '-' ? -ay : ay;
  return true;
}

struct Word {
  bool has = false;
  double value = 0;
};

}  // namespace

std::string header_value(const GcodePaths& gcode, const std::string& key) {
  for (const auto& [k, v] : gcode.header) {
    if (k == key) return v;
  }
  return "";
}

GcodePaths read_gcode_paths(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: cannot open the G-code file; check the path", path.string()));
  }
  GcodePaths result;
  double tx = 0, ty = 0;
  bool begun = false, header_done = false;
  bool relative_e = false;
  double x = 0, y = 0, z = 0, e = 0;
  double width = 0.4, height = 0.08;
  PathType type = PathType::kSolidInfill;
  PathPolyline current;
  std::vector<Eigen::Vector3d> points;
  auto flush = [&] {
    if (points.size() >= 2 && !result.toolpath.layers.empty()) {
      current.points.resize(static_cast<Eigen::Index>(points.size()), 3);
      for (size_t i = 0; i < points.size(); ++i) current.points.row(i) = points[i].transpose();
      result.toolpath.layers.back().paths.push_back(std::move(current));
    }
    current = PathPolyline{};
    points.clear();
  };

  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == ';') {
      if (!header_done && line.size() > 2 && line[1] == ' ') {
        const size_t eq = line.find(" = ");
        if (eq != std::string::npos) {
          result.header.emplace_back(trim(line.substr(2, eq - 2)), trim(line.substr(eq + 3)));
        }
      }
      if (line.rfind("; ---- flatmorph: print begins", 0) == 0) {
        begun = true;
      } else if (line.rfind("; ---- end G-code", 0) == 0) {
        flush();
        break;
      } else if (begun && line == ";LAYER_CHANGE") {
        flush();
        result.toolpath.layers.emplace_back();
      } else if (begun && line.rfind(";Z:", 0) == 0 && !result.toolpath.layers.empty()) {
        result.toolpath.layers.back().z = std::atof(line.c_str() + 3);
      } else if (line.rfind(";HEIGHT:", 0) == 0) {
        height = std::atof(line.c_str() + 8);
        if (!result.toolpath.layers.empty() && result.toolpath.layers.back().height == 0) {
          result.toolpath.layers.back().height = height;
        }
      } else if (line.rfind(";WIDTH:", 0) == 0) {
        width = std::atof(line.c_str() + 7);
      } else if (line.rfind(";TYPE:", 0) == 0) {
        flush();
        const std::string t = line.substr(6);
        type = t == "Skirt/Brim"           ? PathType::kSkirt
               : t == "External perimeter" ? PathType::kExternalPerimeter
               : t == "Perimeter"          ? PathType::kPerimeter
               : t == "Solid infill"       ? PathType::kSolidInfill
                                           : PathType::kCustom;
      }
      continue;
    }
    if (!header_done) {
      header_done = true;
      for (const auto& [k, v] : result.header) {
        if (k == "plate_to_bed" && !parse_plate_to_bed(v, tx, ty)) {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: unreadable plate_to_bed header line '{}'; write the "
                                      "G-code again with flatmorph toolpaths",
                                      path.string(), v));
        }
      }
    }
    // Strip a trailing comment and split into words.
    const std::string code = line.substr(0, line.find(';'));
    std::istringstream words(code);
    std::string command;
    words >> command;
    if (command == "M82") relative_e = false;
    if (command == "M83") relative_e = true;
    if (command != "G0" && command != "G1" && command != "G92") continue;
    Word wx, wy, wz, we;
    std::string w;
    while (words >> w) {
      if (w.size() < 2) continue;
      Word* target = w[0] == 'X'   ? &wx
                     : w[0] == 'Y' ? &wy
                     : w[0] == 'Z' ? &wz
                     : w[0] == 'E' ? &we
                                   : nullptr;
      if (!target) continue;
      char* end = nullptr;
      target->value = std::strtod(w.c_str() + 1, &end);
      target->has = end && *end == '\0' && std::isfinite(target->value);
      if (!target->has) {
        throw UserError(ErrorCategory::kFormat,
                        fmt::format("{}:{}: unreadable word '{}'; is this a G-code file?",
                                    path.string(), line_number, w));
      }
    }
    if (command == "G92") {
      if (we.has) e = we.value;
      continue;
    }
    const double nx = wx.has ? wx.value : x, ny = wy.has ? wy.value : y, nz = wz.has ? wz.value : z;
    double de = 0;
    if (we.has) {
      de = relative_e ? we.value : we.value - e;
      e = relative_e ? e + we.value : we.value;
    }
    const bool moves_xy = nx != x || ny != y;
    if (begun && moves_xy && !result.toolpath.layers.empty()) {
      if (de > 1e-9) {
        if (points.empty()) {
          points.emplace_back(x - tx, y - ty, z);
          current.type = type;
        }
        points.emplace_back(nx - tx, ny - ty, nz);
        SegmentStyle style;
        style.width = width;
        style.layer_height = height;
        current.segments.push_back(style);
      } else {
        flush();
      }
    }
    x = nx;
    y = ny;
    z = nz;
  }
  flush();
  if (!begun) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: not a G-code file written by flatmorph (no '; ---- flatmorph: "
                                "print begins' line); write it with flatmorph toolpaths or design",
                                path.string()));
  }
  return result;
}

}  // namespace flatmorph
