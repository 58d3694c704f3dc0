// Writing small PNGs for the height-map tests, with zlib and nothing of stb_image, so that the
// reader is judged by an independent writer. Grayscale, gray + alpha, RGB and RGBA, 8 or 16 bits.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

namespace flatmorph::testing {

enum class PngColor : uint8_t { kGray = 0, kRgb = 2, kGrayAlpha = 4, kRgba = 6 };

inline int png_channels(PngColor color) {
  switch (color) {
    case PngColor::kGray:
      return 1;
    case PngColor::kGrayAlpha:
      return 2;
    case PngColor::kRgb:
      return 3;
    case PngColor::kRgba:
      return 4;
  }
  return 0;
}

// A PNG of width x height pixels; `samples` holds channels x width x height values, row by row
// from the top, each below 2^bits (bits 8 or 16, stored big-endian as PNG wants).
inline std::string encode_test_png(int width, int height, int bits, PngColor color,
                                   const std::vector<uint16_t>& samples) {
  const int channels = png_channels(color);
  std::vector<unsigned char> raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter None
    for (int x = 0; x < width * channels; ++x) {
      const uint16_t s = samples[static_cast<size_t>(y) * width * channels + x];
      if (bits == 16) raw.push_back(static_cast<unsigned char>(s >> 8));
      raw.push_back(static_cast<unsigned char>(s & 0xff));
    }
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<unsigned char> compressed(size);
  compress2(compressed.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 9);
  compressed.resize(size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  auto be32 = [](std::string& out, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>(v >> s));
  };
  auto chunk = [&](const char* type, const std::string& data) {
    be32(png, static_cast<uint32_t>(data.size()));
    const std::string body = std::string(type, 4) + data;
    png += body;
    be32(png, static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()),
                                          static_cast<uInt>(body.size()))));
  };
  std::string ihdr;
  be32(ihdr, static_cast<uint32_t>(width));
  be32(ihdr, static_cast<uint32_t>(height));
  ihdr += {static_cast<char>(bits), static_cast<char>(color), 0, 0, 0};
  chunk("IHDR", ihdr);
  chunk("IDAT", std::string(compressed.begin(), compressed.end()));
  chunk("IEND", "");
  return png;
}

}  // namespace flatmorph::testing
