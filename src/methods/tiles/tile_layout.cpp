#include "methods/tiles/tile_layout.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "common/error.h"
#include "common/file_text.h"
#include "methods/tiles/outline_file.h"

namespace flatmorph {
namespace {

using nlohmann::json;

[[noreturn]] void refuse(const std::string& source, const std::string& where,
                         const std::string& problem) {
  throw UserError(ErrorCategory::kFormat, fmt::format("{}: {}: {}", source, where, problem));
}

double number(const json& j, const std::string& source, const std::string& where) {
  if (!j.is_number() || !std::isfinite(j.get<double>()) || std::abs(j.get<double>()) > 1e6) {
    refuse(source, where, "expected a finite number of at most 1e6 (mm)");
  }
  return j.get<double>();
}

Eigen::Vector2d point(const json& j, const std::string& source, const std::string& where) {
  if (!j.is_array() || j.size() != 2) refuse(source, where, "expected a point [x, y] in mm");
  return {number(j[0], source, where), number(j[1], source, where)};
}

Eigen::MatrixX2d polygon(const json& j, const std::string& source, const std::string& where) {
  if (!j.is_array() || j.size() < 3 || j.size() > 1'000'000) {
    refuse(source, where, "expected a polygon: 3 or more points [[x, y], ...] in mm");
  }
  Eigen::MatrixX2d p(j.size(), 2);
  for (size_t i = 0; i < j.size(); ++i) {
    p.row(static_cast<Eigen::Index>(i)) =
        point(j[i], source, fmt::format("{}[{}]", where, i)).transpose();
  }
  // Counter-clockwise, as every stage expects (a drawing may go either way).
  double area2 = 0;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const Eigen::Index k = (i + 1) % p.rows();
    area2 += p(i, 0) * p(k, 1) - p(k, 0) * p(i, 1);
  }
  if (area2 < 0) p = p.colwise().reverse().eval();
  return p;
}

// The settings a tile entry (or "defaults") gives, over `tile`.
void read_settings(const json& j, const std::string& source, const std::string& where,
                   const std::filesystem::path& base_dir, TileSpec& tile) {
  static const std::vector<std::string> kKeys = {"circle", "polygon",     "index", "profile",
                                                 "height", "profile_csv", "side",  "hole"};
  for (const auto& [key, value] : j.items()) {
    if (std::find(kKeys.begin(), kKeys.end(), key) == kKeys.end()) {
      refuse(source, where + "." + key,
             "unknown key; a tile takes circle, polygon, index, profile, profile_csv, height, "
             "side, hole");
    }
  }
  if (j.contains("profile")) {
    if (!j["profile"].is_string()) refuse(source, where + ".profile", "expected a name");
    tile.profile = j["profile"].get<std::string>();
    tile.profile_csv.clear();
  }
  if (j.contains("profile_csv")) {
    if (!j["profile_csv"].is_string()) refuse(source, where + ".profile_csv", "expected a path");
    tile.profile_csv = base_dir / j["profile_csv"].get<std::string>();
  }
  if (j.contains("height")) {
    tile.height_mm = number(j["height"], source, where + ".height");
    if (!(tile.height_mm > 0)) refuse(source, where + ".height", "expected a height above 0 mm");
  }
  if (j.contains("side")) {
    const std::string side = j["side"].is_string() ? j["side"].get<std::string>() : "";
    if (side != "up" && side != "down") {
      refuse(source, where + ".side", "expected \"up\" (away from the bed) or \"down\"");
    }
    tile.side = side == "up" ? +1 : -1;
  }
  if (j.contains("hole")) {
    tile.hole_radius_mm = number(j["hole"], source, where + ".hole");
    if (tile.hole_radius_mm < 0) refuse(source, where + ".hole", "expected a radius >= 0 mm");
  }
}

}  // namespace

Eigen::MatrixX2d circle_polygon(const Eigen::Vector2d& center, double radius,
                                double chord_tolerance) {
  // A chord of angle a strays r (1 − cos(a/2)) from the circle.
  const double angle = 2 * std::acos(std::max(-1.0, 1 - chord_tolerance / radius));
  const int sides = std::max(24, static_cast<int>(std::ceil(2 * std::numbers::pi / angle)));
  Eigen::MatrixX2d p(sides, 2);
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides;
    p.row(i) << center.x() + radius * std::cos(a), center.y() + radius * std::sin(a);
  }
  return p;
}

