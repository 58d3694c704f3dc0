// flatmorph calibrate print | fit: print the material samples of Shrink & Morph §4 (or the
// thickness ramp of SCF 2020 §6, the print-speed ramp of Thermorph Fig. 6, or Thermorph's hinge
// sheet, Fig. 6-7), then fit a material file to their measurements. Speeds in mm/s.
// docs/calibration.md
#include <fmt/core.h>

#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>

#include "calibration/calibration_print.h"
#include "calibration/fit.h"
#include "calibration/hinge_sheet.h"
#include "calibration/measurements.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "gcode_input.h"
#include "material/material.h"
#include "output_folder.h"

namespace flatmorph::cli {
namespace {

namespace fs = std::filesystem;

struct PrintOptions {
  std::string printer;
  std::string material;
  std::vector<double> nozzle_temps;
  std::vector<double> layer_heights;
  int repeats = 4;
  std::vector<double> size = {80, 20};
  double thickness = 0.8;
  bool thickness_ramp = false;
  int ramp_layers = 6;
  bool speed_ramp = false;
  std::vector<double> print_speeds;  // mm/s
  bool hinge_sheet = false;
  std::vector<double> hinge_speeds;  // mm/s
  std::vector<double> hinge_widths;  // mm
  std::vector<std::string> hinge_cases;
  double spacing = 0;
  double gap = 5;
  std::string output;
};

struct FitOptions {
  std::vector<std::string> sheets;
  std::string output;
  int set = 0;
  std::string material;
  std::string name;
  std::string plot;
};

void write_text(const fs::path& path, const std::string& text) {
  write_file_atomically(path, false, [&](std::ostream& out) { out << text; });
}

constexpr double kDegree = std::numbers::pi / 180;

// The output paths of a print: OUT.gcode (or OUT-1.gcode, ... for `plates` > 1), OUT.csv, OUT.svg.
struct PrintPaths {
  std::vector<fs::path> gcode;
  fs::path csv, svg;
};

PrintPaths print_paths(const std::string& output, size_t plates) {
  const fs::path out(output);
  const fs::path stem = out.parent_path() / out.stem();
  const std::string extension = out.has_extension() ? out.extension().string() : ".gcode";
  PrintPaths paths;
  for (size_t p = 0; p < plates; ++p) {
    paths.gcode.push_back(
        plates == 1 ? out : fs::path(fmt::format("{}-{}{}", stem.string(), p + 1, extension)));
  }
  paths.csv = fs::path(stem.string() + ".csv");
  paths.svg = fs::path(stem.string() + ".svg");
  return paths;
}

// `calibrate print --hinge-sheet`: Thermorph's hinge strips in PLA (T0) and TPU (T1).
int run_hinge_print(const PrintOptions& o, const GlobalOptions& global) {
  if (o.thickness_ramp || o.speed_ramp) {
    throw UserError(ErrorCategory::kOption,
                    "--hinge-sheet is a calibration of its own, with its own measurement sheet: "
                    "print it alone, without --thickness-ramp or --speed-ramp");
  }
  if (!o.nozzle_temps.empty() || !o.layer_heights.empty() || !o.print_speeds.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "--hinge-sheet prints at the materials' temperatures, in the actuator's 0.2 "
                    "mm layers, at --hinge-speeds: leave out --nozzle-temps, --layer-heights and "
                    "--print-speeds");
  }
  const PrinterProfile printer = load_printer(o.printer);
  const std::vector<Material> materials = load_tool_materials(o.material);
  if (materials.size() != 2) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--hinge-sheet prints PLA with tool 0 and TPU with tool 1: give "
                                "--material PLA,TPU (e.g. pla-generic,tpu-generic), not {} "
                                "material{}",
                                materials.size(), materials.size() == 1 ? "" : "s"));
  }
  HingeSheetOptions options;
  if (!o.hinge_speeds.empty()) {
    options.speeds = o.hinge_speeds;
  } else {
    std::erase_if(options.speeds, [&](double v) { return v > printer.travel_speed; });
  }
  if (!o.hinge_widths.empty()) options.widths = o.hinge_widths;
  if (!o.hinge_cases.empty()) {
    options.case_a = options.case_b = false;
    for (const std::string& c : o.hinge_cases) {
      if (c == "A" || c == "a") {
        options.case_a = true;
      } else if (c == "B" || c == "b") {
        options.case_b = true;
      } else {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("--hinge-cases \"{}\": give A (PLA on the bed), B (TPU on "
                                    "the bed) or A,B",
                                    c));
      }
    }
  }
  options.spacing = o.spacing;
  options.gap = o.gap;
  const HingeSheetPlan plan = plan_hinge_sheet(printer, options);
  // Made (and checked) before anything is written.
  const GcodeResult gcode = make_gcode(plan.toolpath, printer, materials);
  const PrintPaths paths = print_paths(o.output, 1);
  create_output_folder(fs::path(o.output).parent_path());
  write_text(paths.gcode.front(), gcode.text);
  write_text(paths.csv, hinge_sheet_csv_template(plan, materials[0], printer));
  write_text(paths.svg, hinge_sheet_layout_svg(plan, printer, gcode.plate_to_bed,
                                               paths.gcode.front().filename().string()));
  if (!global.quiet) {
    std::vector<std::string> speeds, cases;
    for (double v : options.speeds) speeds.push_back(fmt::format("{:g} ({:g})", v, 60 * v));
    if (options.case_a) cases.emplace_back("A");
    if (options.case_b) cases.emplace_back("B");
    fmt::print(
        "{} hinge strips: case {}, active PLA at {} mm/s (mm/min), actuators {} mm wide between "
        "two {:g} mm faces; PLA {} on T0, TPU {} on T1, printer {}\n",
        plan.strips.size(), fmt::join(cases, " and "), fmt::join(speeds, ", "),
        fmt::join(options.widths, ", "), options.face_length, materials[0].name, materials[1].name,
        printer.name);
    const long s = std::lround(gcode.print_time);
    fmt::print("wrote {}: about {}h {:02}m {:02}s without heating, {:.1f} g, {} tool changes\n",
               paths.gcode.front().string(), s / 3600, (s / 60) % 60, s % 60, gcode.filament_mass,
               gcode.tool_changes);
    fmt::print(
        "wrote {} (fill in each strip's fold angle after heating) and {} (layout and "
        "codes)\n",
        paths.csv.string(), paths.svg.string());
    fmt::print("then: flatmorph calibrate fit {} -o my-pla.json\n", paths.csv.string());
  }
  return 0;
}

