// libFuzzer target for the crease-pattern SVG reader (origami's forward flow): its colours,
// opacities and angles, and the arrangement that cuts the lines into faces. Any bytes must either
// give a crease pattern or a UserError; anything else (a crash, a sanitizer report, another
// exception, a hang, a huge allocation) is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "methods/origami/crease_pattern_svg.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    std::vector<std::string> warnings;
    read_crease_pattern_svg(bytes, "fuzz", {}, &warnings);
  } catch (const UserError&) {
    // The expected answer to a bad file.
  }
  return 0;
}
