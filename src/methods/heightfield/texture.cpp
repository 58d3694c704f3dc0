#include "methods/heightfield/texture.h"

#include <fmt/core.h>
#include <zlib.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/file_text.h"
#include "mesh/io.h"
#include "mesh/io_internal.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

// with_colors: samples this close (relative to their bounding-box diagonal) to a field vertex are
// its colour. height_field_from_mesh welds at 1e-9 of the diagonal; distinct vertices of a real
// mesh are never this close.
constexpr double kMatchRelative = 1e-6;
// colors_at: how far outside the footprint (relative to its xy diagonal) a point may lie.
constexpr double kOutsideRelative = 1e-4;
// colors_at: a barycentric weight this far below 0 is rounding, the point is on the face.
constexpr double kInsideWeight = 1e-9;
constexpr double kMaxDpi = 2400.0;

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string read_text_file(const std::filesystem::path& path, const std::string& what) {
  const std::string source = path.string();
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: no such file: check the path of the {}", source, what));
  }
  return read_file_text(path, what);
}

// The start of a file, enough for any PLY header (read_mesh has read the whole file already).
std::string read_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(1 << 20, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}

Eigen::Vector2d row2(const Eigen::MatrixXd& M, int v) { return Eigen::Vector2d(M(v, 0), M(v, 1)); }
Eigen::Vector3d row3(const Eigen::MatrixXd& M, int v) {
  return Eigen::Vector3d(M(v, 0), M(v, 1), M(v, 2));
}

double area_3d(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = row3(X, F(f, 0));
  return 0.5 * (row3(X, F(f, 1)) - a).cross(row3(X, F(f, 2)) - a).norm();
}

double area_2d(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, int f) {
  return std::abs(triangle_signed_area(row2(X, F(f, 0)), row2(X, F(f, 1)), row2(X, F(f, 2))));
}

// ---------------------------------------------------------------------------------------------
// PLY colours

// The declared type of each scalar property of the `vertex` element, from the PLY header.
std::map<std::string, std::string> ply_vertex_property_types(const std::string& bytes) {
  std::map<std::string, std::string> types;
  mesh_io::LineScanner scanner{bytes};
  std::string_view line;
  bool in_vertex = false;
  while (mesh_io::next_line(scanner, line)) {
    std::string_view rest = line, word, type, name;
    if (!mesh_io::next_token(rest, word)) continue;
    if (word == "end_header") break;
    if (word == "element") {
      in_vertex = mesh_io::next_token(rest, name) && name == "vertex";
    } else if (word == "property" && in_vertex && mesh_io::next_token(rest, type) &&
               type != "list" && mesh_io::next_token(rest, name)) {
      types[std::string(name)] = std::string(type);
    }
  }
  return types;
}

// What a colour property of this type is divided by to lie in [0, 1].
double color_scale(const std::string& type) {
  if (type == "float" || type == "float32" || type == "double" || type == "float64") return 1.0;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 65535.0;
  return 255.0;  // 8-bit types, and 32-bit integers that writers fill with 0-255
}

// with_colors: a cell of the grid of samples.
using CellKey = std::array<long long, 3>;

// ---------------------------------------------------------------------------------------------
// Point location over the field's xy projection (colors_at)

struct FaceGrid {
  Eigen::Vector2d origin;
  double cell = 1.0;
  int nx = 1, ny = 1;
  std::vector<int> start;  // CSR: faces of cell c are faces[start[c] .. start[c + 1])
  std::vector<int> faces;

  // Clamped before the conversion, so that a point far away is no overflow.
  int cell_x(double x) const {
    return static_cast<int>(std::clamp(std::floor((x - origin.x()) / cell), 0.0, nx - 1.0));
  }
  int cell_y(double y) const {
    return static_cast<int>(std::clamp(std::floor((y - origin.y()) / cell), 0.0, ny - 1.0));
  }
};

// Faces registered in every cell their xy bounding box, padded by `pad`, overlaps.
FaceGrid build_face_grid(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double pad) {
  FaceGrid grid;
  const Eigen::Vector2d lo = V.leftCols<2>().colwise().minCoeff().transpose().array() - pad;
  const Eigen::Vector2d hi = V.leftCols<2>().colwise().maxCoeff().transpose().array() + pad;
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-12);
  grid.origin = lo;
  // About one face per cell.
  grid.cell = std::sqrt(size.x() * size.y() / std::max<Eigen::Index>(F.rows(), 1));
  grid.nx = std::clamp(static_cast<int>(std::ceil(size.x() / grid.cell)), 1, 4096);
  grid.ny = std::clamp(static_cast<int>(std::ceil(size.y() / grid.cell)), 1, 4096);
  grid.cell = std::max(size.x() / grid.nx, size.y() / grid.ny);
  auto range = [&](int f, int& x0, int& x1, int& y0, int& y1) {
    double ax = V(F(f, 0), 0), bx = ax, ay = V(F(f, 0), 1), by = ay;
    for (int k = 1; k < 3; ++k) {
      ax = std::min(ax, V(F(f, k), 0));
      bx = std::max(bx, V(F(f, k), 0));
      ay = std::min(ay, V(F(f, k), 1));
      by = std::max(by, V(F(f, k), 1));
    }
    x0 = grid.cell_x(ax - pad);
    x1 = grid.cell_x(bx + pad);
    y0 = grid.cell_y(ay - pad);
    y1 = grid.cell_y(by + pad);
  };
  std::vector<int> count(static_cast<size_t>(grid.nx) * grid.ny + 1, 0);
  for (int f = 0; f < F.rows(); ++f) {
    int x0, x1, y0, y1;
    range(f, x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) ++count[static_cast<size_t>(y) * grid.nx + x + 1];
    }
  }
  for (size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  grid.start = count;
  grid.faces.resize(static_cast<size_t>(count.back()));
  for (int f = 0; f < F.rows(); ++f) {
    int x0, x1, y0, y1;
    range(f, x0, x1, y0, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) grid.faces[count[static_cast<size_t>(y) * grid.nx + x]++] = f;
    }
  }
  return grid;
}