int run_print(const PrintOptions& o, const GlobalOptions& global) {
  if (o.hinge_sheet) return run_hinge_print(o, global);
  if (!o.hinge_speeds.empty() || !o.hinge_widths.empty() || !o.hinge_cases.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "--hinge-speeds, --hinge-widths and --hinge-cases set the hinge sheet: add "
                    "--hinge-sheet");
  }
  if (o.size.size() != 2) {
    throw UserError(ErrorCategory::kOption, "--size takes two numbers: LENGTH,WIDTH in mm");
  }
  const PrinterProfile printer = load_printer(o.printer);
  const Material material = load_material(o.material);
  if (!o.print_speeds.empty() && !o.speed_ramp) {
    throw UserError(ErrorCategory::kOption,
                    "--print-speeds sets the speeds of a speed ramp: add --speed-ramp (the "
                    "ordinary samples print at the material's print_speed)");
  }
  CalibrationPrintOptions options;
  options.thickness_ramp = o.thickness_ramp;
  options.speed_ramp = o.speed_ramp;
  if (!o.nozzle_temps.empty()) {
    options.nozzle_temperatures = o.nozzle_temps;
  } else if (o.thickness_ramp || o.speed_ramp) {
    options.nozzle_temperatures = {material.nozzle_temperature};
  }
  if (!o.layer_heights.empty()) {
    options.layer_heights = o.layer_heights;
  } else if (o.thickness_ramp) {
    options.layer_heights = {0.08, 0.12, 0.16, 0.20, 0.24, 0.28};
  } else if (o.speed_ramp) {
    options.layer_heights = {material.layer_height};
  }
  if (!o.print_speeds.empty()) {
    options.print_speeds = o.print_speeds;
  } else {
    // The default speeds stop at what the printer allows (plan_calibration refuses faster ones
    // when they are asked for).
    std::erase_if(options.print_speeds, [&](double v) { return v > printer.travel_speed; });
  }
  options.repeats = o.repeats;
  options.length = o.size[0];
  options.width = o.size[1];
  options.thickness = o.thickness;
  options.ramp_layers = o.ramp_layers;
  options.spacing = o.spacing;
  options.gap = o.gap;
  options.set_gap = std::max(2 * o.gap, 10.0);
  const CalibrationPlan plan = plan_calibration(printer, material, options);

  // Every file is made (and checked) before any is written.
  const PrintPaths paths = print_paths(o.output, plan.plates.size());
  const std::vector<fs::path>& gcode_paths = paths.gcode;
  std::vector<GcodeResult> results;
  std::vector<Eigen::Vector2d> offsets;
  std::vector<std::string> names;
  for (size_t p = 0; p < plan.plates.size(); ++p) {
    GcodeOptions gcode_options;
    gcode_options.sections = plan.plates[p].sections;
    results.push_back(make_gcode(plan.plates[p].toolpath, printer,
                                 {plate_material(plan, p, material)}, gcode_options));
    offsets.push_back(results.back().plate_to_bed);
    names.push_back(gcode_paths.back().filename().string());
  }
  const fs::path& csv = paths.csv;
  const fs::path& svg = paths.svg;
  create_output_folder(fs::path(o.output).parent_path());
  for (size_t p = 0; p < plan.plates.size(); ++p) write_text(gcode_paths[p], results[p].text);
  write_text(csv, calibration_csv_template(plan, material, printer));
  write_text(svg, calibration_layout_svg(plan, printer, offsets, names));

  if (!global.quiet) {
    fmt::print(
        "{} {} of {} samples ({:g} x {:g} mm, paths {:.3f} mm apart along the length), {} "
        "per set, material {}, printer {}\n",
        plan.sets.size(),
        o.thickness_ramp ? "thickness-ramp sets"
        : o.speed_ramp   ? "speed-ramp sets"
                         : "sets",
        plan.samples.size(), options.length, options.width, plan.extrusion_width, options.repeats,
        material.name, printer.name);
    for (const CalibrationSet& set : plan.sets) {
      fmt::print("  {} ({:.2f} mm thick)\n", set.label(), set.thickness());
    }
    for (size_t p = 0; p < plan.plates.size(); ++p) {
      const long s = std::lround(results[p].print_time);
      fmt::print("wrote {}: {} sets, about {}h {:02}m {:02}s without heating, {:.1f} g\n",
                 gcode_paths[p].string(), plan.plates[p].sets.size(), s / 3600, (s / 60) % 60,
                 s % 60, results[p].filament_mass);
    }
    fmt::print("wrote {} (fill in after heating) and {} (layout and notch legend)\n", csv.string(),
               svg.string());
    fmt::print("then: flatmorph calibrate fit {} -o my-material.json\n", csv.string());
  }
  return 0;
}

