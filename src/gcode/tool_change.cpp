#include "gcode/tool_change.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"

namespace flatmorph {
namespace {

// The prime pad's beads: wider than the nozzle, like a first layer, so that they stick.
constexpr double kPrimeWidthInNozzles = 1.25;
constexpr double kPrimeHeight = 0.2;  // mm
// Gap kept between the print (skirt included) and the prime area, mm.
constexpr double kPrimeClearance = 2.0;

}  // namespace

Eigen::Vector2d PrimePad::point(double s) const {
  const size_t i = static_cast<size_t>(std::upper_bound(arclength.begin(), arclength.end(), s) -
                                       arclength.begin());
  if (i == 0) return corners.front();
  if (i >= corners.size()) return corners.back();
  const double t = (s - arclength[i - 1]) / (arclength[i] - arclength[i - 1]);
  return corners[i - 1] + t * (corners[i] - corners[i - 1]);
}

std::vector<Eigen::Vector2d> PrimePad::corners_between(double s0, double s1) const {
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < corners.size(); ++i) {
    if (arclength[i] > std::min(s0, s1) && arclength[i] < std::max(s0, s1)) {
      out.push_back(corners[i]);
    }
  }
  if (s1 < s0) std::reverse(out.begin(), out.end());
  return out;
}

PrimePad prime_pad(const PrinterProfile& printer) {
  const ToolChange& change = printer.tool_change;
  PrimePad pad;
  pad.bead_width = kPrimeWidthInNozzles * printer.nozzle_diameter;
  pad.bead_height = kPrimeHeight;
  const double w = pad.bead_width;
  const double x0 = change.prime_area_min.x() + w / 2, x1 = change.prime_area_max.x() - w / 2;
  const int rows = static_cast<int>(
      std::floor((change.prime_area_max.y() - change.prime_area_min.y()) / w + 1e-9));
  for (int r = 0; r < rows; ++r) {
    const double y = change.prime_area_min.y() + w / 2 + r * w;
    pad.corners.emplace_back(r % 2 == 0 ? x0 : x1, y);
    pad.corners.emplace_back(r % 2 == 0 ? x1 : x0, y);
  }
  pad.arclength.push_back(0);
  for (size_t i = 1; i < pad.corners.size(); ++i) {
    pad.arclength.push_back(pad.arclength.back() + (pad.corners[i] - pad.corners[i - 1]).norm());
  }
  return pad;
}

double flush_temperature(const Material& from, const Material& to) {
  const double lo = std::max(from.min_nozzle_temperature, to.min_nozzle_temperature);
  const double hi = std::min(from.max_nozzle_temperature, to.max_nozzle_temperature);
  return std::clamp(std::max(from.nozzle_temperature, to.nozzle_temperature), lo, hi);
}

double swap_temperature(const Material& from, const Material& to) {
  const bool overlap = std::max(from.min_nozzle_temperature, to.min_nozzle_temperature) <=
                       std::min(from.max_nozzle_temperature, to.max_nozzle_temperature);
  return overlap ? flush_temperature(from, to) : to.nozzle_temperature;
}

int count_tool_changes(const Toolpath& toolpath, int first_tool) {
  int changes = 0, tool = 0;
  auto at = [&](int next) {
    if (next != tool) ++changes;
    tool = next;
  };
  at(first_tool);  // the skirt is printed by the first tool
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (const SegmentStyle& s : path.segments) {
        if (!s.travel) at(s.tool);
      }
    }
  }
  return changes;
}

std::optional<PrimePad> validate_tool_changes(const Toolpath& toolpath,
                                              const PrinterProfile& printer,
                                              const std::vector<Material>& tool_materials,
                                              const std::set<int>& tools, int first_tool,
                                              const Eigen::Vector2d& print_min,
                                              const Eigen::Vector2d& print_max) {
  const ToolChange& change = printer.tool_change;
  if (printer.extruder_count < 2) return std::nullopt;
  if (change.shared_nozzle) {
    for (int a : tools) {
      for (int b : tools) {
        const Material& ma = tool_materials[static_cast<size_t>(a)];
        const Material& mb = tool_materials[static_cast<size_t>(b)];
        if (a < b && std::max(ma.min_nozzle_temperature, mb.min_nozzle_temperature) >
                         std::min(ma.max_nozzle_temperature, mb.max_nozzle_temperature)) {
          throw UserError(
              ErrorCategory::kOption,
              fmt::format("T{} ({}, {:g}..{:g} C) and T{} ({}, {:g}..{:g} C) share the one nozzle "
                          "of {}, but no temperature suits both for the flush between them: "
                          "print them on a printer with a nozzle per tool, or choose materials "
                          "whose ranges overlap",
                          a, ma.name, ma.min_nozzle_temperature, ma.max_nozzle_temperature, b,
                          mb.name, mb.min_nozzle_temperature, mb.max_nozzle_temperature,
                          printer.name));
        }
      }
    }
  }
  if (change.prime_volume <= 0) return std::nullopt;
  const int changes = count_tool_changes(toolpath, first_tool);
  if (changes == 0) return std::nullopt;
  PrimePad pad = prime_pad(printer);
  const double per_prime = change.prime_volume / (pad.bead_width * pad.bead_height);
  const std::string area =
      fmt::format("x [{:g}, {:g}], y [{:g}, {:g}]", change.prime_area_min.x(),
                  change.prime_area_max.x(), change.prime_area_min.y(), change.prime_area_max.y());
  if (changes * per_prime > pad.capacity() + 1e-9) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("the print changes tools {} times and primes {:g} mm^3 at each, but "
                    "the prime area of {} ({}) holds {} primes: print with fewer "
                    "changes of material, or give a copy of the profile a larger "
                    "tool_change.prime.area or a smaller volume",
                    changes, change.prime_volume, printer.name, area,
                    static_cast<int>(std::floor(pad.capacity() / per_prime))));
  }
  const Eigen::Vector2d lo = print_min.array() - kPrimeClearance;
  const Eigen::Vector2d hi = print_max.array() + kPrimeClearance;
  if ((lo.array() < change.prime_area_max.array()).all() &&
      (hi.array() > change.prime_area_min.array()).all()) {
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("the print spans x [{:.1f}, {:.1f}], y [{:.1f}, {:.1f}] on the bed "
                                "and comes within {:g} mm of the prime area of {} ({}) where tool "
                                "changes prime: place it elsewhere with --at X,Y",
                                print_min.x(), print_max.x(), print_min.y(), print_max.y(),
                                kPrimeClearance, printer.name, area));
  }
  return pad;
}

}  // namespace flatmorph
