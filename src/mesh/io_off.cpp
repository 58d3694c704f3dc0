// Object File Format (Geomview OFF): a header keyword, a counts line, vertex lines, face lines.
#include <fmt/core.h>

#include <climits>

#include "mesh/io_internal.h"

namespace flatmorph::mesh_io {
namespace {

// The smallest text a vertex ("0 0 0\n") and a face ("3 0 1 2\n") can take: bounds what counts a
// file of a given size can really hold.
constexpr unsigned long long kMinVertexBytes = 6;
constexpr unsigned long long kMinFaceBytes = 8;

// The next line that holds something once its `#` comment is removed; false at the end.
bool next_content_line(LineScanner& scanner, std::string_view& content) {
  std::string_view line;
  while (next_line(scanner, line)) {
    line = line.substr(0, line.find('#'));
    std::string_view probe = line;
    std::string_view token;
    if (next_token(probe, token)) {
      content = line;
      return true;
    }
  }
  return false;
}

// Geomview's header keyword is [ST][C][N][4][n]OFF; the extra per-vertex values that S, T, C and N
// announce come after x y z and are ignored, 4 and n change the dimension and are not supported.
bool is_supported_prefix(std::string_view prefix) {
  for (const char letter : {'S', 'T', 'C', 'N'}) {
    if (!prefix.empty() && prefix[0] == letter) prefix.remove_prefix(1);
  }
  return prefix.empty();
}

}  // namespace

MeshFile read_off(std::string_view bytes, const std::string& name) {
  LineScanner scanner{bytes};
  std::string_view rest;
  std::string_view token;
  if (!next_content_line(scanner, rest)) {
    fail(name, "the file holds only comments and blank lines; export the mesh again", {});
  }
  std::string_view counts_line = rest;
  next_token(rest, token);
  if (token.size() >= 3 && token.substr(token.size() - 3) == "OFF") {
    const std::string_view prefix = token.substr(0, token.size() - 3);
    if (!is_supported_prefix(prefix)) {
      fail_at_line(name, scanner.line_number,
                   fmt::format("{} OFF files are not supported (only 3D vertices); export a plain "
                               "OFF file",
                               quote(token)),
                   {});
    }
    std::string_view probe = rest;
    if (next_token(probe, token) && token == "BINARY") {
      fail_at_line(name, scanner.line_number,
                   "binary OFF files are not supported; export an ASCII OFF file", {});
    }
    // Some writers put the counts on the header line itself.
    counts_line = rest;
    probe = rest;
    if (!next_token(probe, token) && !next_content_line(scanner, counts_line)) {
      fail(name, "the file ends after the OFF keyword; the file is truncated, export it again", {});
    }
  } else if (token[0] < '0' || token[0] > '9') {
    fail_at_line(name, scanner.line_number,
                 fmt::format("the file starts with {} instead of OFF; it is not an OFF file, "
                             "check its format",
                             quote(token)),
                 {});
  }

  const long long counts_line_number = scanner.line_number;
  unsigned long long counts[2];
  for (unsigned long long& count : counts) {
    if (!next_token(counts_line, token) || !parse_unsigned(token, count)) {
      fail_at_line(name, counts_line_number,
                   "expected the counts line `vertices faces edges` (whole numbers); fix or "
                   "re-export the mesh",
                   {});
    }
  }
  const unsigned long long num_vertices = counts[0];
  const unsigned long long num_faces = counts[1];
  // Compare the counts with what the rest of the file can hold before reserving anything.
  const unsigned long long remaining = bytes.size() - scanner.position;
  if (num_vertices > remaining || num_faces > remaining ||
      num_vertices * kMinVertexBytes + num_faces * kMinFaceBytes > remaining + 1) {
    fail_at_line(name, counts_line_number,
                 fmt::format("the header announces {} vertices and {} faces, more than the {} "
                             "bytes that follow can hold; the file is truncated or its header is "
                             "wrong, export it again",
                             num_vertices, num_faces, remaining),
                 {});
  }
  if (num_vertices > INT_MAX || num_faces > INT_MAX) {
    fail_at_line(name, counts_line_number, "more vertices or faces than flatmorph can hold", {});
  }

  std::vector<double> xyz;
  xyz.reserve(3 * num_vertices);
  for (unsigned long long i = 0; i < num_vertices; ++i) {
    const Progress progress{static_cast<long long>(i), 0};
    if (!next_content_line(scanner, rest)) {
      fail(name,
           fmt::format("the header announces {} vertices but the data ends after {}; the file is "
                       "truncated, export it again",
                       num_vertices, i),
           progress);
    }
    // Colours or normals after x y z (COFF, NOFF) are ignored.
    for (int k = 0; k < 3; ++k) {
      double value;
      if (!next_token(rest, token)) {
        fail_at_line(name, scanner.line_number,
                     fmt::format("a vertex needs three coordinates, this one has {}; fix or "
                                 "re-export the mesh",
                                 k),
                     progress);
      }
      if (!parse_double(token, value)) {
        fail_at_line(name, scanner.line_number,
                     fmt::format("{} is not a number; vertex coordinates must be numbers, fix or "
                                 "re-export the mesh",
                                 quote(token)),
                     progress);
      }
      xyz.push_back(value);
    }
  }

  std::vector<int> triangles;
  triangles.reserve(3 * num_faces);
  std::vector<int> polygon;
  for (unsigned long long i = 0; i < num_faces; ++i) {
    const Progress progress{static_cast<long long>(num_vertices),
                            static_cast<long long>(triangles.size() / 3)};
    if (!next_content_line(scanner, rest)) {
      fail(name,
           fmt::format("the header announces {} faces but the data ends after {}; the file is "
                       "truncated, export it again",
                       num_faces, i),
           progress);
    }
    unsigned long long size;
    next_token(rest, token);
    if (!parse_unsigned(token, size)) {
      fail_at_line(name, scanner.line_number,
                   fmt::format("{} is not a vertex count; a face line is `n i1 ... in`, fix or "
                               "re-export the mesh",
                               quote(token)),
                   progress);
    }
    if (size < 3) {
      fail_at_line(name, scanner.line_number,
                   fmt::format("a face needs at least 3 vertices, this one has {}; remove it or "
                               "re-export the mesh",
                               size),
                   progress);
    }
    polygon.clear();
    for (unsigned long long k = 0; k < size; ++k) {
      if (!next_token(rest, token)) {
        fail_at_line(name, scanner.line_number,
                     fmt::format("the face announces {} vertices but lists {}; fix or re-export "
                                 "the mesh",
                                 size, k),
                     progress);
      }
      long long index;
      if (!parse_integer(token, index)) {
        fail_at_line(
            name, scanner.line_number,
            fmt::format("{} is not a vertex index; fix or re-export the mesh", quote(token)),
            progress);
      }
      if (index < 0 || static_cast<unsigned long long>(index) >= num_vertices) {
        fail_at_line(name, scanner.line_number,
                     fmt::format("face refers to vertex {} but the file defines {} vertices "
                                 "(numbered from 0); fix or re-export the mesh",
                                 index, num_vertices),
                     progress);
      }
      polygon.push_back(static_cast<int>(index));
    }
    // A colour may follow the indices; it is ignored.
    if (triangles.size() / 3 + polygon.size() - 2 > static_cast<std::size_t>(INT_MAX)) {
      fail_at_line(name, scanner.line_number, "more faces than flatmorph can hold", progress);
    }
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      triangles.insert(triangles.end(), {polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  return {make_mesh(xyz, triangles), {}};
}

}  // namespace flatmorph::mesh_io
