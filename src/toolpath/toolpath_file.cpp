#include "toolpath/toolpath_file.h"

#include <fmt/core.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {
namespace {

constexpr const char* kFormat = "flatmorph-toolpath";
constexpr int kVersion = 1;

constexpr std::pair<PathType, const char*> kTypeNames[] = {
    {PathType::kPerimeter, "perimeter"},
    {PathType::kExternalPerimeter, "external perimeter"},
    {PathType::kSolidInfill, "solid infill"},
    {PathType::kSkirt, "skirt"},
    {PathType::kCustom, "custom"},
};

const char* type_name(PathType type) {
  for (const auto& [t, name] : kTypeNames) {
    if (t == type) return name;
  }
  return "custom";
}

PathType type_of(const std::string& name) {
  for (const auto& [t, n] : kTypeNames) {
    if (name == n) return t;
  }
  return PathType::kCustom;
}

// Micrometres, as fixed-point text: the same toolpath gives the same bytes.
std::string micrometres(double mm) { return fmt::format("{:.3f}", mm); }

}  // namespace

void write_toolpath_file(const std::filesystem::path& path, const Toolpath& toolpath,
                         const std::vector<std::pair<std::string, std::string>>& summary) {
  // Written by hand rather than through nlohmann::json so that 1e5 points cost no DOM and the
  // numbers have a fixed precision.
  std::string out = fmt::format(
      "{{\"format\":\"{}\",\"version\":{},\"units\":\"mm\",\n\"summary\":[", kFormat, kVersion);
  for (size_t i = 0; i < summary.size(); ++i) {
    out += (i ? ",\n" : "\n");
    out += nlohmann::json::array({summary[i].first, summary[i].second}).dump();
  }
  out += "],\n\"layers\":[";
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    const ToolpathLayer& layer = toolpath.layers[k];
    out += fmt::format("{}\n{{\"z\":{},\"height\":{},\"paths\":[", k ? "," : "",
                       micrometres(layer.z), micrometres(layer.height));
    for (size_t p = 0; p < layer.paths.size(); ++p) {
      const PathPolyline& path = layer.paths[p];
      const SegmentStyle style = path.segments.empty() ? SegmentStyle{} : path.segments.front();
      out += fmt::format("{}\n{{\"type\":\"{}\",\"tool\":{},\"width\":{},\"closed\":{},\"xy\":[",
                         p ? "," : "", type_name(path.type), style.tool, micrometres(style.width),
                         path.closed ? "true" : "false");
      for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
        out += fmt::format("{}{},{}", i ? "," : "", micrometres(path.points(i, 0)),
                           micrometres(path.points(i, 1)));
      }
      out += "]}";
    }
    out += "]}";
  }
  out += "]}\n";
  write_file_atomically(path, false, [&](std::ostream& stream) { stream << out; });
}

ToolpathFile read_toolpath_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string text = read_file_text(path, "toolpath file");
  const auto bad = [&](const std::string& problem) {
    return UserError(ErrorCategory::kFormat,
                     fmt::format("{}: {}; write it again with 'flatmorph toolpaths' or "
                                 "'flatmorph design'",
                                 name, problem));
  };
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != kFormat) {
    throw bad("not a flatmorph toolpath file");
  }
  ToolpathFile file;
  try {
    if (j.at("version").get<int>() != kVersion) throw bad("a version this flatmorph does not read");
    for (const auto& item : j.at("summary")) {
      file.summary.emplace_back(item.at(0).get<std::string>(), item.at(1).get<std::string>());
    }
    for (const auto& layer_json : j.at("layers")) {
      ToolpathLayer layer;
      layer.z = layer_json.at("z").get<double>();
      layer.height = layer_json.at("height").get<double>();
      for (const auto& path_json : layer_json.at("paths")) {
        PathPolyline path;
        path.type = type_of(path_json.at("type").get<std::string>());
        path.closed = path_json.at("closed").get<bool>();
        SegmentStyle style;
        style.tool = path_json.at("tool").get<int>();
        style.width = path_json.at("width").get<double>();
        style.layer_height = layer.height;
        const std::vector<double> xy = path_json.at("xy").get<std::vector<double>>();
        if (xy.size() % 2 != 0) throw bad("a path has an odd number of coordinates");
        const Eigen::Index n = static_cast<Eigen::Index>(xy.size() / 2);
        path.points.resize(n, 3);
        for (Eigen::Index i = 0; i < n; ++i)
          path.points.row(i) << xy[2 * i], xy[2 * i + 1], layer.z;
        if (!path.points.allFinite()) throw bad("a point is not finite");
        path.segments.assign(n > 0 ? n - 1 : 0, style);
        layer.paths.push_back(std::move(path));
      }
      file.toolpath.layers.push_back(std::move(layer));
    }
  } catch (const nlohmann::json::exception& e) {
    throw bad(fmt::format("a key is missing or has the wrong type ({})", e.what()));
  }
  return file;
}

std::string summary_value(const ToolpathFile& file, const std::string& key) {
  for (const auto& [k, v] : file.summary) {
    if (k == key) return v;
  }
  return "";
}

}  // namespace flatmorph