TileLayout read_tile_layout(std::string_view json_text, const std::string& source,
                            const std::filesystem::path& base_dir) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw UserError(
        ErrorCategory::kFormat,
        fmt::format("{}: not valid JSON ({}): check the layout's syntax", source, e.what()));
  }
  if (!root.is_object()) refuse(source, "top level", "expected an object {\"tiles\": [...]}");
  for (const auto& [key, value] : root.items()) {
    if (key != "outlines" && key != "defaults" && key != "tiles" && key != "lattice") {
      refuse(source, key, "unknown key; a layout takes outlines, defaults, tiles, lattice");
    }
  }
  TileLayout layout;
  layout.source = source;
  TileSpec defaults;
  if (root.contains("defaults")) {
    const json& d = root["defaults"];
    if (!d.is_object() || d.contains("circle") || d.contains("polygon") || d.contains("index")) {
      refuse(source, "defaults", "expected an object of profile, height, side, hole");
    }
    read_settings(d, source, "defaults", base_dir, defaults);
  }
  std::vector<TileOutline> drawing;
  if (root.contains("outlines")) {
    if (!root["outlines"].is_string()) refuse(source, "outlines", "expected a file name");
    drawing = read_tile_outlines(base_dir / root["outlines"].get<std::string>());
    for (const TileOutline& outline : drawing) {
      TileSpec tile = defaults;
      tile.outline = outline;
      layout.tiles.push_back(tile);
    }
  }
  if (root.contains("tiles")) {
    const json& tiles = root["tiles"];
    if (!tiles.is_array()) refuse(source, "tiles", "expected an array of tiles");
    for (size_t i = 0; i < tiles.size(); ++i) {
      const std::string where = fmt::format("tiles[{}]", i);
      const json& t = tiles[i];
      if (!t.is_object()) refuse(source, where, "expected an object");
      const int shapes = t.contains("circle") + t.contains("polygon") + t.contains("index");
      if (shapes != 1) {
        refuse(source, where,
               "give exactly one of circle, polygon or index (an outline of the "
               "drawing named by \"outlines\")");
      }
      if (t.contains("index")) {
        if (!t["index"].is_number_integer() || t["index"].get<long long>() < 0 ||
            t["index"].get<long long>() >= static_cast<long long>(drawing.size())) {
          refuse(source, where + ".index",
                 fmt::format("expected the index of an outline of the drawing (0 to {})",
                             static_cast<long long>(drawing.size()) - 1));
        }
        TileSpec& tile = layout.tiles[t["index"].get<size_t>()];
        read_settings(t, source, where, base_dir, tile);
        continue;
      }
      TileSpec tile = defaults;
      read_settings(t, source, where, base_dir, tile);
      tile.outline.source = fmt::format("{}: {}", source, where);
      if (t.contains("circle")) {
        const json& c = t["circle"];
        if (!c.is_object() || !c.contains("radius")) {
          refuse(source, where + ".circle", "expected {\"center\": [x, y], \"radius\": r}");
        }
        const Eigen::Vector2d center = c.contains("center")
                                           ? point(c["center"], source, where + ".circle.center")
                                           : Eigen::Vector2d::Zero();
        const double radius = number(c["radius"], source, where + ".circle.radius");
        if (!(radius > 0)) refuse(source, where + ".circle.radius", "expected a radius above 0");
        tile.outline.boundary = circle_polygon(center, radius);
      } else {
        tile.outline.boundary = polygon(t["polygon"], source, where + ".polygon");
      }
      layout.tiles.push_back(tile);
    }
  }
  if (layout.tiles.empty()) refuse(source, "tiles", "no tile: give tiles or outlines");
  if (root.contains("lattice")) {
    const json& l = root["lattice"];
    if (!l.is_object()) refuse(source, "lattice", "expected an object");
    layout.has_lattice = true;
    LatticeSpec& s = layout.lattice;
    for (const auto& [key, value] : l.items()) {
      const std::string where = "lattice." + key;
      if (key == "outline") {
        s.outline = polygon(value, source, where);
      } else if (key == "margin") {
        s.margin_mm = number(value, source, where);
      } else if (key == "spacing") {
        s.spacing_mm = number(value, source, where);
      } else if (key == "overlap") {
        s.overlap_mm = number(value, source, where);
      } else if (key == "layer_height") {
        s.layer_height_mm = number(value, source, where);
      } else if (key == "feed_rate") {
        s.feed_rate = number(value, source, where);
      } else if (key == "layers") {
        if (!value.is_number_integer() || value.get<long long>() < 1 ||
            value.get<long long>() > 50) {
          refuse(source, where, "expected a whole number of layers, 1 to 50");
        }
        s.layers = value.get<int>();
      } else if (key == "material") {
        if (!value.is_string()) refuse(source, where, "expected a material preset or file");
        s.material = value.get<std::string>();
      } else {
        refuse(source, where,
               "unknown key; a lattice takes outline, margin, spacing, overlap, layer_height, "
               "layers, feed_rate, material");
      }
    }
    if (!(s.spacing_mm > 0) || !(s.margin_mm >= 0) || !(s.layer_height_mm > 0) ||
        !(s.feed_rate > 0)) {
      refuse(source, "lattice",
             "spacing, layer_height and feed_rate must be above 0 and margin at least 0");
    }
  }
  return layout;
}

TileLayout load_tile_layout(const std::filesystem::path& path, const TileSpec& defaults) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".json") {
    return read_tile_layout(read_file_text(path, "layout"), path.string(), path.parent_path());
  }
  TileLayout layout;
  layout.source = path.string();
  for (const TileOutline& outline : read_tile_outlines(path)) {
    TileSpec tile = defaults;
    tile.outline = outline;
    layout.tiles.push_back(tile);
  }
  if (layout.tiles.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no closed outline in the drawing: draw each tile as a closed "
                                "polyline or circle",
                                path.string()));
  }
  return layout;
}

}  // namespace flatmorph
