// libFuzzer target for one mesh reader (FLATMORPH_FUZZ_FORMAT: kObj, kPly, kStl or kOff): any
// bytes must either give a mesh or a UserError; anything else (a crash, a sanitizer report, another
// exception, a hang) is a bug. A mesh that reads is also checked and repaired as the commands do,
// so that hostile geometry reaches the validation code too.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "mesh/io_internal.h"
#include "mesh/validate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    MeshFile file =
        mesh_io::read_mesh_bytes(bytes, "fuzz", mesh_io::MeshFormat::FLATMORPH_FUZZ_FORMAT);
    diagnose_mesh(file.mesh);
    repair_mesh(file.mesh);
    require_disk(file.mesh, "fuzz");
  } catch (const UserError&) {
    // The expected answer to a bad file.
  }
  return 0;
}
