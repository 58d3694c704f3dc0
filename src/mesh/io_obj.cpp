// Wavefront OBJ: only `v` and `f` statements matter for a surface; everything else is ignored.
#include <fmt/core.h>

#include <algorithm>
#include <climits>

#include "common/atomic_file.h"
#include "mesh/io_internal.h"

namespace flatmorph {
namespace mesh_io {
namespace {

// A face that names a vertex defined further down. OBJ only allows this in practice for positive
// indices, and whether it is valid is known only at the end of the file.
struct ForwardReference {
  long long line;
  long long index;
  long long faces_before;
};

}  // namespace

MeshFile read_obj(std::string_view bytes, const std::string& name) {
  std::vector<double> xyz;
  std::vector<int> triangles;
  std::vector<int> polygon;
  std::vector<ForwardReference> forward;
  LineScanner scanner{bytes};
  std::string_view line;
  while (next_line(scanner, line)) {
    std::string_view rest = line;
    std::string_view keyword;
    if (!next_token(rest, keyword)) continue;
    const bool is_vertex = keyword == "v";
    if (!is_vertex && keyword != "f") continue;
    const long long num_vertices = static_cast<long long>(xyz.size() / 3);
    const long long num_faces = static_cast<long long>(triangles.size() / 3);
    const Progress progress{num_vertices, num_faces};
    const long long line_number = scanner.line_number;
    std::string_view token;
    if (is_vertex) {
      // Extra numbers after z (w, or a colour) are tolerated and ignored.
      for (int k = 0; k < 3; ++k) {
        if (!next_token(rest, token) || token[0] == '#') {
          fail_at_line(name, line_number,
                       fmt::format("a vertex needs three coordinates (`v x y z`), this one has {}; "
                                   "fix or re-export the mesh",
                                   k),
                       progress);
        }
        double value;
        if (!parse_double(token, value)) {
          fail_at_line(name, line_number,
                       fmt::format("{} is not a number; vertex coordinates must be numbers, fix or "
                                   "re-export the mesh",
                                   quote(token)),
                       progress);
        }
        xyz.push_back(value);
      }
      if (num_vertices + 1 > INT_MAX) {
        fail_at_line(name, line_number, "more vertices than flatmorph can hold; simplify the mesh",
                     progress);
      }
      continue;
    }

    polygon.clear();
    long long max_index = 0;
    while (next_token(rest, token) && token[0] != '#') {
      // v, v/vt, v//vn, v/vt/vn: only the vertex index matters.
      const std::string_view index_text = token.substr(0, token.find('/'));
      long long index;
      if (!parse_integer(index_text, index)) {
        fail_at_line(name, line_number,
                     fmt::format("{} is not a vertex index; face entries must be whole numbers "
                                 "(`f 1 2 3` or `f 1/1/1 2/2/2 3/3/3`), fix or re-export the mesh",
                                 quote(token)),
                     progress);
      }
      if (index == 0) {
        fail_at_line(name, line_number,
                     "a face uses vertex index 0, but OBJ indices start at 1 (or count back from "
                     "-1); fix or re-export the mesh",
                     progress);
      }
      if (index < 0) {
        if (-index > num_vertices) {
          fail_at_line(name, line_number,
                       fmt::format("face refers to vertex {} (counting back) but only {} vertices "
                                   "come before this line; fix or re-export the mesh",
                                   index, num_vertices),
                       progress);
        }
        index += num_vertices;
      } else {
        if (index > INT_MAX) {
          fail_at_line(name, line_number,
                       fmt::format("face refers to vertex {}, more than flatmorph can hold; fix "
                                   "or re-export the mesh",
                                   index),
                       progress);
        }
        max_index = std::max(max_index, index);
        index -= 1;
      }
      polygon.push_back(static_cast<int>(index));
    }
    if (polygon.size() < 3) {
      fail_at_line(name, line_number,
                   fmt::format("a face needs at least 3 vertices, this one has {}; remove it or "
                               "re-export the mesh",
                               polygon.size()),
                   progress);
    }
    if (max_index > num_vertices) forward.push_back({line_number, max_index, num_faces});
    if (num_faces + static_cast<long long>(polygon.size()) - 2 > INT_MAX) {
      fail_at_line(name, line_number, "more faces than flatmorph can hold; simplify the mesh",
                   progress);
    }
    // Fan triangulation keeps the polygon's orientation in every triangle.
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
      triangles.insert(triangles.end(), {polygon[0], polygon[i], polygon[i + 1]});
    }
  }

  const long long num_vertices = static_cast<long long>(xyz.size() / 3);
  for (const ForwardReference& ref : forward) {
    if (ref.index > num_vertices) {
      fail_at_line(name, ref.line,
                   fmt::format("face refers to vertex {} but the file defines {} vertices; fix or "
                               "re-export the mesh",
                               ref.index, num_vertices),
                   {num_vertices, ref.faces_before});
    }
  }
  if (num_vertices == 0 && triangles.empty()) {
    fail(name,
         "the file has no vertex (`v`) or face (`f`) lines; it is not an OBJ mesh, export it "
         "again",
         {});
  }
  return {make_mesh(xyz, triangles), {}};
}

}  // namespace mesh_io

void write_obj(const std::filesystem::path& path, const Mesh& mesh) {
  mesh_io::check_mesh_for_writing(mesh, "write_obj");
  std::string out = "# flatmorph\n";
  out.reserve(out.size() + static_cast<std::size_t>(mesh.V.rows()) * 64 +
              static_cast<std::size_t>(mesh.F.rows()) * 24);
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      mesh_io::append_double(out, mesh.V(i, k));
    }
    out += '\n';
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    fmt::format_to(std::back_inserter(out), "f {} {} {}\n", mesh.F(f, 0) + 1, mesh.F(f, 1) + 1,
                   mesh.F(f, 2) + 1);
  }
  write_file_atomically(path, true, [&](std::ostream& stream) {
    stream.write(out.data(), static_cast<std::streamsize>(out.size()));
  });
}

}  // namespace flatmorph