// ---------------------------------------------------------------------------------------------
// Rasterizing the plate

// Vertex positions in pixel units (x right, y down) over a placement.
Eigen::MatrixX2d to_pixels(const RasterPlacement& placement, const Eigen::MatrixXd& plate) {
  Eigen::MatrixX2d P(plate.rows(), 2);
  for (Eigen::Index v = 0; v < plate.rows(); ++v) {
    P(v, 0) = (plate(v, 0) - placement.left_mm) / placement.pixel_mm;
    P(v, 1) = (placement.top_mm - plate(v, 1)) / placement.pixel_mm;
  }
  return P;
}

// Calls visit(f, x, y, w) for every pixel (x, y) whose centre lies in face f of the plate, w the
// barycentric weights of F(f, 0..2). Each edge's side test is evaluated with its two vertices in
// index order, so that the two faces sharing an edge compute the same number with opposite
// meaning; a centre exactly on the edge goes to the face on the left of the edge so ordered. Hence
// a pixel centre on a shared edge is drawn once, not twice or never.
template <typename Visit>
void rasterize(const RasterPlacement& placement, const Eigen::MatrixXd& plate,
               const Eigen::MatrixXi& F, Visit&& visit) {
  const Eigen::MatrixX2d P = to_pixels(placement, plate);
  for (int f = 0; f < F.rows(); ++f) {
    // Edge k is opposite corner k.
    std::array<int, 3> lo, hi;
    std::array<double, 3> sign;
    bool degenerate = false;
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      lo[k] = std::min(a, b);
      hi[k] = std::max(a, b);
      const int c = F(f, k);
      const double side = (P(hi[k], 0) - P(lo[k], 0)) * (P(c, 1) - P(lo[k], 1)) -
                          (P(hi[k], 1) - P(lo[k], 1)) * (P(c, 0) - P(lo[k], 0));
      if (!(side != 0.0) || !std::isfinite(side)) degenerate = true;
      sign[k] = side > 0.0 ? 1.0 : -1.0;
    }
    if (degenerate) continue;
    double x_min = P(F(f, 0), 0), x_max = x_min, y_min = P(F(f, 0), 1), y_max = y_min;
    for (int k = 1; k < 3; ++k) {
      x_min = std::min(x_min, P(F(f, k), 0));
      x_max = std::max(x_max, P(F(f, k), 0));
      y_min = std::min(y_min, P(F(f, k), 1));
      y_max = std::max(y_max, P(F(f, k), 1));
    }
    // Pixels whose centre (x + 0.5) lies in [min, max], clamped to the image before the
    // conversion to int (a plate far larger than the image is no overflow).
    const auto first = [](double lo, int n) {
      return static_cast<int>(std::clamp(std::ceil(lo - 0.5), 0.0, static_cast<double>(n)));
    };
    const auto last = [](double hi, int n) {
      return static_cast<int>(std::clamp(std::floor(hi - 0.5), -1.0, n - 1.0));
    };
    const int x0 = first(x_min, placement.width), x1 = last(x_max, placement.width);
    const int y0 = first(y_min, placement.height), y1 = last(y_max, placement.height);
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        Eigen::Vector3d w;
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const double e = (P(hi[k], 0) - P(lo[k], 0)) * (py - P(lo[k], 1)) -
                           (P(hi[k], 1) - P(lo[k], 1)) * (px - P(lo[k], 0));
          w[k] = sign[k] * e;
          inside = w[k] > 0.0 || (w[k] == 0.0 && sign[k] > 0.0);
        }
        if (!inside) continue;
        const double sum = w.sum();
        if (!(sum > 0.0)) continue;
        visit(f, x, y, Eigen::Vector3d(w / sum));
      }
    }
  }
}

void check_sheet(const char* who, const Eigen::MatrixXd& plate, const Eigen::MatrixXd& shape,
                 const Eigen::MatrixXi& F) {
  if (plate.cols() < 2 || shape.cols() != 3 || plate.rows() != shape.rows() || F.cols() != 3 ||
      plate.rows() == 0 || F.rows() == 0) {
    throw std::invalid_argument(fmt::format(
        "{}: plate must be #V x 2, the shape #V x 3 and F #F x 3, none empty (got "
        "{} x {}, {} x {}, {} x {})",
        who, plate.rows(), plate.cols(), shape.rows(), shape.cols(), F.rows(), F.cols()));
  }
  if (F.minCoeff() < 0 || F.maxCoeff() >= plate.rows()) {
    throw std::invalid_argument(fmt::format("{}: a face index is out of range", who));
  }
  if (!plate.leftCols<2>().allFinite() || !shape.allFinite()) {
    throw std::invalid_argument(fmt::format("{}: a coordinate is not finite", who));
  }
}

