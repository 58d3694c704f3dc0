// What the two PNG readers (gray_image.cpp: height maps, color_image.cpp: textures) share before
// stb_image decodes: the size limit, the checks of the file's structure, the decoder's buffers.
// Internal to methods/heightfield/.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

// Declarations only: the decoder is compiled once, in stb_image_png.cpp.
#define STBI_NO_STDIO
#include <stb/stb_image.h>

namespace flatmorph::png_bytes {

// A file larger than this cannot be a PNG of at most kMaxGrayImagePixels pixels of 4 channels of
// 16 bits (512 MiB uncompressed, and deflate expands incompressible data by well under 1 %).
inline constexpr std::uintmax_t kMaxFileBytes = 640ULL << 20;

inline constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P',  'N',  'G',
                                                               '\r', '\n', 0x1a, '\n'};

// Frees what stb_image returns (std::unique_ptr's deleter).
struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// How a reader words its refusals: the image's name and the advice after each problem.
struct PngAdvice {
  std::string_view what;          // "height map": "... too large for a height map PNG"
  std::string_view if_empty;      // after "empty file: "
  std::string_view if_not_png;    // after "(it does not start with the PNG signature): "
  std::string_view if_zero_size;  // after "the PNG has zero size (W x H pixels): "
  std::string_view if_too_large;  // after "W x H pixels is more than flatmorph reads (...); "
  std::string_view if_damaged;    // after a chunk past the end or a missing IEND
};

// Refuses (UserError naming `source`) what stb_image must not see: an empty file, no signature, a
// file over INT_MAX bytes, a zero or absurd size in IHDR (checked before anything is allocated for
// it), a chunk claiming more bytes than the file holds (stb_image sizes its buffers by what the
// chunk headers claim, before reading: a few hundred bytes claiming a 2 GB chunk would have it
// allocate 2 GB), or no IEND. After this, what stb_image allocates is bounded by the file's size.
void check_png_structure(std::string_view bytes, const std::string& source,
                         const PngAdvice& advice);

}  // namespace flatmorph::png_bytes
