// Grayscale images read from PNG files: the pixels of a height-field image (SCF 2020 input). An
// image has no units; height_field_from_image gives it millimetres.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

// The largest image read, in pixels (width x height): 8192 x 8192 is already far finer than a
// printed plate can show (0.02 mm per pixel over 180 mm), and decoding more costs gigabytes.
inline constexpr long long kMaxGrayImagePixels = 8192LL * 8192LL;

struct GrayImage {
  int width = 0;   // pixels
  int height = 0;  // pixels
  int bits = 8;    // 8 or 16: the depth of the file's samples, kept so that no level is lost
  // Row-major, top row first, width * height samples in [0, max_value()].
  std::vector<uint16_t> samples;

  int max_value() const { return (1 << bits) - 1; }
  uint16_t at(int x, int y) const { return samples[static_cast<size_t>(y) * width + x]; }
};

// Reads a PNG: grayscale (8 or 16 bits) as it is; grayscale + alpha, RGB and RGBA as their
// luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709 weights on the stored values, rounded),
// at the file's bit depth. Alpha is ignored: a height map's transparency has no height. Palette
// PNGs are expanded to RGB first. Throws UserError naming the file: kFile when it cannot be
// read, kFormat when it is not a PNG, is truncated or damaged, or has zero size, kResource when it
// has more than kMaxGrayImagePixels pixels.
GrayImage read_gray_png(const std::filesystem::path& path);

// The same from bytes in memory; `source` names them in messages.
GrayImage read_gray_png_bytes(std::string_view bytes, const std::string& source);

}  // namespace flatmorph
