// libFuzzer target for plate stack files (read_plate_design reading flat.stack.json beside a fixed
// flat.ply of two faces): any bytes give a PlateDesign or a UserError, nothing else. The reader
// takes files, so each input goes through a temporary folder of this process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.h"
#include "mesh/io.h"
#include "plate/plate_design.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  static const std::filesystem::path dir = [] {
    const std::filesystem::path d = std::filesystem::temp_directory_path() /
                                    ("flatmorph-fuzz-stack-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    // The plate of tests/data/stack/two_faces.stack.json: a 10 mm square cut in two, per-face
    // property layer_2_theta.
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
  {
    std::ofstream out(dir / "flat.stack.json", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    read_plate_design(dir / "flat.ply", Material{}, 10);
  } catch (const UserError&) {
  }
  return 0;
}