Canvas draw_marks(Canvas canvas, const RasterPlacement& placement,
                  const std::vector<Eigen::Vector2d>& marks) {
  const double half_line = 0.5 * std::max(kMarkLineMm, placement.pixel_mm);
  const double reach = kMarkArmMm + half_line;
  const double p = placement.pixel_mm;
  for (const Eigen::Vector2d& c : marks) {
    const int x0 =
        std::max(0, static_cast<int>(std::floor((c.x() - reach - placement.left_mm) / p)));
    const int x1 = std::min(canvas.width - 1,
                            static_cast<int>(std::ceil((c.x() + reach - placement.left_mm) / p)));
    const int y0 =
        std::max(0, static_cast<int>(std::floor((placement.top_mm - c.y() - reach) / p)));
    const int y1 = std::min(canvas.height - 1,
                            static_cast<int>(std::ceil((placement.top_mm - c.y() + reach) / p)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d d = placement.pixel_center(x, y) - c;
        const bool ring = std::abs(d.norm() - kMarkRadiusMm) <= half_line;
        const bool cross = (std::abs(d.x()) <= half_line && std::abs(d.y()) <= kMarkArmMm) ||
                           (std::abs(d.y()) <= half_line && std::abs(d.x()) <= kMarkArmMm);
        if (!ring && !cross) continue;
        unsigned char* px = &canvas.rgb[(static_cast<size_t>(y) * canvas.width + x) * 3];
        px[0] = px[1] = px[2] = 0;
      }
    }
  }
  return canvas;
}

// ---------------------------------------------------------------------------------------------
// Checkerboard

using Square = std::pair<int, int>;

Square square_of(double x, double y, double s) {
  return {static_cast<int>(std::floor(x / s)), static_cast<int>(std::floor(y / s))};
}

// Area of the part of triangle abc (xy) inside the rectangle [x0, x1] x [y0, y1]
// (Sutherland-Hodgman against its four sides, then the shoelace formula).
double clipped_area(const std::array<Eigen::Vector2d, 3>& triangle, double x0, double x1, double y0,
                    double y1) {
  std::vector<Eigen::Vector2d> polygon(triangle.begin(), triangle.end()), next;
  // Side k keeps the points with keep(p) >= 0.
  auto clip = [&](auto keep) {
    next.clear();
    for (size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d& a = polygon[i];
      const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
      const double ka = keep(a), kb = keep(b);
      if (ka >= 0.0) next.push_back(a);
      if ((ka >= 0.0) != (kb >= 0.0)) next.push_back(a + (b - a) * (ka / (ka - kb)));
    }
    polygon.swap(next);
  };
  clip([&](const Eigen::Vector2d& p) { return p.x() - x0; });
  clip([&](const Eigen::Vector2d& p) { return x1 - p.x(); });
  clip([&](const Eigen::Vector2d& p) { return p.y() - y0; });
  clip([&](const Eigen::Vector2d& p) { return y1 - p.y(); });
  return std::abs(signed_area(polygon));
}

// Area on the target surface of every square of side s that it touches.
std::map<Square, double> all_square_areas(const Eigen::MatrixXd& target, const Eigen::MatrixXi& F,
                                          double s) {
  std::map<Square, double> areas;
  for (int f = 0; f < F.rows(); ++f) {
    const double xy_area = area_2d(target, F, f);
    if (!(xy_area > 0.0)) continue;
    const double ratio = area_3d(target, F, f) / xy_area;
    const std::array<Eigen::Vector2d, 3> t = {row2(target, F(f, 0)), row2(target, F(f, 1)),
                                              row2(target, F(f, 2))};
    const Square lo = square_of(std::min({t[0].x(), t[1].x(), t[2].x()}),
                                std::min({t[0].y(), t[1].y(), t[2].y()}), s);
    const Square hi = square_of(std::max({t[0].x(), t[1].x(), t[2].x()}),
                                std::max({t[0].y(), t[1].y(), t[2].y()}), s);
    for (int i = lo.first; i <= hi.first; ++i) {
      for (int j = lo.second; j <= hi.second; ++j) {
        const double a = clipped_area(t, i * s, (i + 1) * s, j * s, (j + 1) * s);
        if (a > 0.0) areas[{i, j}] += a * ratio;
      }
    }
  }
  return areas;
}

// A positive square size that numbers the target's squares within int (at most a million across).
void check_square(double square_mm, const Eigen::MatrixXd& target) {
  if (!(std::isfinite(square_mm) && square_mm > 0.0)) {
    throw std::invalid_argument("checkerboard: the square size must be a positive number of mm");
  }
  const double reach = target.leftCols<2>().cwiseAbs().maxCoeff();
  if (!(reach / square_mm < 1e6)) {
    throw std::invalid_argument("checkerboard: squares too small for the target's size");
  }
}

}  // namespace

