#include "methods/heightfield/color_image.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <type_traits>

#include "common/error.h"
#include "common/file_text.h"
#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/png_bytes.h"

namespace flatmorph {
namespace {

using png_bytes::big_endian_32;
using png_bytes::kMaxFileBytes;
using png_bytes::kPngSignature;
using png_bytes::StbFree;

constexpr const char* kExportAgain = "export the texture again as an 8- or 16-bit PNG";

// Coordinates this close outside [0, 1] are float rounding of an edge, not a repeat.
constexpr double kUvEdgeTolerance = 1e-6;

[[noreturn]] void refuse(ErrorCategory category, const std::string& source,
                         const std::string& problem) {
  throw UserError(category, fmt::format("{}: {}", source, problem));
}

// What stb_image must not see (as read_gray_png_bytes checks, worded for a texture): no signature,
// a zero or absurd size in IHDR, a chunk claiming more bytes than the file holds (stb_image would
// allocate what it claims before reading), no IEND.
void check_png_structure(std::string_view bytes, const std::string& source) {
  if (bytes.empty())
    refuse(ErrorCategory::kFormat, source, fmt::format("empty file: {}", kExportAgain));
  if (bytes.size() < kPngSignature.size() ||
      !std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin(),
                  [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); })) {
    refuse(ErrorCategory::kFormat, source,
           "not a PNG file (it does not start with the PNG signature): flatmorph reads textures "
           "as PNG only; convert the image (e.g. `convert texture.jpg texture.png`)");
  }
  if (bytes.size() > static_cast<size_t>(INT_MAX)) {
    refuse(ErrorCategory::kResource, source,
           fmt::format("{} bytes is too large for a texture PNG; scale the image down to at most "
                       "8192 x 8192 pixels",
                       bytes.size()));
  }
  if (bytes.size() >= 24 && bytes.substr(12, 4) == "IHDR") {
    const uint32_t width = big_endian_32(bytes, 16), height = big_endian_32(bytes, 20);
    if (width == 0 || height == 0) {
      refuse(
          ErrorCategory::kFormat, source,
          fmt::format("the PNG has zero size ({} x {} pixels): {}", width, height, kExportAgain));
    }
    if (static_cast<uint64_t>(width) * height > static_cast<uint64_t>(kMaxGrayImagePixels)) {
      refuse(ErrorCategory::kResource, source,
             fmt::format("{} x {} pixels is more than flatmorph reads (8192 x 8192 pixels in "
                         "all); scale the texture down",
                         width, height));
    }
  }
  size_t at = kPngSignature.size();
  while (at + 8 <= bytes.size()) {
    const uint64_t length = big_endian_32(bytes, at);
    if (at + 12 + length > bytes.size()) {
      refuse(ErrorCategory::kFormat, source,
             fmt::format("the PNG is truncated or damaged (a chunk at byte {} claims {} bytes, "
                         "past the end of the file): {}",
                         at, length, kExportAgain));
    }
    if (bytes.substr(at + 4, 4) == "IEND") return;
    at += 12 + length;
  }
  refuse(ErrorCategory::kFormat, source,
         fmt::format("the PNG is truncated (it ends before its IEND chunk): {}", kExportAgain));
}

// RGB samples from a decoded image of `channels` channels (1 gray, 2 gray + alpha, 3 RGB, 4 RGBA),
// alpha composited on white.
template <typename Sample>
std::vector<uint16_t> to_rgb(const Sample* pixels, size_t count, int channels, int max_value) {
  std::vector<uint16_t> rgb(count * 3);
  const double max = max_value;
  for (size_t i = 0; i < count; ++i) {
    const Sample* p = pixels + i * channels;
    const bool gray = channels <= 2;
    const bool alpha = channels == 2 || channels == 4;
    for (int k = 0; k < 3; ++k) {
      const double c = gray ? p[0] : p[k];
      if (!alpha) {
        rgb[i * 3 + k] = static_cast<uint16_t>(c);
        continue;
      }
      const double a = p[channels - 1] / max;
      const double on_white = max - a * (max - c);
      rgb[i * 3 + k] = static_cast<uint16_t>(std::clamp(std::round(on_white), 0.0, max));
    }
  }
  return rgb;
}

