#include "raster/raster.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace flatmorph {

void Canvas::blend(int x, int y, const Rgb& c, double coverage) {
  if (x < 0 || y < 0 || x >= width || y >= height || coverage <= 0) return;
  unsigned char* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
  for (int k = 0; k < 3; ++k) {
    p[k] = static_cast<unsigned char>(std::lround(p[k] + (c[k] - p[k]) * std::min(1.0, coverage)));
  }
}

void Canvas::segment(Eigen::Vector2d a, Eigen::Vector2d b, double half, const Rgb& c,
                     const Eigen::Vector4i& clip) {
  const int x0 = std::max(clip[0], static_cast<int>(std::floor(std::min(a.x(), b.x()) - half - 1)));
  const int x1 = std::min(clip[2], static_cast<int>(std::ceil(std::max(a.x(), b.x()) + half + 1)));
  const int y0 = std::max(clip[1], static_cast<int>(std::floor(std::min(a.y(), b.y()) - half - 1)));
  const int y1 = std::min(clip[3], static_cast<int>(std::ceil(std::max(a.y(), b.y()) + half + 1)));
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      const double dist = (p - (a + t * d)).norm();
      blend(x, y, c, half + 0.5 - dist);
    }
  }
}

void Canvas::rect(int x0, int y0, int x1, int y1, const Rgb& c) {
  for (int y = std::max(0, y0); y < std::min(height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(width, x1); ++x) blend(x, y, c, 1);
  }
}

void Canvas::triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                      const Eigen::Vector3d& p2, const Eigen::Vector3d& c0,
                      const Eigen::Vector3d& c1, const Eigen::Vector3d& c2) {
  if (depth.empty()) depth.assign(static_cast<size_t>(width) * height, INFINITY);
  const double area = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p2.x() - p0.x()) * (p1.y() - p0.y());
  if (!(std::abs(area) > 1e-12)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p0.x(), p1.x(), p2.x()}))));
  const int x1 =
      std::min(width - 1, static_cast<int>(std::ceil(std::max({p0.x(), p1.x(), p2.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p0.y(), p1.y(), p2.y()}))));
  const int y1 =
      std::min(height - 1, static_cast<int>(std::ceil(std::max({p0.y(), p1.y(), p2.y()}))));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      // Barycentric weights; the sign of `area` makes both orientations work.
      const double w0 = ((p1.x() - px) * (p2.y() - py) - (p2.x() - px) * (p1.y() - py)) / area;
      const double w1 = ((p2.x() - px) * (p0.y() - py) - (p0.x() - px) * (p2.y() - py)) / area;
      const double w2 = 1 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      const double z = w0 * p0.z() + w1 * p1.z() + w2 * p2.z();
      float& d = depth[static_cast<size_t>(y) * width + x];
      if (!(z < d)) continue;
      d = static_cast<float>(z);
      const Eigen::Vector3d c = w0 * c0 + w1 * c1 + w2 * c2;
      unsigned char* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
      for (int k = 0; k < 3; ++k) {
        p[k] = static_cast<unsigned char>(std::lround(255 * std::clamp(c[k], 0.0, 1.0)));
      }
    }
  }
}

Canvas downsampled(const Canvas& canvas, int factor) {
  Canvas out(canvas.width / factor, canvas.height / factor);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int k = 0; k < 3; ++k) {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy) {
          for (int dx = 0; dx < factor; ++dx) {
            sum +=
                canvas
                    .rgb[(static_cast<size_t>(y * factor + dy) * canvas.width + (x * factor + dx)) *
                             3 +
                         k];
          }
        }
        out.rgb[(static_cast<size_t>(y) * out.width + x) * 3 + k] =
            static_cast<unsigned char>((sum + factor * factor / 2) / (factor * factor));
      }
    }
  }
  return out;
}

namespace {

// Glyphs of a 3 x 5 pixel font, one row per 3 bits (top row first).
unsigned short glyph(char ch) {
  static constexpr unsigned short kDigits[10] = {075557, 026227, 071747, 071717, 055711,
                                                 074717, 074757, 071111, 075757, 075717};
  if (ch >= '0' && ch <= '9') return kDigits[ch - '0'];
  switch (ch) {
    case '.':
      return 000002;
    case '-':
      return 000700;
    case '%':
      return 051245;
    default:
      return 0;
  }
}

}  // namespace

int text_width(std::string_view text, int scale) {
  return text.empty() ? 0 : static_cast<int>(text.size()) * 4 * scale - scale;
}