// -----------------------------------------------------------------------------------------------
// Colour input

ColorSamples read_ply_vertex_colors(const std::filesystem::path& ply) {
  const std::string source = ply.string();
  const MeshFile file = read_mesh(ply);
  const auto types = ply_vertex_property_types(read_header(ply));
  ColorSamples samples;
  samples.points = file.mesh.V;
  samples.colors.resize(file.mesh.num_vertices(), 3);
  for (const std::string prefix : {"", "diffuse_"}) {
    const std::array<std::string, 3> names = {prefix + "red", prefix + "green", prefix + "blue"};
    std::array<const Eigen::VectorXd*, 3> channels{};
    for (int k = 0; k < 3; ++k) channels[k] = file.properties.find_vertex(names[k]);
    if (!channels[0] || !channels[1] || !channels[2]) continue;
    for (int k = 0; k < 3; ++k) {
      const auto type = types.find(names[k]);
      const double scale = color_scale(type == types.end() ? "uchar" : type->second);
      for (int v = 0; v < samples.colors.rows(); ++v) {
        const double c = (*channels[k])[v] / scale;
        if (!(c >= -1e-9 && c <= 1.0 + 1e-9)) {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: vertex {} at ({:.3f}, {:.3f}, {:.3f}) has {} = {}, "
                                      "outside 0..{} for its type {}: fix the colours or "
                                      "re-export them",
                                      source, v, file.mesh.V(v, 0), file.mesh.V(v, 1),
                                      file.mesh.V(v, 2), names[k], (*channels[k])[v], scale,
                                      type == types.end() ? "?" : type->second));
        }
        samples.colors(v, k) = std::clamp(c, 0.0, 1.0);
      }
    }
    return samples;
  }
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("{}: the PLY has no vertex colours (vertex properties red, green, "
                              "blue): export it with vertex colours, or give an OBJ with texture "
                              "coordinates and its texture PNG",
                              source));
}

ColorSamples read_obj_texture_colors(const std::filesystem::path& obj, const ColorImage& image) {
  using mesh_io::fail_at_line;
  using mesh_io::quote;
  const std::string name = obj.string();
  const std::string bytes = read_text_file(obj, "OBJ");
  std::vector<double> xyz, uv;
  // Per face corner: vertex, texture coordinate (0-based; -1 when the corner has none).
  std::vector<std::pair<long long, long long>> corners;
  std::vector<long long> corner_line;  // the line of each corner, for messages
  long long first_corner_without_uv = 0;
  mesh_io::LineScanner scanner{bytes};
  std::string_view line;
  while (mesh_io::next_line(scanner, line)) {
    std::string_view rest = line, keyword, token;
    if (!mesh_io::next_token(rest, keyword)) continue;
    const long long line_number = scanner.line_number;
    const mesh_io::Progress progress{static_cast<long long>(xyz.size() / 3), 0};
    if (keyword == "v" || keyword == "vt") {
      const bool is_vertex = keyword == "v";
      const int needed = is_vertex ? 3 : 1;
      double values[3] = {0.0, 0.0, 0.0};
      for (int k = 0; k < (is_vertex ? 3 : 2); ++k) {
        if (!mesh_io::next_token(rest, token) || token[0] == '#') {
          if (k < needed) {
            fail_at_line(name, line_number,
                         is_vertex ? "a vertex needs three coordinates (`v x y z`); fix or "
                                     "re-export the mesh"
                                   : "a texture coordinate needs at least u (`vt u v`); fix or "
                                     "re-export the mesh",
                         progress);
          }
          break;
        }
        if (!mesh_io::parse_double(token, values[k]) || !std::isfinite(values[k])) {
          fail_at_line(
              name, line_number,
              fmt::format("{} is not a finite number; fix or re-export the mesh", quote(token)),
              progress);
        }
      }
      auto& out = is_vertex ? xyz : uv;
      out.insert(out.end(), values, values + (is_vertex ? 3 : 2));
      continue;
    }
    if (keyword != "f") continue;
    int count = 0;
    while (mesh_io::next_token(rest, token) && token[0] != '#') {
      // v, v/vt, v//vn, v/vt/vn.
      const size_t slash = token.find('/');
      const std::string_view v_text = token.substr(0, slash);
      std::string_view vt_text;
      if (slash != std::string_view::npos) {
        vt_text = token.substr(slash + 1);
        vt_text = vt_text.substr(0, vt_text.find('/'));
      }
      const long long counts[2] = {static_cast<long long>(xyz.size() / 3),
                                   static_cast<long long>(uv.size() / 2)};
      long long index[2] = {0, -1};
      const std::string_view texts[2] = {v_text, vt_text};
      for (int k = 0; k < 2; ++k) {
        if (k == 1 && vt_text.empty()) break;
        long long i;
        if (!mesh_io::parse_integer(texts[k], i) || i == 0 || (i < 0 && -i > counts[k])) {
          fail_at_line(name, line_number,
                       fmt::format("{} is not a valid {} index in a face; fix or re-export the "
                                   "mesh",
                                   quote(token), k == 0 ? "vertex" : "texture coordinate"),
                       progress);
        }
        // Negative indices count back from the last one defined; positive ones may refer ahead
        // and are checked at the end.
        index[k] = i < 0 ? i + counts[k] : i - 1;
      }
      if (index[1] < 0 && first_corner_without_uv == 0) first_corner_without_uv = line_number;
      corners.emplace_back(index[0], index[1]);
      corner_line.push_back(line_number);
      ++count;
    }
    if (count < 3) {
      fail_at_line(name, line_number, "a face needs at least 3 vertices; fix or re-export the mesh",
                   progress);
    }
  }
  if (uv.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no texture coordinates (`vt` lines): export the OBJ with its "
                                "UVs (texture coordinates), or give a PLY with vertex colours",
                                name));
  }
  if (first_corner_without_uv != 0) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}:{}: a face corner has no texture coordinate (`f v ...` or "
                                "`f v//vn ...`): every face needs UVs (`f v/vt ...`); export the "
                                "OBJ with UVs on the whole surface",
                                name, first_corner_without_uv));
  }
  const long long num_vertices = static_cast<long long>(xyz.size() / 3);
  const long long num_uvs = static_cast<long long>(uv.size() / 2);
  for (size_t c = 0; c < corners.size(); ++c) {
    if (corners[c].first >= num_vertices || corners[c].second >= num_uvs) {
      fail_at_line(
          name, corner_line[c],
          fmt::format("a face refers to {} {}, but the file has only {}; fix or "
                      "re-export the mesh",
                      corners[c].first >= num_vertices ? "vertex" : "texture coordinate",
                      (corners[c].first >= num_vertices ? corners[c].first : corners[c].second) + 1,
                      corners[c].first >= num_vertices ? num_vertices : num_uvs),
          {num_vertices, 0});
    }
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  ColorSamples samples;
  samples.points.resize(static_cast<Eigen::Index>(corners.size()), 3);
  samples.colors.resize(static_cast<Eigen::Index>(corners.size()), 3);
  for (size_t c = 0; c < corners.size(); ++c) {
    const auto [v, t] = corners[c];
    const auto row = static_cast<Eigen::Index>(c);
    for (int k = 0; k < 3; ++k) samples.points(row, k) = xyz[static_cast<size_t>(v) * 3 + k];
    samples.colors.row(row) =
        sample_bilinear(image, uv[static_cast<size_t>(t) * 2], uv[static_cast<size_t>(t) * 2 + 1])
            .transpose();
  }
  return samples;
}