// The hinge curve's numbers and the strips it fits worst, for the terminal.
void print_hinge_fit(const HingeCurveFit& fit) {
  const HingeCurve& c = fit.curve;
  fmt::print(
      "hinge curve, fold angle per mm of actuator width (degree {} / {}), calibrated for {:g} to "
      "{:g} mm/s:\n  speed mm/s (mm/min)   case A /mm (radius mm)   case B /mm (radius mm)\n",
      c.case_a_coefficients.size() - 1, c.case_b_coefficients.size() - 1, c.min_speed, c.max_speed);
  for (int i = 0; i <= 4; ++i) {
    const double v = c.min_speed + (c.max_speed - c.min_speed) * i / 4;
    const double a = hinge_curvature(c, v, true), b = hinge_curvature(c, v, false);
    fmt::print("  {:>6.1f} ({:>6.0f})       {:.4f} ({:>5.1f})          {:.4f} ({:>5.1f})\n", v,
               60 * v, a, 1 / a, b, 1 / b);
  }
  fmt::print(
      "residuals (measured - curve x width): case A {:.1f} deg RMS, {:.1f} at most; case B "
      "{:.1f} deg RMS, {:.1f} at most\n",
      fit.rms_residual_a / kDegree, fit.max_residual_a / kDegree, fit.rms_residual_b / kDegree,
      fit.max_residual_b / kDegree);
  for (const HingeStripFit& s : fit.strips) {
    if (std::abs(s.fold_angle - s.predicted) < 5 * kDegree) continue;
    fmt::print("  strip {} (case {}, {:g} mm/s, {:g} mm): measured {:.1f} deg, curve {:.1f}\n",
               s.strip, s.pla_on_bed ? "A" : "B", s.speed, s.width, s.fold_angle / kDegree,
               s.predicted / kDegree);
  }
}

