#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/png_bytes.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {
namespace {

using png_bytes::kMaxFileBytes;
using png_bytes::StbFree;

// Rec. 709 luma weights (they sum to 1, so a gray RGB pixel keeps its value exactly).
constexpr double kRed = 0.2126, kGreen = 0.7152, kBlue = 0.0722;

// Gray samples from a decoded image of `channels` channels (1 gray, 2 gray + alpha, 3 RGB, 4 RGBA).
template <typename Sample>
std::vector<uint16_t> to_gray(const Sample* pixels, size_t count, int channels, int max_value) {
  std::vector<uint16_t> gray(count);
  for (size_t i = 0; i < count; ++i) {
    const Sample* p = pixels + i * channels;
    if (channels <= 2) {
      gray[i] = p[0];
      continue;
    }
    const double y = std::round(kRed * p[0] + kGreen * p[1] + kBlue * p[2]);
    gray[i] = static_cast<uint16_t>(std::min(y, static_cast<double>(max_value)));
  }
  return gray;
}

constexpr png_bytes::PngAdvice kHeightMapAdvice = {
    .what = "height map",
    .if_empty = "save the height map as an 8- or 16-bit PNG",
    .if_not_png = "save the height map as an 8- or 16-bit grayscale PNG",
    .if_zero_size = "export the height map again",
    .if_too_large = "scale the image down",
    .if_damaged = "export the height map again as an 8- or 16-bit PNG"};

[[noreturn]] void throw_undecodable(const std::string& source) {
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("{}: not a readable PNG image ({}): the file is truncated or "
                              "damaged; export the height map again as an 8- or 16-bit PNG",
                              source, stbi_failure_reason()));
}

}  // namespace

GrayImage read_gray_png_bytes(std::string_view bytes, const std::string& source) {
  png_bytes::check_png_structure(bytes, source, kHeightMapAdvice);
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int length = static_cast<int>(bytes.size());
  int channels = 0;
  GrayImage image;
  // stbi_load_16 keeps all 16 bits of a 16-bit file; stbi_load would cut them to 8.
  const bool sixteen = stbi_is_16_bit_from_memory(data, length);
  image.bits = sixteen ? 16 : 8;
  const auto decode = [&](auto* pixels) {
    std::unique_ptr<std::remove_pointer_t<decltype(pixels)>, StbFree> owned(pixels);
    if (!owned) throw_undecodable(source);
    image.samples = to_gray(owned.get(), static_cast<size_t>(image.width) * image.height, channels,
                            image.max_value());
  };
  if (sixteen) {
    decode(stbi_load_16_from_memory(data, length, &image.width, &image.height, &channels, 0));
  } else {
    decode(stbi_load_from_memory(data, length, &image.width, &image.height, &channels, 0));
  }
  return image;
}

GrayImage read_gray_png(const std::filesystem::path& path) {
  const std::string source = path.string();
  const std::string bytes = read_file_text(path, "height map PNG", [&](std::uintmax_t size) {
    if (size > kMaxFileBytes) {
      throw UserError(ErrorCategory::kResource,
                      fmt::format("{}: {} bytes is too large for a height map PNG; scale the "
                                  "image down to at most 8192 x 8192 pixels",
                                  source, size));
    }
  });
  return read_gray_png_bytes(bytes, source);
}

}  // namespace flatmorph