HeightField with_colors(HeightField field, const ColorSamples& samples, const std::string& source) {
  const Eigen::MatrixXd& S = samples.points;
  if (S.cols() != 3 || samples.colors.cols() != 3 || samples.colors.rows() != S.rows()) {
    throw std::invalid_argument("with_colors: points and colours must both be #S x 3");
  }
  if (field.V.rows() > 0 && S.rows() == 0) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: no coloured vertices: give the mesh the height field was "
                                "made from, with its colours",
                                source));
  }
  Eigen::MatrixXd colors(field.V.rows(), 3);
  if (field.V.rows() == 0) {
    field.colors = colors;
    return field;
  }
  const Eigen::Vector3d lo = S.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = S.colwise().maxCoeff().transpose();
  const double tolerance = kMatchRelative * (hi - lo).norm();
  // Cells of side `cell` (>= tolerance) hold the samples; a vertex looks in the 27 around its own.
  const double cell = tolerance > 0.0 ? tolerance : 1.0;
  auto key = [&](const Eigen::Vector3d& p) {
    CellKey k;
    for (int a = 0; a < 3; ++a) k[a] = static_cast<long long>(std::floor((p[a] - lo[a]) / cell));
    return k;
  };
  std::vector<std::pair<CellKey, int>> cells;
  cells.reserve(static_cast<size_t>(S.rows()));
  for (int s = 0; s < S.rows(); ++s) cells.emplace_back(key(row3(S, s)), s);
  std::sort(cells.begin(), cells.end());
  for (int v = 0; v < field.V.rows(); ++v) {
    const Eigen::Vector3d p = row3(field.V, v);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    const bool near_box = ((p - lo).array() >= -tolerance).all() &&
                          ((p - hi).array() <= tolerance).all() && p.allFinite();
    if (near_box) {
      const CellKey k = key(p);
      // Samples in index order within and across cells, so that the mean's rounding is fixed.
      std::vector<int> found;
      for (long long dx = -1; dx <= 1; ++dx) {
        for (long long dy = -1; dy <= 1; ++dy) {
          for (long long dz = -1; dz <= 1; ++dz) {
            const CellKey n = {k[0] + dx, k[1] + dy, k[2] + dz};
            auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(n, -1));
            for (; it != cells.end() && it->first == n; ++it) {
              if ((row3(S, it->second) - p).norm() <= tolerance) found.push_back(it->second);
            }
          }
        }
      }
      std::sort(found.begin(), found.end());
      for (int s : found) sum += samples.colors.row(s).transpose();
      count = static_cast<int>(found.size());
    }
    if (count == 0) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: the height field's vertex at ({:.4f}, {:.4f}, {:.4f}) has "
                                  "no colour there (no coloured vertex within {:.2g}): the "
                                  "colours must come from the mesh the height field was made "
                                  "from, at the same scale",
                                  source, p.x(), p.y(), p.z(), tolerance));
    }
    colors.row(v) = (sum / count).transpose();
  }
  field.colors = std::move(colors);
  return field;
}

