#include "methods/heightfield/color_image.h"

#include <fmt/core.h>

#include <algorithm>
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

using png_bytes::kMaxFileBytes;
using png_bytes::StbFree;

constexpr const char* kExportAgain = "export the texture again as an 8- or 16-bit PNG";

// Coordinates this close outside [0, 1] are float rounding of an edge, not a repeat.
constexpr double kUvEdgeTolerance = 1e-6;

[[noreturn]] void refuse(ErrorCategory category, const std::string& source,
                         const std::string& problem) {
  throw UserError(category, fmt::format("{}: {}", source, problem));
}

constexpr png_bytes::PngAdvice kTextureAdvice = {
    .what = "texture",
    .if_empty = kExportAgain,
    .if_not_png =
        "flatmorph reads textures as PNG only; convert the image (e.g. `convert "
        "texture.jpg texture.png`)",
    .if_zero_size = kExportAgain,
    .if_too_large = "scale the texture down",
    .if_damaged = kExportAgain};

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
  png_bytes::check_png_structure(bytes, source, kTextureAdvice);
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
