#include "gcode_replay.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace flatmorph::testing {
namespace {

// The value after `letter` in the words of a command ("X12.5" -> 12.5), or NaN.
double word(const std::vector<std::string>& words, char letter) {
  for (size_t i = 1; i < words.size(); ++i) {
    if (!words[i].empty() && words[i][0] == letter)
      return std::strtod(words[i].c_str() + 1, nullptr);
  }
  return std::nan("");
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

double ReadLayer::filament() const {
  double sum = 0;
  for (const ReadExtrusion& e : extrusions) sum += e.filament;
  return sum;
}

ReadGcode read_gcode(const std::string& text, double cx, double cy) {
  ReadGcode r;
  std::istringstream in(text);
  std::string raw;
  double x = std::nan(""), y = std::nan(""), z = std::nan(""), e = 0;
  bool relative_xyz = false, m83 = false, declared = false, extruded = false;
  std::map<int, double> retracted;  // per tool: each has its own filament
  std::map<int, double> nozzle;
  double last_target = -1;
  int tool = 0;
  int material = -1;      // the tool whose material the last swap loaded into the one nozzle
  size_t extrusions = 0;  // in layers, so far
  double feed = -1;
  std::string type;
  double width = 0, height = 0;
  // After ;LAYER_CHANGE, the next two lines must be ;Z: and ;HEIGHT:.
  int expect_tags = 0;
  while (std::getline(in, raw)) {
    r.lines.push_back(raw);
    if (expect_tags == 2 && !starts_with(raw, ";Z:")) {
      r.annotation_errors.push_back("no ;Z: right after ;LAYER_CHANGE: " + raw);
    }
    if (expect_tags == 1 && !starts_with(raw, ";HEIGHT:")) {
      r.annotation_errors.push_back("no ;HEIGHT: right after ;Z: " + raw);
    }
    if (expect_tags > 0) --expect_tags;
    if (starts_with(raw, ";LAYER_CHANGE")) {
      r.layers.emplace_back();
      expect_tags = 2;
      type.clear();  // each layer must say its type again before extruding
      continue;
    }
    if (starts_with(raw, ";Z:") && !r.layers.empty()) {
      r.layers.back().z_tag = std::stod(raw.substr(3));
      continue;
    }
    if (starts_with(raw, ";HEIGHT:")) {
      height = std::stod(raw.substr(8));
      if (!r.layers.empty() && r.layers.back().height_tag < 0) r.layers.back().height_tag = height;
      continue;
    }
    if (starts_with(raw, ";WIDTH:")) {
      width = std::stod(raw.substr(7));
      continue;
    }
    if (starts_with(raw, ";TYPE:")) {
      type = raw.substr(6);
      continue;
    }
    if (starts_with(raw, ";FILAMENT_SWAP:T")) {
      const int next = std::atoi(raw.c_str() + 16);
      const int from = material < 0 ? tool : material;
      if (next != from) {
        r.filament_swaps.push_back({static_cast<int>(r.lines.size()), from, next, extrusions});
      }
      material = next;
      continue;
    }
    if (starts_with(raw, "; ")) {
      const size_t eq = raw.find(" = ");
      if (eq != std::string::npos) r.header[raw.substr(2, eq - 2)] = raw.substr(eq + 3);
    }
    const std::string code = raw.substr(0, raw.find(';'));
    std::istringstream ws(code);
    std::vector<std::string> words;
    for (std::string w; ws >> w;) words.push_back(w);
    if (words.empty()) continue;
    const std::string& c = words[0];
    if (c == "G0" || c == "G1" || c == "G28") r.motors_off_at_end = false;
    if (c == "M0" || c == "M1" || c == "M25" || c == "M600" || c == "M601" || c == "PAUSE" ||
        (c == "M400" && words.size() > 1 && words[1] == "U1")) {
      r.pauses.push_back(static_cast<int>(r.lines.size()));
    }
    if (c == "G0" || c == "G1") {
      const double nx = word(words, 'X'), ny = word(words, 'Y'), nz = word(words, 'Z');
      if (!std::isnan(word(words, 'F'))) feed = word(words, 'F');
      const double ox = x, oy = y, oz = z;
      if (!std::isnan(nx)) x = relative_xyz ? x + nx : nx;
      if (!std::isnan(ny)) y = relative_xyz ? y + ny : ny;
      if (!std::isnan(nz)) z = relative_xyz ? z + nz : nz;
      if (!std::isnan(x) && !std::isnan(y)) {
        r.min_x = std::min(r.min_x, x);
        r.max_x = std::max(r.max_x, x);
        r.min_y = std::min(r.min_y, y);
        r.max_y = std::max(r.max_y, y);
        r.max_radius = std::max(r.max_radius, std::hypot(x - cx, y - cy));
      }
      if (!std::isnan(z)) {
        r.max_z = std::max(r.max_z, z);
        r.min_z = std::min(r.min_z, z);
      }
      const double ev = word(words, 'E');
      if (std::isnan(ev)) continue;
      if (c == "G0") ++r.g0_with_e;
      const double de = (m83 || relative_xyz) ? ev : ev - e;
      e = (m83 || relative_xyz) ? e + ev : ev;
      const bool moves = !std::isnan(nx) || !std::isnan(ny) || !std::isnan(nz);
      if (de < 0) {
        retracted[tool] -= de;
        continue;
      }
      if (!moves) {
        retracted[tool] = std::max(0.0, retracted[tool] - de);
        continue;
      }
      if (retracted[tool] > 1e-9) ++r.extrusions_while_retracted;
      if (de <= 0) continue;
      if (!extruded) r.mode_declared_before_extrusion = declared;
      extruded = true;
      if (r.layers.empty()) {
        r.filament_before_layers += de;
        continue;
      }
      if (type.empty() || width <= 0) {
        r.annotation_errors.push_back("extrusion without ;TYPE: or ;WIDTH: in effect: " + raw);
      }
      const auto target = nozzle.find(tool);
      r.layers.back().extrusions.push_back(
          {ox, oy, x, y, z, de, type, width, height, material < 0 ? tool : material,
           target == nozzle.end() ? -1 : target->second, last_target, feed, oz});
      ++extrusions;
    } else if (c == "G90") {
      relative_xyz = false;
    } else if (c == "G91") {
      relative_xyz = true;
    } else if (c == "M82") {
      m83 = false;
      declared = true;
    } else if (c == "M83") {
      m83 = true;
      declared = true;
    } else if (c == "G92") {
      const double ev = word(words, 'E');
      if (!std::isnan(ev)) {
        e = ev;
        if (ev == 0 && !r.layers.empty()) ++r.g92_e0_in_layers;
      }
    } else if (c == "M104" || c == "M109") {
      double t = word(words, 'S');
      if (std::isnan(t)) t = word(words, 'R');
      const double which = word(words, 'T');
      if (!std::isnan(t)) {
        const int target_tool = std::isnan(which) ? tool : static_cast<int>(which);
        nozzle[target_tool] = t;
        last_target = t;
        r.nozzle_targets.push_back(t);
        r.tool_nozzle_targets[target_tool].push_back(t);
      }
    } else if (c == "M140" || c == "M190") {
      const double t = word(words, 'S');
      if (!std::isnan(t)) {
        r.final_bed = t;
        r.bed_targets.push_back(t);
      }
    } else if (c == "TURN_OFF_HEATERS") {
      for (auto& [k, v] : nozzle) v = 0;
      r.final_bed = 0;
    } else if (c == "M84" || c == "M18") {
      r.motors_off_at_end = true;
    } else if (c[0] == 'T' && c.size() > 1 && std::isdigit(static_cast<unsigned char>(c[1]))) {
      const int next = std::atoi(c.c_str() + 1);
      if (next != tool) {
        r.tool_changes.push_back({static_cast<int>(r.lines.size()), tool, next, extrusions});
      }
      tool = next;
    }
  }
  r.final_nozzle = -1;
  for (const auto& [k, v] : nozzle) r.final_nozzle = std::max(r.final_nozzle, v);
  r.final_tool_nozzle = nozzle;
  r.relative_e = m83;
  return r;
}

}  // namespace flatmorph::testing