HeightField with_texture(HeightField field, const std::filesystem::path& mesh,
                         const std::filesystem::path& image) {
  const std::string ext = lower_extension(mesh);
  const std::string source = mesh.string();
  if (ext == ".ply") {
    if (!image.empty()) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: a PLY carries its colours per vertex, so the texture image "
                                  "{} is not used: drop the image, or give an OBJ with texture "
                                  "coordinates",
                                  source, image.string()));
    }
    return with_colors(std::move(field), read_ply_vertex_colors(mesh), source);
  }
  if (ext == ".obj") {
    if (image.empty()) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: an OBJ's colours come from a texture image: give the "
                                  "texture PNG its texture coordinates refer to",
                                  source));
    }
    return with_colors(std::move(field), read_obj_texture_colors(mesh, read_color_png(image)),
                       source);
  }
  throw UserError(ErrorCategory::kOption,
                  fmt::format("{}: colours come from a PLY with vertex colours or an OBJ with "
                              "texture coordinates and a PNG; a {} file carries none: convert "
                              "the coloured model to PLY or OBJ",
                              source, ext.empty() ? "extensionless" : ext));
}

Eigen::MatrixXd colors_at(const HeightField& field, const Eigen::MatrixXd& points_xy) {
  const Eigen::MatrixXd& V = field.V;
  const Eigen::MatrixXi& F = field.F;
  if (field.colors.rows() != V.rows() || field.colors.cols() != 3 || V.rows() == 0 ||
      F.rows() == 0) {
    throw std::invalid_argument("colors_at: the field has no colours (or no faces)");
  }
  if (points_xy.cols() < 2) throw std::invalid_argument("colors_at: points must be #P x 2");
  const Eigen::Vector2d lo = V.leftCols<2>().colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = V.leftCols<2>().colwise().maxCoeff().transpose();
  const double tolerance = kOutsideRelative * (hi - lo).norm();
  const FaceGrid grid = build_face_grid(V, F, tolerance);
  Eigen::MatrixXd colors(points_xy.rows(), 3);
  for (Eigen::Index i = 0; i < points_xy.rows(); ++i) {
    const Eigen::Vector2d p(points_xy(i, 0), points_xy(i, 1));
    if (!p.allFinite()) {
      throw std::invalid_argument(fmt::format("colors_at: point {} is not finite", i));
    }
    const int c = grid.cell_y(p.y()) * grid.nx + grid.cell_x(p.x());
    // The face containing p (the one it lies deepest in), else the nearest one.
    int best_face = -1;
    double best_inside = -std::numeric_limits<double>::infinity();
    Eigen::Vector3d best_w = Eigen::Vector3d::Zero();
    int near_face = -1;
    double near_distance = std::numeric_limits<double>::infinity();
    Eigen::Vector3d near_w = Eigen::Vector3d::Zero();
    for (int at = grid.start[c]; at < grid.start[c + 1]; ++at) {
      const int f = grid.faces[at];
      const std::array<Eigen::Vector2d, 3> t = {row2(V, F(f, 0)), row2(V, F(f, 1)),
                                                row2(V, F(f, 2))};
      const double area2 = cross2(t[1] - t[0], t[2] - t[0]);
      if (!(std::abs(area2) > 0.0)) continue;
      Eigen::Vector3d w;
      for (int k = 0; k < 3; ++k) {
        w[k] = cross2(t[(k + 1) % 3] - p, t[(k + 2) % 3] - p) / area2;
      }
      if (w.minCoeff() > best_inside) {
        best_inside = w.minCoeff();
        best_face = f;
        best_w = w;
      }
      if (w.minCoeff() >= -kInsideWeight) continue;
      for (int k = 0; k < 3; ++k) {
        double s = 0.0;
        const double d = segment_distance(p, t[(k + 1) % 3], t[(k + 2) % 3], s);
        if (d < near_distance) {
          near_distance = d;
          near_face = f;
          near_w = Eigen::Vector3d::Zero();
          near_w[(k + 1) % 3] = 1.0 - s;
          near_w[(k + 2) % 3] = s;
        }
      }
    }
    int face = -1;
    Eigen::Vector3d w;
    if (best_face >= 0 && best_inside >= -kInsideWeight) {
      face = best_face;
      w = best_w.cwiseMax(0.0);
      w /= w.sum();
    } else if (near_face >= 0 && near_distance <= tolerance) {
      face = near_face;
      w = near_w;
    } else {
      throw std::invalid_argument(
          fmt::format("colors_at: point ({:.4f}, {:.4f}) mm lies outside the height field's "
                      "footprint (by more than {:.2g} mm)",
                      p.x(), p.y(), tolerance));
    }
    colors.row(i).setZero();
    for (int k = 0; k < 3; ++k) colors.row(i) += w[k] * field.colors.row(F(face, k));
  }
  return colors;
}

// -----------------------------------------------------------------------------------------------
// Screen print

