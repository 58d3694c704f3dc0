// STL, ASCII and binary: a soup of triangles, welded here into an indexed mesh.
#include <fmt/core.h>

#include <bit>
#include <climits>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "mesh/io_internal.h"

namespace flatmorph::mesh_io {
namespace {

constexpr std::size_t kBinaryHeaderBytes = 84;    // 80-byte comment + uint32 triangle count
constexpr std::size_t kBinaryTriangleBytes = 50;  // normal, 3 corners, uint16 attribute

struct CornerKey {
  std::uint64_t bits[3];
  bool operator==(const CornerKey& other) const {
    return bits[0] == other.bits[0] && bits[1] == other.bits[1] && bits[2] == other.bits[2];
  }
};

struct CornerHash {
  std::size_t operator()(const CornerKey& key) const {
    // splitmix64 finalizer: the raw bits of nearby coordinates differ only in a few low bits.
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::uint64_t b : key.bits) {
      std::uint64_t z = b + h;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
      h ^= z ^ (z >> 31);
      h *= 0x9e3779b97f4a7c15ull;
    }
    return static_cast<std::size_t>(h);
  }
};

// Corners that are bitwise equal become one vertex, numbered in order of first appearance.
// -0 and +0 are the same point, so -0 is folded to +0 first.
struct Welder {
  std::unordered_map<CornerKey, int, CornerHash> index_of;
  std::vector<double> xyz;
  std::vector<int> triangles;
};

int weld(Welder& welder, const double (&corner)[3]) {
  CornerKey key;
  for (int k = 0; k < 3; ++k) {
    const double value = corner[k] == 0.0 ? 0.0 : corner[k];
    key.bits[k] = std::bit_cast<std::uint64_t>(value);
  }
  const auto [it, inserted] =
      welder.index_of.try_emplace(key, static_cast<int>(welder.xyz.size() / 3));
  if (inserted) welder.xyz.insert(welder.xyz.end(), {corner[0], corner[1], corner[2]});
  return it->second;
}

Progress progress_of(const Welder& welder) {
  return {static_cast<long long>(welder.xyz.size() / 3),
          static_cast<long long>(welder.triangles.size() / 3)};
}

std::uint32_t read_u32_le(const char* p) {
  unsigned char b[4];
  std::memcpy(b, p, 4);
  return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
         static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const char x = (a[i] >= 'A' && a[i] <= 'Z') ? static_cast<char>(a[i] - 'A' + 'a') : a[i];
    if (x != b[i]) return false;
  }
  return true;
}

// ASCII STL starts with "solid" and, unlike binary, never holds a zero byte. Binary files whose
// 80-byte comment also starts with "solid" are common, so the word alone decides nothing.
bool looks_like_ascii(std::string_view bytes) {
  std::string_view rest = bytes;
  std::string_view first;
  if (!next_token(rest, first)) return false;
  const bool starts_with_solid =
      first.size() >= 5 && equals_ignoring_case(first.substr(0, 5), "solid");
  return starts_with_solid && std::memchr(bytes.data(), 0, bytes.size()) == nullptr;
}

MeshFile read_binary_stl(std::string_view bytes, const std::string& name,
                         std::uint64_t num_triangles) {
  if (num_triangles > INT_MAX) fail(name, "more triangles than flatmorph can hold", {});
  Welder welder;
  welder.index_of.reserve(static_cast<std::size_t>(num_triangles / 2 + 1));
  welder.xyz.reserve(static_cast<std::size_t>(num_triangles * 3 / 2 + 3));
  welder.triangles.reserve(static_cast<std::size_t>(num_triangles * 3));
  for (std::uint64_t t = 0; t < num_triangles; ++t) {
    // Skip the stored normal: the corner order defines the orientation.
    const char* corners = bytes.data() + kBinaryHeaderBytes + t * kBinaryTriangleBytes + 12;
    for (int c = 0; c < 3; ++c) {
      double corner[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = std::bit_cast<float>(read_u32_le(corners + 12 * c + 4 * k));
      }
      welder.triangles.push_back(weld(welder, corner));
    }
  }
  return {make_mesh(welder.xyz, welder.triangles), {}};
}

