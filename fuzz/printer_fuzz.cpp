// libFuzzer target for printer profile JSON (parse_printer): any bytes give a PrinterProfile or a
// UserError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "gcode/printer_profile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  try {
    parse_printer(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const UserError&) {
  }
  return 0;
}