ScreenPrint render_screen_print(const Eigen::MatrixXd& plate, const Eigen::MatrixXd& target,
                                const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors,
                                const ScreenPrintOptions& options) {
  check_sheet("render_screen_print", plate, target, F);
  if (colors.rows() != plate.rows() || colors.cols() != 3) {
    throw std::invalid_argument("render_screen_print: colours must be #V x 3");
  }
  if (!colors.allFinite() || colors.minCoeff() < 0.0 || colors.maxCoeff() > 1.0) {
    throw std::invalid_argument("render_screen_print: colours must lie in [0, 1]");
  }
  if (!(std::isfinite(options.dpi) && options.dpi > 0.0 && options.dpi <= kMaxDpi)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("screen print: {} dpi is not a print resolution: give one "
                                "between 1 and {} (300 is usual for screen-print film)",
                                options.dpi, kMaxDpi));
  }
  if (!(std::isfinite(options.margin_mm) && options.margin_mm >= 0.0)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("screen print: the margin must be 0 mm or more, not {}", options.margin_mm));
  }
  if (options.registration_marks && options.margin_mm < kMarkReachMm) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("screen print: a {} mm margin cannot hold the registration marks, "
                                "which reach {} mm beyond the sheet: give a margin of at least {} "
                                "mm, or turn the marks off",
                                options.margin_mm, kMarkReachMm, kMarkReachMm));
  }
  ScreenPrint print;
  print.dpi = options.dpi;
  const double p = 25.4 / options.dpi;
  const Eigen::Vector2d lo = plate.leftCols<2>().colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = plate.leftCols<2>().colwise().maxCoeff().transpose();
  const double width = std::ceil((hi.x() - lo.x() + 2.0 * options.margin_mm) / p);
  const double height = std::ceil((hi.y() - lo.y() + 2.0 * options.margin_mm) / p);
  if (std::max(width, 1.0) * std::max(height, 1.0) > static_cast<double>(kMaxGrayImagePixels)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("screen print: {:.0f} x {:.0f} mm at {} dpi would be {:.0f} x "
                    "{:.0f} pixels, more than flatmorph writes (8192 x 8192 in all): "
                    "lower the dpi",
                    hi.x() - lo.x() + 2.0 * options.margin_mm,
                    hi.y() - lo.y() + 2.0 * options.margin_mm, options.dpi, width, height));
  }
  RasterPlacement& placement = print.placement;
  placement.left_mm = lo.x() - options.margin_mm;
  placement.top_mm = hi.y() + options.margin_mm;
  placement.pixel_mm = p;
  placement.width = std::max(1, static_cast<int>(width));
  placement.height = std::max(1, static_cast<int>(height));

  // Paper §6.5: opacity a_t / a_f per face, clamped to what ink can do.
  print.opacity.resize(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const double flat = area_2d(plate, F, f);
    const double ratio = flat > 0.0 ? area_3d(target, F, f) / flat : 1.0;
    print.opacity[f] = std::clamp(std::isfinite(ratio) ? ratio : 1.0, 0.0, 1.0);
  }

  Canvas canvas(placement.width, placement.height);
  rasterize(placement, plate, F, [&](int f, int x, int y, const Eigen::Vector3d& w) {
    const double alpha = print.opacity[f];
    unsigned char* px = &canvas.rgb[(static_cast<size_t>(y) * canvas.width + x) * 3];
    for (int k = 0; k < 3; ++k) {
      const double c =
          w[0] * colors(F(f, 0), k) + w[1] * colors(F(f, 1), k) + w[2] * colors(F(f, 2), k);
      const double ink = 1.0 - alpha * (1.0 - std::clamp(c, 0.0, 1.0));
      px[k] = static_cast<unsigned char>(std::lround(255.0 * ink));
    }
  });
  if (options.registration_marks) {
    const double offset = kMarkGapMm + kMarkArmMm;
    print.marks = {Eigen::Vector2d(lo.x() - offset, hi.y() + offset),
                   Eigen::Vector2d(hi.x() + offset, hi.y() + offset),
                   Eigen::Vector2d(lo.x() - offset, lo.y() - offset)};
    canvas = draw_marks(std::move(canvas), placement, print.marks);
  }
  print.image = std::move(canvas);
  return print;
}

std::vector<unsigned char> screen_print_png(const ScreenPrint& print) {
  std::vector<unsigned char> png = encode_png(print.image);
  // pHYs (PNG 1.2 §4.2.4.2) must come before the image data: right after IHDR, which is always
  // the first chunk (8 bytes of signature, then 4 + 4 + 13 + 4 bytes).
  constexpr size_t kAfterIhdr = 8 + 4 + 4 + 13 + 4;
  const auto per_metre = static_cast<uint32_t>(std::lround(print.dpi / 0.0254));
  std::vector<unsigned char> chunk;
  auto be32 = [&chunk](uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) chunk.push_back(static_cast<unsigned char>(v >> s));
  };
  be32(9);
  for (const char c : {'p', 'H', 'Y', 's'}) chunk.push_back(static_cast<unsigned char>(c));
  be32(per_metre);
  be32(per_metre);
  chunk.push_back(1);  // unit: the metre
  be32(static_cast<uint32_t>(crc32(0, chunk.data() + 4, static_cast<uInt>(chunk.size() - 4))));
  png.insert(png.begin() + kAfterIhdr, chunk.begin(), chunk.end());
  return png;
}

