// libFuzzer target for the height-map PNG reader: any bytes must either give an image or a
// UserError; anything else (a crash, a sanitizer report, another exception, a hang) is a bug. An
// image that reads is also turned into a coarse height field and checked, as the heightfield
// method does, so that hostile pixels reach the depression and overhang checks too.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/height_field.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const GrayImage image = read_gray_png_bytes(bytes, "fuzz");
    // 32 x 24 squares whatever the image's size: the checks, not the grid, are under test.
    height_field_from_image(image, 160.0, 120.0, 35.0, 5.0, "fuzz");
  } catch (const UserError&) {
    // The expected answer to a bad file or a refused surface.
  }
  return 0;
}