int draw_text(Canvas& canvas, int x, int y, std::string_view text, int scale, const Rgb& c) {
  for (size_t d = 0; d < text.size(); ++d) {
    const unsigned short g = glyph(text[d]);
    for (int row = 0; row < 5; ++row) {
      for (int col = 0; col < 3; ++col) {
        if (g >> ((4 - row) * 3 + (2 - col)) & 1) {
          const int px = x + static_cast<int>(d) * 4 * scale + col * scale;
          const int py = y + row * scale;
          canvas.rect(px, py, px + scale, py + scale, c);
        }
      }
    }
  }
  return text_width(text, scale);
}

Eigen::Vector3d viridis(double t) {
  static const double kStops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  const double s = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4;
  const int i = std::min(3, static_cast<int>(s));
  const double f = s - i;
  Eigen::Vector3d c;
  for (int k = 0; k < 3; ++k) c[k] = (kStops[i][k] * (1 - f) + kStops[i + 1][k] * f) / 255;
  return c;
}

Rgb to_rgb(const Eigen::Vector3d& c) {
  Rgb out;
  for (int k = 0; k < 3; ++k) {
    out[k] = static_cast<unsigned char>(std::lround(255 * std::clamp(c[k], 0.0, 1.0)));
  }
  return out;
}

Rgb order_color(size_t index, size_t count) {
  const double t = count > 1 ? static_cast<double>(index) / static_cast<double>(count - 1) : 0.0;
  static const double kStops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  const double s = t * 4;
  const int i = std::min(3, static_cast<int>(s));
  const double f = s - i;
  Rgb c;
  for (int k = 0; k < 3; ++k) {
    c[k] = static_cast<unsigned char>(std::lround(kStops[i][k] * (1 - f) + kStops[i + 1][k] * f));
  }
  return c;
}

Eigen::Vector3d cyclic_color(double t) {
  const double a = 2 * std::numbers::pi * (std::isfinite(t) ? t : 0.0);
  return {0.5 + 0.42 * std::cos(a), 0.5 + 0.42 * std::cos(a - 2 * std::numbers::pi / 3),
          0.5 + 0.42 * std::cos(a - 4 * std::numbers::pi / 3)};
}

Eigen::Vector3d diverging_color(double t) {
  const Eigen::Vector3d blue(59 / 255.0, 76 / 255.0, 192 / 255.0);
  const Eigen::Vector3d white(242 / 255.0, 242 / 255.0, 242 / 255.0);
  const Eigen::Vector3d red(180 / 255.0, 4 / 255.0, 38 / 255.0);
  const double s = std::clamp(std::isfinite(t) ? t : 0.0, -1.0, 1.0);
  return s < 0 ? Eigen::Vector3d(white + (blue - white) * -s)
               : Eigen::Vector3d(white + (red - white) * s);
}

namespace {

void append_chunk(std::vector<unsigned char>& png, const char* type,
                  const std::vector<unsigned char>& data) {
  auto be32 = [&png](uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) png.push_back(static_cast<unsigned char>(v >> s));
  };
  be32(static_cast<uint32_t>(data.size()));
  const size_t start = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  be32(static_cast<uint32_t>(crc32(0, png.data() + start, static_cast<uInt>(png.size() - start))));
}

}  // namespace

std::vector<unsigned char> encode_png(const Canvas& canvas) {
  std::vector<unsigned char> raw;
  raw.reserve(static_cast<size_t>(canvas.height) * (canvas.width * 3 + 1));
  for (int y = 0; y < canvas.height; ++y) {
    raw.push_back(0);  // filter type None
    const auto row = canvas.rgb.begin() + static_cast<std::ptrdiff_t>(y) * canvas.width * 3;
    raw.insert(raw.end(), row, row + canvas.width * 3);
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<unsigned char> compressed(size);
  if (compress2(compressed.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK) {
    throw std::runtime_error("PNG: zlib compression failed");
  }
  compressed.resize(size);

  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<unsigned char> ihdr;
  for (uint32_t v : {static_cast<uint32_t>(canvas.width), static_cast<uint32_t>(canvas.height)}) {
    for (int s = 24; s >= 0; s -= 8) ihdr.push_back(static_cast<unsigned char>(v >> s));
  }
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, no filter, no interlace
  append_chunk(png, "IHDR", ihdr);
  append_chunk(png, "IDAT", compressed);
  append_chunk(png, "IEND", {});
  return png;
}

}  // namespace flatmorph