// Where coordinate t in [0, 1]-with-repeat falls: the pixel index below it and the weight of the
// one above, along an axis of n pixels whose ends are pixel centres.
void locate(double t, int n, int& below, double& weight) {
  if (t < -kUvEdgeTolerance || t > 1.0 + kUvEdgeTolerance) t -= std::floor(t);
  t = std::clamp(t, 0.0, 1.0);
  if (n == 1) {
    below = 0;
    weight = 0.0;
    return;
  }
  const double x = t * (n - 1);
  below = std::min(static_cast<int>(std::floor(x)), n - 2);
  weight = x - below;
}

}  // namespace

Eigen::Vector3d ColorImage::at(int x, int y) const {
  const size_t i = (static_cast<size_t>(y) * width + x) * 3;
  return Eigen::Vector3d(rgb[i], rgb[i + 1], rgb[i + 2]) / static_cast<double>(max_value());
}

Eigen::Vector3d sample_bilinear(const ColorImage& image, double u, double v) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    throw std::invalid_argument("sample_bilinear: empty image or samples not 3 x width x height");
  }
  if (!std::isfinite(u) || !std::isfinite(v)) {
    throw std::invalid_argument("sample_bilinear: texture coordinates must be finite");
  }
  int x = 0, y = 0;
  double wx = 0.0, wy = 0.0;
  locate(u, image.width, x, wx);
  // Rows run down from the top while v runs up: row = (1 - v) (height - 1).
  locate(1.0 - v, image.height, y, wy);
  const int x1 = std::min(x + 1, image.width - 1), y1 = std::min(y + 1, image.height - 1);
  return (1 - wy) * ((1 - wx) * image.at(x, y) + wx * image.at(x1, y)) +
         wy * ((1 - wx) * image.at(x, y1) + wx * image.at(x1, y1));
}

ColorImage read_color_png_bytes(std::string_view bytes, const std::string& source) {
  check_png_structure(bytes, source);
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int length = static_cast<int>(bytes.size());
  int channels = 0;
  ColorImage image;
  // stbi_load_16 keeps all 16 bits of a 16-bit file; stbi_load would cut them to 8.
  const bool sixteen = stbi_is_16_bit_from_memory(data, length);
  image.bits = sixteen ? 16 : 8;
  const auto decode = [&](auto* pixels) {
    std::unique_ptr<std::remove_pointer_t<decltype(pixels)>, StbFree> owned(pixels);
    if (!owned) {
      refuse(ErrorCategory::kFormat, source,
             fmt::format("not a readable PNG image ({}): the file is truncated or damaged; {}",
                         stbi_failure_reason(), kExportAgain));
    }
    image.rgb = to_rgb(owned.get(), static_cast<size_t>(image.width) * image.height, channels,
                       image.max_value());
  };
  if (sixteen) {
    decode(stbi_load_16_from_memory(data, length, &image.width, &image.height, &channels, 0));
  } else {
    decode(stbi_load_from_memory(data, length, &image.width, &image.height, &channels, 0));
  }
  return image;
}

ColorImage read_color_png(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    refuse(ErrorCategory::kFile, source,
           "no such file: check the path of the texture image (a PNG)");
  }
  const std::string bytes = read_file_text(path, "texture PNG", [&](std::uintmax_t size) {
    if (size > kMaxFileBytes) {
      refuse(ErrorCategory::kResource, source,
             fmt::format("{} bytes is too large for a texture PNG; scale the image down to at "
                         "most 8192 x 8192 pixels",
                         size));
    }
  });
  return read_color_png_bytes(bytes, source);
}

}  // namespace flatmorph
