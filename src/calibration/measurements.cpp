#include "calibration/measurements.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include "calibration/sheet_csv.h"
#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {
namespace {

constexpr const char* kRequiredColumns[] = {
    "sample",       "set",           "nozzle_temperature", "layer_height",
    "layers",       "length_before", "width_before",       "thickness_before",
    "length_after", "width_after",   "thickness_after"};
// Ratios after / before outside these ranges are typos or unit mistakes (the material file's own
// ranges, material.cpp).
constexpr double kRatioRange[3][2] = {{0.2, 1.0}, {0.2, 2.0}, {0.2, 3.0}};

SampleMeasurement parse_row(const SheetRow& r, int line, const MeasurementSheet& sheet) {
  SampleMeasurement m;
  m.line = line;
  m.sample = r.whole("sample");
  m.set = r.whole("set");
  m.nozzle_temperature = r.positive("nozzle_temperature");
  m.layer_height = r.positive("layer_height");
  m.layers = r.whole("layers");
  if (sheet.speed_ramp) m.print_speed = r.positive("print_speed");
  // The ramps calibrate lambda1 alone; the curl (Delta lambda1) comes from the ordinary sets.
  const bool needs_curvature = !sheet.thickness_ramp && !sheet.speed_ramp;
  m.length_before = r.positive("length_before");
  m.width_before = r.positive("width_before");
  m.thickness_before = r.positive("thickness_before");
  if (lower_case(r.text("length_after")) == "skip") {
    m.skipped = true;
    return m;
  }
  // Curvature: given, or from rise and chord.
  std::optional<double> rise, chord;
  if (!r.empty("rise") || !r.empty("chord")) {
    rise = r.number("rise");
    chord = r.positive("chord");
    if (std::abs(*rise) > 2 * *chord) {
      r.fail("rise", fmt::format("a rise of {} mm over a chord of {} mm is not a curl of a strip; "
                                 "check the two values",
                                 *rise, *chord));
    }
  }
  if (!r.empty("curvature")) {
    m.curvature = r.number("curvature");
    if (std::abs(*m.curvature) > 1) {
      r.fail("curvature", fmt::format("{} /mm is a radius under 1 mm; give the curvature in 1/mm "
                                      "(1 / radius in mm)",
                                      *m.curvature));
    }
  } else if (rise) {
    m.curvature = curvature_from_rise(*rise, *chord);
  } else if (needs_curvature) {
    r.fail("curvature", "the value is missing; give the curvature (1/mm), or rise and chord (mm)");
  }
  if (r.empty("length_after") && rise) {
    m.length_after = arc_length_from_rise(*rise, *chord);
  } else {
    m.length_after = r.positive("length_after");
  }
  m.width_after = r.positive("width_after");
  m.thickness_after = r.positive("thickness_after");

  if (m.length_after > m.length_before) {
    r.fail(r.empty("length_after") ? "chord" : "length_after",
           fmt::format("the length grew along the path, from {} to {} mm; heated samples shrink "
                       "along their paths: check the values (before and after swapped?) and that "
                       "the sample was heated above 60 C",
                       m.length_before, m.length_after));
  }
  const double ratios[3] = {m.length_after / m.length_before, m.width_after / m.width_before,
                            m.thickness_after / m.thickness_before};
  const char* columns[3] = {"length_after", "width_after", "thickness_after"};
  for (int i = 0; i < 3; ++i) {
    if (ratios[i] < kRatioRange[i][0] || ratios[i] > kRatioRange[i][1]) {
      r.fail(columns[i], fmt::format("after / before = {:.3f} is outside [{}, {}], which no "
                                     "PLA does: a typo, or other units than mm?",
                                     ratios[i], kRatioRange[i][0], kRatioRange[i][1]));
    }
  }
  return m;
}

}  // namespace

double curvature_from_rise(double rise, double chord) {
  return 2 * rise / (rise * rise + chord * chord / 4);
}

double arc_length_from_rise(double rise, double chord) {
  const double s = std::abs(rise);
  if (s == 0) return chord;
  const double radius = (chord * chord / 4 + s * s) / (2 * s);
  // Half the arc's angle: sin = (chord / 2) / R, cos = (R - s) / R (beyond a half circle when s >
  // R).
  return 2 * radius * std::atan2(chord / 2, radius - s);
}

double delta_lambda1_from_curvature(double h, double lambda3, double lambda1, double kappa) {
  return -h * lambda3 * lambda1 * kappa;  // Shrink & Morph §4.2, b = b-bar with Eq. 17, 18
}