// Refuses a material that its own file could not hold, naming the sheets.
void check_material(const Material& m, const FitOptions& o) {
  try {
    parse_material_json(material_json(m), "the fitted material");
  } catch (const UserError& e) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: {}", fmt::join(o.sheets, ", "), e.what()));
  }
}

// `calibrate fit` of a hinge sheet alone: the material the strips were printed with (or
// --material) with the fitted hinge curve.
int run_hinge_fit(const FitOptions& o, const GlobalOptions& global, const HingeSheet& sheet,
                  const HingeCurveFit& fit) {
  Material m = !o.material.empty() ? load_material(o.material)
               : sheet.material    ? *sheet.material
                                   : load_material("pla-generic");
  const fs::path out(o.output);
  m.name = o.name.empty() ? out.stem().string() : o.name;
  m.description +=
      fmt::format(" (hinge curve: calibrated by flatmorph calibrate fit from {})", sheet.source);
  m.hinge_curve = fit.curve;
  check_material(m, o);
  create_output_folder(out.parent_path());
  write_material(out, m);
  if (!global.quiet) {
    print_hinge_fit(fit);
    fmt::print("wrote {} (use it with --material {})\n", out.string(), out.string());
  }
  return 0;
}

int run_fit(const FitOptions& o, const GlobalOptions& global) {
  std::vector<MeasurementSheet> sheets;
  std::optional<HingeSheet> hinge;
  for (const std::string& path : o.sheets) {
    if (!is_hinge_sheet_file(path)) {
      sheets.push_back(read_measurements(path));
    } else if (hinge) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: a second hinge sheet; give one", path));
    } else {
      hinge = read_hinge_measurements(path);
    }
  }
  std::optional<HingeCurveFit> hinge_fit;
  if (hinge) hinge_fit = fit_hinge_curve(*hinge);
  if (sheets.empty()) return run_hinge_fit(o, global, *hinge, *hinge_fit);
  auto is_ramp = [](const MeasurementSheet& s) { return s.thickness_ramp || s.speed_ramp; };
  bool any_sets = false;
  for (const MeasurementSheet& s : sheets) any_sets = any_sets || !is_ramp(s);

  // Candidates: the sets of the ordinary sheets (or of the ramps when there are none).
  std::vector<SetFit> sets;
  const MeasurementSheet* base_sheet = nullptr;
  std::optional<ThicknessCurve> curve;
  std::optional<SpeedCurve> speed_curve;
  for (const MeasurementSheet& s : sheets) {
    if (s.thickness_ramp) {
      if (curve) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("{}: a second thickness-ramp sheet; give one", s.source));
      }
      curve = fit_thickness_curve(s);
    }
    if (s.speed_ramp) {
      if (speed_curve) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("{}: a second speed-ramp sheet; give one", s.source));
      }
      speed_curve = fit_speed_curve(s);
    }
    if (is_ramp(s) == any_sets) continue;
    for (const SetFit& f : fit_sets(s)) {
      if (o.set > 0 && f.set == o.set && base_sheet != nullptr && base_sheet != &s) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("--set {} is in {} and in {}: fit them one at a time", o.set,
                                    base_sheet->source, s.source));
      }
      if (o.set == 0 || f.set == o.set) base_sheet = &s;
      sets.push_back(f);
    }
    if (base_sheet == nullptr) base_sheet = &s;
  }
  if (sets.empty()) {
    throw UserError(ErrorCategory::kFormat, "no set has a measured sample: nothing to fit");
  }
  std::vector<SetFit> ranked = sets;
  rank_sets(ranked);
  const SetFit* chosen = &ranked.front();
  if (o.set > 0) {
    chosen = nullptr;
    for (const SetFit& f : ranked) {
      if (f.set == o.set) chosen = &f;
    }
    if (chosen == nullptr) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("--set {}: no such set with measured samples in the sheets", o.set));
    }
  }
  Material base;
  if (!o.material.empty()) {
    base = load_material(o.material);
  } else if (base_sheet->material) {
    base = *base_sheet->material;
  } else {
    base = load_material("pla-generic");
  }
  const fs::path out(o.output);
  const std::string name = o.name.empty() ? out.stem().string() : o.name;
  std::string description = fmt::format(
      "calibrated by flatmorph calibrate fit from {}: set {} ({:g} C, {:g} mm x {} layers, "
      "{:.2f} mm{}), {} samples, contraction {:.1f} +- {:.1f} %",
      base_sheet->source, chosen->set, chosen->nozzle_temperature, chosen->layer_height,
      chosen->layers, chosen->thickness,
      chosen->print_speed > 0 ? fmt::format(", {:g} mm/s", chosen->print_speed) : "",
      chosen->samples, chosen->contraction_pct.mean, chosen->contraction_pct.std);
  if (!chosen->delta_lambda1) description += "; delta_lambda1 not measured (kept the base's)";
  if (hinge_fit) description += fmt::format("; hinge curve from {}", hinge->source);
  Material fitted = fitted_material(base, *chosen, name, description);
  fitted.thickness_curve = curve;
  fitted.speed_curve = speed_curve;
  if (hinge_fit) fitted.hinge_curve = hinge_fit->curve;
  // The material file's checks on the whole, before anything is written: a speed curve must cover
  // the print_speed the written set was measured at.
  check_material(fitted, o);

  std::vector<SetFit> all;
  for (const MeasurementSheet& s : sheets) {
    for (const SetFit& f : fit_sets(s)) all.push_back(f);
  }
  const bool plot_speeds =
      std::any_of(all.begin(), all.end(), [](const SetFit& f) { return f.speed_ramp; });
  const bool plot_heights =
      std::any_of(all.begin(), all.end(), [](const SetFit& f) { return !f.speed_ramp; });
  const fs::path plot = o.plot.empty() ? fs::path(out).replace_extension(".svg") : fs::path(o.plot);
  // One plot per x axis: the speed ramp's beside the layer heights' when there are both.
  const fs::path speed_plot =
      plot_heights
          ? plot.parent_path() / (plot.stem().string() + "-speed" + plot.extension().string())
          : plot;
  create_output_folder(out.parent_path());
  write_material(out, fitted);
  if (plot_heights) write_text(plot, contraction_plot_svg(all, curve));
  if (plot_speeds) write_text(speed_plot, speed_contraction_plot_svg(all, speed_curve));

  if (!global.quiet) {
    fmt::print(
        "rank  set  nozzle C  layer mm  layers  mm/s   n   lambda1        lambda2        "
        "lambda3        contraction %   curvature /mm      delta_lambda1\n");
    for (size_t r = 0; r < ranked.size(); ++r) {
      const SetFit& f = ranked[r];
      fmt::print(
          "{:>4}  {:>3}  {:>8g}  {:>8g}  {:>6}  {:>4}  {:>2}  {:.3f}+-{:.3f}  {:.3f}+-{:.3f}  "
          "{:.3f}+-{:.3f}  {:>5.1f}+-{:<5.1f}   {}  {}{}\n",
          r + 1, f.set, f.nozzle_temperature, f.layer_height, f.layers,
          f.print_speed > 0 ? fmt::format("{:g}", f.print_speed) : std::string("-"), f.samples,
          f.lambda1.mean, f.lambda1.std, f.lambda2.mean, f.lambda2.std, f.lambda3.mean,
          f.lambda3.std, f.contraction_pct.mean, f.contraction_pct.std,
          f.curvature ? fmt::format("{:.4f}+-{:.4f}", f.curvature->mean, f.curvature->std)
                      : std::string("    (not measured)"),
          f.delta_lambda1
              ? fmt::format("{:+.4f}+-{:.4f}", f.delta_lambda1->mean, f.delta_lambda1->std)
              : std::string("-"),
          &f == chosen ? "  <- written" : "");
    }
    if (curve) {
      fmt::print(
          "thickness curve: lambda1(h), degree {}, for layer heights {:g} to {:g} mm "
          "({} layers): lambda1 {:.3f} to {:.3f}\n",
          curve->lambda1_coefficients.size() - 1, curve->min_layer_height, curve->max_layer_height,
          curve->layers, lambda1_at_layer_height(*curve, curve->min_layer_height),
          lambda1_at_layer_height(*curve, curve->max_layer_height));
    }
    if (speed_curve) {
      fmt::print(
          "speed curve: lambda1(v), degree {}, for print speeds {:g} to {:g} mm/s ({:g} mm "
          "layers): lambda1 {:.3f} to {:.3f}; print_speed {:g} mm/s is the reference\n",
          speed_curve->lambda1_coefficients.size() - 1, speed_curve->min_print_speed,
          speed_curve->max_print_speed, speed_curve->layer_height,
          lambda1_at_print_speed(*speed_curve, speed_curve->min_print_speed),
          lambda1_at_print_speed(*speed_curve, speed_curve->max_print_speed), fitted.print_speed);
    }
    if (hinge_fit) print_hinge_fit(*hinge_fit);
    fmt::print("wrote {} (use it with --material {}) and {}{}\n", out.string(), out.string(),
               plot_heights ? plot.string() : speed_plot.string(),
               plot_heights && plot_speeds ? " and " + speed_plot.string() : "");
  }
  return 0;
}

}  // namespace

