// What the two PNG readers (gray_image.cpp: height maps, color_image.cpp: textures) share before
// stb_image decodes: the size limit, the signature, the chunk headers' integers, the decoder's
// buffers. Internal to methods/heightfield/.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
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

// The unsigned 32-bit big-endian integer at byte `at` (the caller checks that 4 bytes are there).
inline uint32_t big_endian_32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

}  // namespace flatmorph::png_bytes
