// libFuzzer target for the G-code reader (read_gcode_deposition): any bytes give the beads they
// deposit or a UserError, nothing else. Small line and bead limits keep every input fast; the
// limits' own errors are UserErrors too.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "gcode/gcode_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  GcodeReadOptions options;
  options.max_lines = 5000;
  options.max_beads = 20000;
  try {
    read_gcode_deposition(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.gcode",
                          options);
  } catch (const UserError&) {
  }
  return 0;
}
