// A small software rasterizer for the pictures flatmorph writes (G-code layer previews, report
// pictures): an RGB canvas with anti-aliased segments, filled triangles with per-vertex colours and
// a depth buffer, a tiny digit font, colour maps, and a PNG encoder (zlib). Pixel coordinates: x
// right, y down, pixel centres at +0.5. The bytes depend only on the input.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

namespace flatmorph {

using Rgb = std::array<unsigned char, 3>;

struct Canvas {
  int width;
  int height;
  std::vector<unsigned char> rgb;  // row-major, 3 bytes per pixel
  std::vector<float> depth;        // per pixel, smaller is nearer; empty until a triangle uses it

  Canvas(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 255) {}

  // Mixes colour c into pixel (x, y) with weight `coverage` (clamped to [0, 1]).
  void blend(int x, int y, const Rgb& c, double coverage);

  // An anti-aliased segment of width 2 * half (pixels), with round ends, clipped to the box
  // clip = (x0, y0, x1, y1) (x1, y1 exclusive).
  void segment(Eigen::Vector2d a, Eigen::Vector2d b, double half, const Rgb& c,
               const Eigen::Vector4i& clip);

  void rect(int x0, int y0, int x1, int y1, const Rgb& c);

  // A filled triangle (x, y in pixels, z the depth) with colours interpolated from its corners;
  // pixels whose centre lies inside are drawn where the depth test passes (no anti-aliasing:
  // draw at a multiple of the size and `downsampled` for smooth edges).
  void triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                const Eigen::Vector3d& c0, const Eigen::Vector3d& c1, const Eigen::Vector3d& c2);
};

// The canvas shrunk by an integer factor (box filter): anti-aliasing for triangles.
Canvas downsampled(const Canvas& canvas, int factor);

// Text of digits, '.', '-', ' ' and '%' in a 3 x 5 pixel font magnified `scale` times; (x, y) is
// the top-left corner. Returns the width drawn, pixels.
int draw_text(Canvas& canvas, int x, int y, std::string_view text, int scale, const Rgb& c);
// Width `draw_text` would draw.
int text_width(std::string_view text, int scale);

// Print order as colour: a viridis-like ramp (dark blue, teal, green, yellow), readable in grey.
Rgb order_color(size_t index, size_t count);
// The same ramp at t in [0, 1] (clamped), channels in [0, 1].
Eigen::Vector3d viridis(double t);
// A cyclic map of period 1 (t and t + 1 give the same colour), channels in [0, 1]: for line
// directions, t = theta / pi.
Eigen::Vector3d cyclic_color(double t);
// A diverging map: blue at t = -1, white at 0, red at +1 (clamped), channels in [0, 1].
Eigen::Vector3d diverging_color(double t);

Rgb to_rgb(const Eigen::Vector3d& c);

// The canvas as a PNG file (RGB, 8 bits, no interlace).
std::vector<unsigned char> encode_png(const Canvas& canvas);

}  // namespace flatmorph
