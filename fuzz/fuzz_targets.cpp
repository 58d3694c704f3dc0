// One libFuzzer program for every reader: FLATMORPH_FUZZ_TARGET names the reader under test
// (fuzz/README.md lists them). One program rather than one per reader so that the sanitized tree
// links the library once. For each target, any bytes must give a result or a UserError; anything
// else (a crash, a sanitizer report, another exception, a hang) is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "calibration/fit.h"
#include "calibration/measurements.h"
#include "common/error.h"
#include "gcode/gcode_reader.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/io.h"
#include "mesh/io_internal.h"
#include "mesh/validate.h"
#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/height_field.h"
#include "methods/origami/crease_pattern_svg.h"
#include "methods/tiles/dxf_outlines.h"
#include "methods/tiles/svg_outlines.h"
#include "plate/plate_design.h"

namespace flatmorph {
namespace {

// A mesh that reads is also checked and repaired as the commands do, so that hostile geometry
// reaches the validation code too.
void read_mesh(std::string_view bytes, mesh_io::MeshFormat format) {
  MeshFile file = mesh_io::read_mesh_bytes(bytes, "fuzz", format);
  diagnose_mesh(file.mesh);
  repair_mesh(file.mesh);
  require_disk(file.mesh, "fuzz");
}

// The input as a file of this process, for the readers that take a path.
void write_bytes(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::filesystem::path process_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("flatmorph-fuzz-" + name + "-" + std::to_string(::getpid()));
}

void read_material(std::string_view bytes) {
  static const std::filesystem::path path = process_temp_path("material").string() + ".json";
  write_bytes(path, bytes);
  load_material(path.string());
}

// read_plate_design reading flat.stack.json beside a fixed flat.ply: the plate of
// tests/data/stack/two_faces.stack.json, a 10 mm square cut in two, per-face layer_2_theta.
void read_stack(std::string_view bytes) {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d = process_temp_path("stack");
    std::filesystem::create_directories(d);
    Mesh mesh;
    mesh.V.resize(4, 3);
    mesh.V << 0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0;
    mesh.F.resize(2, 3);
    mesh.F << 0, 1, 2, 0, 2, 3;
    MeshProperties properties;
    properties.set_face("layer_2_theta", Eigen::Vector2d(0.5, -0.25));
    write_ply(d / "flat.ply", mesh, properties);
    return d;
  }();
  write_bytes(dir / "flat.stack.json", bytes);
  read_plate_design(dir / "flat.ply", Material{}, 10);
}

void read_gcode(std::string_view bytes) {
  GcodeReadOptions options;
  options.max_lines = 5000;
  options.max_beads = 20000;
  read_gcode_deposition(bytes, "fuzz.gcode", options);
}

// An image that reads is turned into a coarse height field (32 x 24 squares whatever its size)
// and checked as the heightfield method does, so that hostile pixels reach the depression and
// overhang checks too.
void read_height_image(std::string_view bytes) {
  const GrayImage image = read_gray_png_bytes(bytes, "fuzz");
  height_field_from_image(image, 160.0, 120.0, 35.0, 5.0, "fuzz");
}

void read_measurement_sheet(std::string_view bytes) {
  const MeasurementSheet sheet = parse_measurements(bytes, "fuzz");
  sample_ratios(sheet);
  fit_sets(sheet);
}

struct FuzzTarget {
  const char* name;
  void (*read)(std::string_view bytes);
};

const FuzzTarget kTargets[] = {
    {"fuzz_obj", [](std::string_view b) { read_mesh(b, mesh_io::MeshFormat::kObj); }},
    {"fuzz_ply", [](std::string_view b) { read_mesh(b, mesh_io::MeshFormat::kPly); }},
    {"fuzz_stl", [](std::string_view b) { read_mesh(b, mesh_io::MeshFormat::kStl); }},
    {"fuzz_off", [](std::string_view b) { read_mesh(b, mesh_io::MeshFormat::kOff); }},
    {"fuzz_material", read_material},
    {"fuzz_printer", [](std::string_view b) { parse_printer(b, "fuzz"); }},
    {"fuzz_csv", read_measurement_sheet},
    {"fuzz_stack", read_stack},
    {"fuzz_gcode", read_gcode},
    {"fuzz_height_image", read_height_image},
    {"fuzz_dxf_outlines",
     [](std::string_view b) {
       std::vector<std::string> warnings;
       read_dxf_outlines(b, "fuzz", {}, &warnings);
     }},
    {"fuzz_svg_outlines",
     [](std::string_view b) {
       std::vector<std::string> warnings;
       read_svg_outlines(b, "fuzz", {}, &warnings);
     }},
    {"fuzz_crease_pattern_svg",
     [](std::string_view b) {
       std::vector<std::string> warnings;
       read_crease_pattern_svg(b, "fuzz", {}, &warnings);
     }},
};

const FuzzTarget* chosen_target = nullptr;

}  // namespace
}  // namespace flatmorph

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  using flatmorph::kTargets;
  const char* name = std::getenv("FLATMORPH_FUZZ_TARGET");
  for (const auto& target : kTargets) {
    if (name != nullptr && std::string_view(name) == target.name) {
      flatmorph::chosen_target = &target;
      return 0;
    }
  }
  std::fprintf(stderr, "flatmorph_fuzz: set FLATMORPH_FUZZ_TARGET to one of:");
  for (const auto& target : kTargets) std::fprintf(stderr, " %s", target.name);
  std::fprintf(stderr, " (it is %s)\n", name != nullptr ? name : "not set");
  std::exit(2);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    flatmorph::chosen_target->read(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const flatmorph::UserError&) {
    // The expected answer to a bad input.
  }
  return 0;
}