void write_screen_print_png(const std::filesystem::path& path, const ScreenPrint& print) {
  const std::vector<unsigned char> png = screen_print_png(print);
  write_file_atomically(path, true, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

// -----------------------------------------------------------------------------------------------
// Checkerboard acceptance

SquareLabels checkerboard_labels(const RasterPlacement& placement, const Eigen::MatrixXd& plate,
                                 const Eigen::MatrixXd& target, const Eigen::MatrixXi& F,
                                 double square_mm) {
  check_sheet("checkerboard_labels", plate, target, F);
  check_square(square_mm, target);
  SquareLabels result;
  result.placement = placement;
  const size_t pixels = static_cast<size_t>(placement.width) * placement.height;
  constexpr Square kNone = {INT_MIN, INT_MIN};
  std::vector<Square> square(pixels, kNone);
  rasterize(placement, plate, F, [&](int f, int x, int y, const Eigen::Vector3d& w) {
    Eigen::Vector2d t = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k) t += w[k] * row2(target, F(f, k));
    square[static_cast<size_t>(y) * placement.width + x] = square_of(t.x(), t.y(), square_mm);
  });
  std::vector<Square> sorted;
  for (const Square& s : square) {
    if (s != kNone) sorted.push_back(s);
  }
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  for (const Square& s : sorted) result.squares.emplace_back(s.first, s.second);
  result.labels.assign(pixels, -1);
  for (size_t i = 0; i < pixels; ++i) {
    if (square[i] == kNone) continue;
    result.labels[i] = static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), square[i]) -
                                        sorted.begin());
  }
  return result;
}

Eigen::VectorXd risen_label_areas(const SquareLabels& labels, const Eigen::MatrixXd& plate,
                                  const Eigen::MatrixXd& risen, const Eigen::MatrixXi& F) {
  check_sheet("risen_label_areas", plate, risen, F);
  const RasterPlacement& placement = labels.placement;
  if (labels.labels.size() != static_cast<size_t>(placement.width) * placement.height) {
    throw std::invalid_argument("risen_label_areas: labels do not match the placement");
  }
  Eigen::VectorXd ratio(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const double flat = area_2d(plate, F, f);
    ratio[f] = flat > 0.0 ? area_3d(risen, F, f) / flat : 0.0;
  }
  Eigen::VectorXd areas = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(labels.squares.size()));
  const double pixel_area = placement.pixel_mm * placement.pixel_mm;
  rasterize(placement, plate, F, [&](int f, int x, int y, const Eigen::Vector3d&) {
    const int label = labels.labels[static_cast<size_t>(y) * placement.width + x];
    if (label >= 0) areas[label] += pixel_area * ratio[f];
  });
  return areas;
}

Eigen::VectorXd target_square_areas(const Eigen::MatrixXd& target, const Eigen::MatrixXi& F,
                                    double square_mm, const std::vector<Eigen::Vector2i>& squares) {
  check_sheet("target_square_areas", target, target, F);
  check_square(square_mm, target);
  const std::map<Square, double> all = all_square_areas(target, F, square_mm);
  Eigen::VectorXd areas(static_cast<Eigen::Index>(squares.size()));
  for (size_t i = 0; i < squares.size(); ++i) {
    const auto it = all.find({squares[i].x(), squares[i].y()});
    areas[static_cast<Eigen::Index>(i)] = it == all.end() ? 0.0 : it->second;
  }
  return areas;
}

CheckerboardCheck check_checkerboard(const SquareLabels& labels, const Eigen::MatrixXd& plate,
                                     const Eigen::MatrixXd& target, const Eigen::MatrixXd& risen,
                                     const Eigen::MatrixXi& F, double square_mm,
                                     double min_fraction) {
  check_sheet("check_checkerboard", plate, target, F);
  check_square(square_mm, target);
  const Eigen::VectorXd risen_areas = risen_label_areas(labels, plate, risen, F);
  CheckerboardCheck check;
  for (const auto& [square, area] : all_square_areas(target, F, square_mm)) {
    if (area < min_fraction * square_mm * square_mm) continue;
    const Eigen::Vector2i key(square.first, square.second);
    const auto it =
        std::lower_bound(labels.squares.begin(), labels.squares.end(), key,
                         [](const Eigen::Vector2i& a, const Eigen::Vector2i& b) {
                           return std::make_pair(a.x(), a.y()) < std::make_pair(b.x(), b.y());
                         });
    const bool found = it != labels.squares.end() && *it == key;
    const double risen_area = found ? risen_areas[it - labels.squares.begin()] : 0.0;
    const double error = std::abs(risen_area - area) / area;
    ++check.squares_compared;
    if (check.squares_compared == 1 || error > check.worst_relative_error) {
      check.worst_relative_error = error;
      check.worst_square = key;
      check.worst_target_mm2 = area;
      check.worst_risen_mm2 = risen_area;
    }
  }
  return check;
}

}  // namespace flatmorph
