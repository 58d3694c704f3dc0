#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/png_bytes.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>

#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {
namespace {

using png_bytes::big_endian_32;
using png_bytes::kMaxFileBytes;
using png_bytes::kPngSignature;
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

// Every chunk up to IEND must lie within the file. stb_image sizes its buffers by what the chunk
// headers claim, before reading: a few hundred bytes claiming a 2 GB chunk would have it allocate
// 2 GB. After this, what it allocates for the data is bounded by the file's size.
void check_chunks(std::string_view bytes, const std::string& source) {
  size_t at = kPngSignature.size();
  while (at + 8 <= bytes.size()) {
    const uint64_t length = big_endian_32(bytes, at);
    const std::string type(bytes.substr(at + 4, 4));
    if (at + 12 + length > bytes.size()) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: the PNG is truncated or damaged (a chunk at byte {} claims "
                                  "{} bytes, past the end of the file): export the height map "
                                  "again as an 8- or 16-bit PNG",
                                  source, at, length));
    }
    if (type == "IEND") return;
    at += 12 + length;
  }
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("{}: the PNG is truncated (it ends before its IEND chunk): export "
                              "the height map again as an 8- or 16-bit PNG",
                              source));
}

[[noreturn]] void throw_undecodable(const std::string& source) {
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("{}: not a readable PNG image ({}): the file is truncated or "
                              "damaged; export the height map again as an 8- or 16-bit PNG",
                              source, stbi_failure_reason()));
}

}  // namespace

GrayImage read_gray_png_bytes(std::string_view bytes, const std::string& source) {
  if (bytes.empty()) {
    throw UserError(
        ErrorCategory::kFormat,
        fmt::format("{}: empty file: save the height map as an 8- or 16-bit PNG", source));
  }
  if (bytes.size() < kPngSignature.size() ||
      !std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin(),
                  [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); })) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: not a PNG file (it does not start with the PNG signature): "
                                "save the height map as an 8- or 16-bit grayscale PNG",
                                source));
  }
  if (bytes.size() > static_cast<size_t>(INT_MAX)) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: {} bytes is too large for a height map PNG; scale the image "
                                "down to at most 8192 x 8192 pixels",
                                source, bytes.size()));
  }
  // The size from the header (IHDR, always the first chunk) before stb_image sees the file, so
  // that zero and absurd sizes get their own message and nothing is allocated for the latter.
  if (bytes.size() >= 24 && bytes.substr(12, 4) == "IHDR") {
    const uint32_t width = big_endian_32(bytes, 16), height = big_endian_32(bytes, 20);
    if (width == 0 || height == 0) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: the PNG has zero size ({} x {} pixels): export the height "
                                  "map again",
                                  source, width, height));
    }
    if (static_cast<uint64_t>(width) * height > static_cast<uint64_t>(kMaxGrayImagePixels)) {
      throw UserError(ErrorCategory::kResource,
                      fmt::format("{}: {} x {} pixels is more than flatmorph reads (8192 x 8192 "
                                  "pixels in all); scale the image down",
                                  source, width, height));
    }
  }
  check_chunks(bytes, source);
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
