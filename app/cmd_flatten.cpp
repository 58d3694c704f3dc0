// flatmorph flatten: the flat plate of a target surface and its print directions theta1
// (Shrink & Morph §3.2.1; docs/flatten.md).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "commands.h"
#include "common/error.h"
#include "common/stopwatch.h"
#include "material/material.h"
#include "mesh/io.h"
#include "mesh/prepare.h"
#include "mesh_input.h"
#include "methods/shrink_morph/design.h"
#include "methods/shrink_morph/flatten.h"
#include "output_folder.h"

namespace flatmorph::cli {
namespace {

// More faces than this would need more memory and time than a design run should.
constexpr int kMaxFaces = 2'000'000;

struct FlattenCliOptions {
  RunInput input;
  double width_mm = std::numeric_limits<double>::quiet_NaN();
  double w_D = 0.0;
  std::string material = "pla-paper";
  int layers = 10;
  int faces = 10000;
  bool flip = false;
  std::string output;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

// Checked before anything is read or written, so that a bad value leaves no output behind.
void check(const FlattenCliOptions& o) {
  require(std::isfinite(o.width_mm) && o.width_mm > 0,
          fmt::format("--width {}: the plate width must be a positive number of mm (e.g. --width "
                      "150)",
                      o.width_mm));
  require(std::isfinite(o.w_D) && o.w_D >= 0,
          fmt::format("--wD {}: the smoothing weight must be 0 (no smoothing) or positive (the "
                      "paper uses 0.1)",
                      o.w_D));
  require(o.faces >= 1 && o.faces <= kMaxFaces,
          fmt::format("--faces {}: the face count must be between 1 and {}", o.faces, kMaxFaces));
  require(o.layers >= 1 && o.layers <= 1000,
          fmt::format("--layers {}: give 1 to 1000 layers", o.layers));
  require(!o.output.empty(), "flatmorph flatten needs an output folder: -o DIR");
}

int run_flatten(const FlattenCliOptions& options, const GlobalOptions& global) {
  check(options);
  const Material material = load_material(options.material);

  const auto start = Clock::now();
  const std::string source = describe(options.input);
  const PreparedTarget prepared =
      prepare_target(read_target_mesh(options.input).mesh, source, options.faces);
  const Mesh& mesh = prepared.mesh;
  const int input_faces = prepared.input_faces;
  const double prepare_seconds = seconds_since(start);

  FlattenOptions flatten_options =
      flatmorph::flatten_options(material, options.width_mm, options.w_D);
  flatten_options.flip = options.flip;
  const FlatPlate plate = flatten(mesh, flatten_options);

  // The plate at z = 0 with the target's vertex and face order, so the two files pair up, printed
  // with theta2 = 0.
  const std::filesystem::path dir = options.output;
  create_output_folder(dir);
  write_ply(dir / "target.ply", plate.target);
  write_plate_design(dir / "flat.ply",
                     shrink_morph_plate_design(plate, Eigen::VectorXd(), material, options.layers));

  for (const std::string& warning : plate.warnings) {
    fmt::print(stderr, "flatmorph: warning: {}\n", warning);
  }
  if (global.quiet) return 0;
  const Eigen::RowVector2d extent =
      plate.plate.colwise().maxCoeff() - plate.plate.colwise().minCoeff();
  fmt::print("target:      {} ({} faces, {} after Loop subdivision, {} vertices)\n", source,
             input_faces, plate.target.num_faces(), plate.target.num_vertices());
  fmt::print("material:    {} (lambda1 {}, lambda2 {})\n", material.name, material.lambda1,
             material.lambda2);
  fmt::print("plate:       {:.1f} x {:.1f} mm{}\n", extent(0), extent(1),
             options.flip ? ", target's normal side down (--flip)" : "");
  fmt::print("singular-value deviation: mean {:.3f} %, max {:.2f} %\n",
             100 * plate.feasibility.mean_deviation, 100 * plate.feasibility.max_deviation);
  fmt::print("infeasible area (deviation > 5 %): {:.2f} %\n",
             100 * plate.feasibility.infeasible_area_fraction);
  fmt::print("Dirichlet energy of e^(2i theta1): {:.2f}\n", plate.direction_dirichlet);
  fmt::print("time:        prepare {:.2f} s", prepare_seconds);
  for (const FlattenStep& step : plate.steps) {
    fmt::print(", {} {:.2f} s", step.name, step.seconds);
    if (step.name != "tutte") fmt::print(" ({} it)", step.iterations);
  }
  fmt::print("\nwrote:       {}, {}\n", (dir / "flat.ply").string(), (dir / "target.ply").string());
  return 0;
}

}  // namespace

Command make_flatten_command(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<FlattenCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "flatten",
      "Flatten a target surface into the plate to print and its print directions theta1 "
      "(Shrink & Morph 3.2.1). Writes DIR/flat.ply (the plate at z = 0, per-face theta1 in "
      "radians and sv_deviation) and DIR/target.ply (the target scaled like the plate, same "
      "vertex and face order). The side the target's face normals point to becomes the top of "
      "the plate, away from the print bed.");
  add_mesh_input(sub, options->input);
  sub->add_option("--width", options->width_mm,
                  "Largest extent of the plate, in mm; the target is scaled by the same factor")
      ->required();
  sub->add_option("--wD", options->w_D,
                  "Smoothing weight of the print directions (Eq. 12), 0 for none; the paper "
                  "uses 0.1 for smoother paths at a small cost in shape accuracy")
      ->capture_default_str();
  sub->add_option("--layers", options->layers,
                  "Number of printed layers the plate's stack file records (flat.stack.json; "
                  "toolpaths and simulate print that many)")
      ->capture_default_str();
  sub->add_option("--material", options->material,
                  "Material preset name or material JSON file; its shrink ratios lambda1, "
                  "lambda2 set the plate (see 'flatmorph materials')")
      ->capture_default_str();
  sub->add_option("--faces", options->faces,
                  "Loop-subdivide the target until it has at least this many faces")
      ->capture_default_str();
  sub->add_flag("--flip", options->flip,
                "Print the other side down: the side the target's normals point to goes on the "
                "bed");
  sub->add_option("-o,--output", options->output,
                  "Output folder (created if needed) for flat.ply and target.ply")
      ->required();
  return {sub, [options, &global] { return run_flatten(*options, global); }};
}

}  // namespace flatmorph::cli