MeshFile read_ascii_stl(std::string_view bytes, const std::string& name) {
  Welder welder;
  std::vector<int> polygon;
  bool in_facet = false;
  long long facet_line = 0;
  LineScanner scanner{bytes};
  std::string_view line;
  while (next_line(scanner, line)) {
    std::string_view rest = line;
    std::string_view keyword;
    if (!next_token(rest, keyword)) continue;
    const long long line_number = scanner.line_number;
    if (equals_ignoring_case(keyword, "solid") || equals_ignoring_case(keyword, "endsolid") ||
        equals_ignoring_case(keyword, "outer") || equals_ignoring_case(keyword, "endloop")) {
      continue;
    }
    if (equals_ignoring_case(keyword, "facet")) {
      if (in_facet) {
        fail_at_line(name, line_number,
                     "a facet starts before the previous one has its `endfacet`; the file is "
                     "corrupted, export it again",
                     progress_of(welder));
      }
      in_facet = true;
      facet_line = line_number;
      polygon.clear();
    } else if (equals_ignoring_case(keyword, "vertex")) {
      if (!in_facet) {
        fail_at_line(name, line_number,
                     "`vertex` outside a facet; the file is corrupted, export it again",
                     progress_of(welder));
      }
      double corner[3];
      for (int k = 0; k < 3; ++k) {
        std::string_view token;
        if (!next_token(rest, token)) {
          fail_at_line(name, line_number,
                       fmt::format("a vertex needs three coordinates, this one has {}; export "
                                   "the file again",
                                   k),
                       progress_of(welder));
        }
        if (!parse_double(token, corner[k])) {
          fail_at_line(name, line_number,
                       fmt::format("{} is not a number; vertex coordinates must be numbers, "
                                   "export the file again",
                                   quote(token)),
                       progress_of(welder));
        }
      }
      polygon.push_back(weld(welder, corner));
    } else if (equals_ignoring_case(keyword, "endfacet")) {
      if (!in_facet) {
        fail_at_line(name, line_number,
                     "`endfacet` without a `facet`; the file is corrupted, export it again",
                     progress_of(welder));
      }
      if (polygon.size() < 3) {
        fail_at_line(name, facet_line,
                     fmt::format("a facet needs 3 vertices, this one has {}; export the file "
                                 "again",
                                 polygon.size()),
                     progress_of(welder));
      }
      if (welder.triangles.size() / 3 + polygon.size() - 2 > static_cast<std::size_t>(INT_MAX)) {
        fail_at_line(name, line_number, "more triangles than flatmorph can hold",
                     progress_of(welder));
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        welder.triangles.insert(welder.triangles.end(), {polygon[0], polygon[k], polygon[k + 1]});
      }
      in_facet = false;
    } else {
      fail_at_line(name, line_number,
                   fmt::format("unexpected {}; an ASCII STL holds only solid, facet, outer loop, "
                               "vertex, endloop, endfacet and endsolid lines, export it again",
                               quote(keyword)),
                   progress_of(welder));
    }
  }
  if (in_facet) {
    fail(name,
         fmt::format("the file ends inside the facet that starts on line {}; the file is "
                     "truncated, export it again",
                     facet_line),
         progress_of(welder));
  }
  return {make_mesh(welder.xyz, welder.triangles), {}};
}

}  // namespace

MeshFile read_stl(std::string_view bytes, const std::string& name) {
  // Binary when the announced count explains the size exactly, whatever the comment says.
  std::uint64_t num_triangles = 0;
  std::uint64_t expected_size = 0;
  if (bytes.size() >= kBinaryHeaderBytes) {
    num_triangles = read_u32_le(bytes.data() + 80);
    expected_size = kBinaryHeaderBytes + kBinaryTriangleBytes * num_triangles;
    if (expected_size == bytes.size()) return read_binary_stl(bytes, name, num_triangles);
  }
  if (looks_like_ascii(bytes)) return read_ascii_stl(bytes, name);
  if (bytes.size() < kBinaryHeaderBytes) {
    fail(name,
         fmt::format("the file has {} bytes, too few for a binary STL (84 at least), and does not "
                     "start with `solid` like an ASCII STL; it is not an STL file, export it again",
                     bytes.size()),
         {});
  }
  fail(name,
       fmt::format("binary STL header announces {} triangles ({} bytes) but the file has {} bytes; "
                   "{}, export it again",
                   num_triangles, expected_size, bytes.size(),
                   expected_size > bytes.size() ? "the file is truncated"
                                                : "the file is corrupted or has trailing data"),
       {});
}

}  // namespace flatmorph::mesh_io
