// libFuzzer target for the DXF tile-outline reader: any bytes must either give outlines or a
// UserError; anything else (a crash, a sanitizer report, another exception, a hang, a huge
// allocation) is a bug. The reader chains, nests and checks the loops for crossings itself, so
// hostile geometry reaches those stages too.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "methods/tiles/dxf_outlines.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    std::vector<std::string> warnings;
    read_dxf_outlines(bytes, "fuzz", {}, &warnings);
  } catch (const UserError&) {
    // The expected answer to a bad file.
  }
  return 0;
}
