#include "methods/heightfield/png_bytes.h"

#include <fmt/core.h>

#include <algorithm>
#include <climits>

#include "common/error.h"
#include "methods/heightfield/gray_image.h"

namespace flatmorph::png_bytes {
namespace {

// The unsigned 32-bit big-endian integer at byte `at` (the caller checks that 4 bytes are there).
uint32_t big_endian_32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

[[noreturn]] void refuse(ErrorCategory category, const std::string& source,
                         const std::string& problem) {
  throw UserError(category, fmt::format("{}: {}", source, problem));
}

}  // namespace

void check_png_structure(std::string_view bytes, const std::string& source,
                         const PngAdvice& advice) {
  if (bytes.empty())
    refuse(ErrorCategory::kFormat, source, fmt::format("empty file: {}", advice.if_empty));
  if (bytes.size() < kPngSignature.size() ||
      !std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin(),
                  [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); })) {
    refuse(ErrorCategory::kFormat, source,
           fmt::format("not a PNG file (it does not start with the PNG signature): {}",
                       advice.if_not_png));
  }
  if (bytes.size() > static_cast<size_t>(INT_MAX)) {
    refuse(ErrorCategory::kResource, source,
           fmt::format("{} bytes is too large for a {} PNG; scale the image down to at most "
                       "8192 x 8192 pixels",
                       bytes.size(), advice.what));
  }
  // IHDR is always the first chunk.
  if (bytes.size() >= 24 && bytes.substr(12, 4) == "IHDR") {
    const uint32_t width = big_endian_32(bytes, 16), height = big_endian_32(bytes, 20);
    if (width == 0 || height == 0) {
      refuse(ErrorCategory::kFormat, source,
             fmt::format("the PNG has zero size ({} x {} pixels): {}", width, height,
                         advice.if_zero_size));
    }
    if (static_cast<uint64_t>(width) * height > static_cast<uint64_t>(kMaxGrayImagePixels)) {
      refuse(ErrorCategory::kResource, source,
             fmt::format("{} x {} pixels is more than flatmorph reads (8192 x 8192 pixels in "
                         "all); {}",
                         width, height, advice.if_too_large));
    }
  }
  size_t at = kPngSignature.size();
  while (at + 8 <= bytes.size()) {
    const uint64_t length = big_endian_32(bytes, at);
    if (at + 12 + length > bytes.size()) {
      refuse(ErrorCategory::kFormat, source,
             fmt::format("the PNG is truncated or damaged (a chunk at byte {} claims {} bytes, "
                         "past the end of the file): {}",
                         at, length, advice.if_damaged));
    }
    if (bytes.substr(at + 4, 4) == "IEND") return;
    at += 12 + length;
  }
  refuse(
      ErrorCategory::kFormat, source,
      fmt::format("the PNG is truncated (it ends before its IEND chunk): {}", advice.if_damaged));
}

}  // namespace flatmorph::png_bytes