Command make_calibrate_command(CLI::App& app, const GlobalOptions& global) {
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "Measure your own filament: 'calibrate print' writes G-code for test samples (one set per "
      "nozzle temperature and layer height, or per layer height or print speed for the ramps, or "
      "Thermorph's hinge strips), 'calibrate fit' turns their measurements into a material file "
      "(docs/calibration.md).");
  sub->require_subcommand(1);

  auto p = std::make_shared<PrintOptions>();
  CLI::App* print = sub->add_subcommand(
      "print",
      "Write the G-code of the calibration samples (Shrink & Morph §4.1: 80 x 20 x 0.8 mm "
      "cuboids, paths along the length, each sample's id notched into one end), a CSV template "
      "to fill in (OUT.csv) and the layout with sample ids (OUT.svg). Several G-code files "
      "(OUT-1.gcode, ...) when the samples do not fit one bed. With --hinge-sheet, Thermorph's "
      "hinge strips in PLA and TPU instead.");
  print->add_option("--printer", p->printer, "Printer preset name or JSON file")->required();
  print
      ->add_option("--material", p->material,
                   "Material preset name or JSON file: bed, speeds, fan and the safe temperature "
                   "range; with --hinge-sheet two, PLA,TPU (tools 0 and 1)")
      ->required();
  print
      ->add_option("--nozzle-temps", p->nozzle_temps,
                   "Nozzle temperatures, C (default 190,200,210; with --thickness-ramp or "
                   "--speed-ramp the material's)")
      ->delimiter(',');
  print
      ->add_option("--layer-heights", p->layer_heights,
                   "Layer heights, mm (default 0.08,0.12,0.16; with --thickness-ramp "
                   "0.08,0.12,...,0.28; with --speed-ramp the material's)")
      ->delimiter(',');
  print->add_option("--repeats", p->repeats, "Samples per set")->capture_default_str();
  print->add_option("--size", p->size, "Sample LENGTH,WIDTH in mm")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  print
      ->add_option("--thickness", p->thickness,
                   "Sample thickness, mm: round(thickness / layer height) layers")
      ->capture_default_str();
  print->add_flag("--thickness-ramp", p->thickness_ramp,
                  "Layer-thickness calibration (SCF 2020 §6): samples of --ramp-layers layers "
                  "over a range of layer heights, one nozzle temperature");
  print->add_option("--ramp-layers", p->ramp_layers, "Layers of a thickness-ramp sample")
      ->capture_default_str();
  print->add_flag("--speed-ramp", p->speed_ramp,
                  "Print-speed calibration (Thermorph Fig. 6: faster printing stores more stretch, "
                  "so lambda1 gets smaller): one set per --print-speeds at one layer height and "
                  "nozzle temperature (default: the material's); every layer but the first at the "
                  "set's speed, the first at the material's first-layer speed so that it sticks. "
                  "'calibrate fit' on its sheet adds the material's speed curve lambda1(v)");
  print
      ->add_option("--print-speeds", p->print_speeds,
                   "Speeds of a speed ramp, mm/s, at most the printer's travel speed (default "
                   "20,40,60,90,120,150, those the printer allows; Thermorph's 1500-9000 mm/min "
                   "are 25-150 mm/s)")
      ->delimiter(',');
  print->add_flag(
      "--hinge-sheet", p->hinge_sheet,
      "Thermorph's hinge calibration (Fig. 6-7): strips of two 20 x 10 mm PLA faces "
      "joined by an actuator (3 active PLA layers across the hinge, 1 TPU layer, 0.2 mm "
      "each), one per --hinge-speeds x --hinge-widths x --hinge-cases, each coded by "
      "notches; needs --material PLA,TPU and a printer that prints two materials. "
      "'calibrate fit' on its sheet (the fold angles) adds the hinge curve");
  print
      ->add_option("--hinge-speeds", p->hinge_speeds,
                   "Active PLA speeds of the hinge strips, mm/s (default 50,75,100,125,150: the "
                   "paper's 3000-9000 mm/min, those the printer allows)")
      ->delimiter(',');
  print
      ->add_option("--hinge-widths", p->hinge_widths,
                   "Actuator widths of the hinge strips, mm (default 5,10,15,20)")
      ->delimiter(',');
  print
      ->add_option("--hinge-cases", p->hinge_cases,
                   "Stacking cases of the hinge strips: A (PLA on the bed), B (TPU on the bed) "
                   "(default A,B)")
      ->delimiter(',');
  print->add_option("--spacing", p->spacing,
                    "Distance between paths = extrusion width, mm (default: the nozzle diameter)");
  print->add_option("--gap", p->gap, "Gap between samples, mm")->capture_default_str();
  print->add_option("-o,--output", p->output, "G-code file to write (OUT.gcode)")->required();

  auto f = std::make_shared<FitOptions>();
  CLI::App* fit = sub->add_subcommand(
      "fit",
      "Fit a material file to the filled-in measurement CSV(s) of 'calibrate print': lambda1, "
      "lambda2, lambda3 (mean and std per set), the contraction, delta_lambda1 = -h lambda3 "
      "lambda1 kappa from the curl (Shrink & Morph §4.2); ranks the sets by contraction and "
      "writes the best (or --set); a thickness-ramp CSV adds the thickness curve, a speed-ramp CSV "
      "the speed curve (a set of a speed ramp also sets print_speed, the speed it was measured "
      "at), a hinge sheet the hinge curve (fold angle per mm of actuator width vs the active "
      "PLA's speed, per case; alone, it is added to the material the strips were printed with). "
      "Also writes OUT.svg, contraction vs layer height per temperature (Fig. 8), or vs "
      "print speed for a speed ramp (OUT-speed.svg beside other sheets).");
  fit->add_option("measurements", f->sheets, "Filled-in CSV file(s)")->required();
  fit->add_option("-o,--output", f->output, "Material file to write (JSON)")->required();
  fit->add_option("--set", f->set, "Write this set instead of the best one (the set column)");
  fit->add_option("--material", f->material,
                  "Base material for the keys not measured (default: the one the samples were "
                  "printed with, recorded in the CSV)");
  fit->add_option("--name", f->name, "Material name (default: the output file's name)");
  fit->add_option("--plot", f->plot, "Plot file (default: OUT with .svg)");

  return {sub, [sub, print, fit, p, f, &global] {
            (void)sub;
            if (print->parsed()) return run_print(*p, global);
            if (fit->parsed()) return run_fit(*f, global);
            return 2;
          }};
}

}  // namespace flatmorph::cli
