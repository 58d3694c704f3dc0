// Colour images read from PNG files: the texture of a height field (SCF 2020 §6.5, "Color
// Mapping": the target surface's colours come from an OBJ's texture coordinates into an image).
// An image has no units; texture coordinates (u, v) place it on the surface.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

struct ColorImage {
  int width = 0;   // pixels
  int height = 0;  // pixels
  int bits = 8;    // 8 or 16: the depth of the file's samples
  // Row-major, top row first, 3 samples (R, G, B) per pixel in [0, max_value()].
  std::vector<uint16_t> rgb;

  int max_value() const { return (1 << bits) - 1; }
  // The colour of pixel (x, y) (x right, y down from the top row), channels in [0, 1].
  Eigen::Vector3d at(int x, int y) const;
};

// Reads a PNG as RGB at the file's bit depth: gray (and palette) files become R = G = B (palette
// ones as their RGB), and a transparent pixel is composited on white, c = 1 - a (1 - c) per
// channel, rounded to the file's depth: a texture's transparency is where no ink goes, and the
// printed sheet is white under the ink. The decoder is stb_image's (stb_image_png.cpp), PNG only.
// Throws UserError naming the file: kFile when it cannot be read, kFormat when it is not a PNG
// (a JPEG, say: convert it), is truncated or damaged, or has zero size, kResource when it has
// more than kMaxGrayImagePixels pixels.
ColorImage read_color_png(const std::filesystem::path& path);

// The same from bytes in memory; `source` names them in messages.
ColorImage read_color_png_bytes(std::string_view bytes, const std::string& source);

// The image's colour at texture coordinates (u, v), interpolated bilinearly between the four
// nearest pixels, channels in [0, 1]. Convention (that of OBJ and of every exporter: Blender,
// MeshLab, Rhino): u runs right and v up, the image's corners are pixel centres, so the sample is
// at pixel column x = u (width - 1) and row y = (1 - v) (height - 1); (0, 0) is the bottom-left
// pixel. Coordinates outside [0, 1] repeat the image (u - floor(u)), as an OBJ material does by
// default (MTL `-clamp off`); those within 1e-6 of [0, 1] are clamped instead, so that a 1.0000001
// from a float export stays at the edge. Throws std::invalid_argument for an empty image or a
// non-finite coordinate.
Eigen::Vector3d sample_bilinear(const ColorImage& image, double u, double v);

}  // namespace flatmorph