MeasurementSheet parse_measurements(std::string_view text, const std::string& source) {
  MeasurementSheet sheet;
  sheet.source = source;
  std::vector<std::string> names;
  int header_line = 0;
  std::map<int, int> sample_lines;               // sample id -> line
  std::map<int, const SampleMeasurement*> sets;  // set id -> first row
  std::vector<SampleMeasurement> rows;
  for (const SheetLine& l : sheet_lines(text)) {
    const int line = l.line;
    const std::string_view raw = l.text;
    if (l.comment) {
      const std::string& key = l.key;
      const std::string_view value = l.value;
      if (key == "kind") {
        if (value != "sets" && value != "thickness-ramp" && value != "speed-ramp") {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: line {}: kind \"{}\" is none of sets, thickness-ramp, "
                                      "speed-ramp; keep the template's line",
                                      source, line, value));
        }
        sheet.thickness_ramp = value == "thickness-ramp";
        sheet.speed_ramp = value == "speed-ramp";
      } else if (key == "samples") {
        int n = 0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
        if (ec != std::errc() || ptr != value.data() + value.size() || n < 1) {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: line {}: \"samples = {}\" is not a count; keep the "
                                      "template's line",
                                      source, line, value));
        }
        sheet.expected_samples = n;
        sheet.expected_samples_line = line;
      } else if (key == "material") {
        sheet.material =
            parse_material_json(value, fmt::format("{}: line {} (material)", source, line));
      }
      continue;
    }
    if (names.empty()) {
      header_line = line;
      names = sheet_columns(raw, line, source, kRequiredColumns);
      if (sheet.speed_ramp && std::find(names.begin(), names.end(), "print_speed") == names.end()) {
        throw UserError(ErrorCategory::kFormat,
                        fmt::format("{}: line {}: no column \"print_speed\", which a speed-ramp "
                                    "sheet needs (mm/s); start from the CSV that 'flatmorph "
                                    "calibrate print --speed-ramp' wrote",
                                    source, line));
      }
      continue;
    }
    std::vector<std::string_view> cells = split_cells(raw);
    if (cells.size() > names.size()) {
      throw UserError(
          ErrorCategory::kFormat,
          fmt::format("{}: line {}, column {}: the row has {} cells but line {} names "
                      "{} columns; remove the extra cells (a decimal comma? write "
                      "79.5, not 79,5)",
                      source, line, names.size() + 1, cells.size(), header_line, names.size()));
    }
    const SheetRow row(source, line, names, std::move(cells), "sample", "length_after");
    rows.push_back(parse_row(row, line, sheet));
  }
  if (names.empty() || rows.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no measurements (a line naming the columns, then one row per "
                                "sample); start from the CSV that 'flatmorph calibrate print' "
                                "wrote",
                                source));
  }
  for (const SampleMeasurement& m : rows) {
    const SheetRow row(source, m.line, names, {}, "sample", "length_after");
    if (const auto [it, fresh] = sample_lines.emplace(m.sample, m.line); !fresh) {
      row.fail("sample",
               fmt::format("sample {} appears twice (also on line {}); one row per sample",
                           m.sample, it->second));
    }
    const auto [it, fresh] = sets.emplace(m.set, &m);
    const SampleMeasurement& first = *it->second;
    if (!fresh) {
      for (const auto& [column, a, b] :
           {std::tuple{"nozzle_temperature", first.nozzle_temperature, m.nozzle_temperature},
            std::tuple{"layer_height", first.layer_height, m.layer_height},
            std::tuple{"layers", double(first.layers), double(m.layers)},
            std::tuple{"print_speed", first.print_speed, m.print_speed}}) {
        if (a != b) {
          row.fail(column, fmt::format("set {} has {} here but {} on line {}; the rows of a set "
                                       "share their printing parameters",
                                       m.set, b, a, first.line));
        }
      }
    }
  }
  if (sheet.expected_samples >= 0 && static_cast<int>(rows.size()) != sheet.expected_samples) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: line {}: the template lists {} samples but the file has {} "
                                "rows (last on line {}); keep one row per printed sample and "
                                "write skip in length_after for a lost one",
                                source, sheet.expected_samples_line, sheet.expected_samples,
                                rows.size(), rows.back().line));
  }
  sheet.rows = std::move(rows);
  return sheet;
}

MeasurementSheet read_measurements(const std::filesystem::path& path) {
  return parse_measurements(read_file_text(path, "measurements"), path.string());
}

std::vector<SampleRatios> sample_ratios(const MeasurementSheet& sheet) {
  std::vector<SampleRatios> out;
  for (const SampleMeasurement& m : sheet.rows) {
    if (m.skipped) continue;
    SampleRatios r;
    r.sample = m.sample;
    r.set = m.set;
    r.lambda1 = m.length_after / m.length_before;  // §4.1: lambda = l / l0
    r.lambda2 = m.width_after / m.width_before;
    r.lambda3 = m.thickness_after / m.thickness_before;
    r.contraction_pct = 100 * (1 - r.lambda1);
    r.curvature = m.curvature;
    if (m.curvature) {
      r.delta_lambda1 =
          delta_lambda1_from_curvature(m.thickness_before, r.lambda3, r.lambda1, *m.curvature);
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace flatmorph
