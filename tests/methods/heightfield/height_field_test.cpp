// Height fields: every input the self-rising method refuses (paper §4, §8) is refused with one line
// naming where, and the mesh and image inputs give the surfaces they describe.
#include "methods/heightfield/height_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>

#include "common/error.h"
#include "mesh/io.h"
#include "mesh/mesh_fixtures.h"
#include "methods/heightfield/png_fixtures.h"
#include "test_support.h"

namespace flatmorph::height_field_test {
namespace {

using testing::grid_mesh;

HeightField from_mesh(const Mesh& mesh) { return HeightField{mesh.V, mesh.F, {}}; }

// The refusal of check_height_field as (category, message); a failed expectation when it accepts.
struct Refusal {
  ErrorCategory category = ErrorCategory::kFile;
  std::string message;
};
Refusal refusal(const HeightField& field) {
  try {
    check_height_field(field, "surface.obj");
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("surface.obj: ", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    return {e.category(), e.what()};
  }
  ADD_FAILURE() << "accepted";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// z = height (1 - X^2)(1 - Y^2) over [-20, 20]^2 mm (X = x / 20): one peak, zero on the boundary,
// 8 x 8 squares of 5 mm.
Mesh hill(double height = 10.0, int n = 8) {
  return grid_mesh(n, n, [&](double u, double v) {
    const double x = 2.0 * u - 1.0, y = 2.0 * v - 1.0;
    return Eigen::Vector3d(20.0 * x, 20.0 * y, height * (1.0 - x * x) * (1.0 - y * y));
  });
}

// The vertex of `mesh` at (x, y), exactly.
int vertex_at(const Mesh& mesh, double x, double y) {
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.V(v, 0) == x && mesh.V(v, 1) == y) return v;
  }
  ADD_FAILURE() << "no vertex at " << x << ", " << y;
  return 0;
}

// The mesh without the faces whose centroid lies in the box [x0, x1] x [y0, y1].
Mesh without_faces_in(const Mesh& mesh, double x0, double x1, double y0, double y1) {
  Mesh out{mesh.V, Eigen::MatrixXi(0, 3)};
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += mesh.V.row(mesh.F(f, k)).transpose() / 3.0;
    if (c.x() > x0 && c.x() < x1 && c.y() > y0 && c.y() < y1) continue;
    out.F.conservativeResize(out.F.rows() + 1, 3);
    out.F.row(out.F.rows() - 1) = mesh.F.row(f);
  }
  return out;
}

// (x, y) of the first "at (x, y) mm" in a message.
Eigen::Vector2d reported_point(const std::string& message) {
  std::smatch m;
  if (!std::regex_search(message, m, std::regex(R"(at \((-?[0-9.]+), (-?[0-9.]+)\) mm)"))) {
    ADD_FAILURE() << "no point in: " << message;
    return Eigen::Vector2d::Zero();
  }
  return Eigen::Vector2d(std::stod(m[1]), std::stod(m[2]));
}

TEST(HeightFieldCheck, AcceptsAHill) {
  EXPECT_NO_THROW(check_height_field(from_mesh(hill()), "hill"));
}

TEST(HeightFieldCheck, AcceptsAFlatBaseAtTheBoundaryHeight) {
  // A round hill of radius 12 mm on a 40 mm square whose corners are flat at z = 0: the flat
  // vertices are as low as the boundary and drain over it, so they are no pit.
  const Mesh mesh = grid_mesh(16, 16, [](double u, double v) {
    const double x = 40.0 * u - 20.0, y = 40.0 * v - 20.0;
    return Eigen::Vector3d(x, y, std::max(0.0, 8.0 * (1.0 - (x * x + y * y) / 144.0)));
  });
  int flat_interior = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    flat_interior +=
        mesh.V(v, 2) == 0.0 && std::abs(mesh.V(v, 0)) < 20 && std::abs(mesh.V(v, 1)) < 20;
  }
  ASSERT_GT(flat_interior, 20);
  EXPECT_NO_THROW(check_height_field(from_mesh(mesh), "base"));
}

TEST(HeightFieldCheck, AcceptsASaddleAndAFlatTop) {
  // z = (x^2 - y^2) / 40: the boundary is not level and the centre is a saddle, not a pit.
  const Mesh saddle = grid_mesh(8, 8, [](double u, double v) {
    const double x = 40.0 * u - 20.0, y = 40.0 * v - 20.0;
    return Eigen::Vector3d(x, y, (x * x - y * y) / 40.0);
  });
  EXPECT_NO_THROW(check_height_field(from_mesh(saddle), "saddle"));
  // A mesa: the hill cut flat at 6 mm.
  Mesh mesa = hill();
  for (int v = 0; v < mesa.num_vertices(); ++v) mesa.V(v, 2) = std::min(mesa.V(v, 2), 6.0);
  EXPECT_NO_THROW(check_height_field(from_mesh(mesa), "mesa"));
}

TEST(HeightFieldCheck, AcceptsClockwiseFaces) {
  // The same surface seen from below is still a graph: only a face against the others is not.
  Mesh mesh = hill();
  mesh.F.col(1).swap(mesh.F.col(2));
  EXPECT_NO_THROW(check_height_field(from_mesh(mesh), "down"));
}

TEST(HeightFieldCheck, RefusesAHoleSayingWhere) {
  // The four faces around (10, -10): a hole bounded by the 8 vertices around that point.
  const Mesh mesh = without_faces_in(hill(), 5.0, 15.0, -15.0, -5.0);
  ASSERT_EQ(mesh.num_faces(), hill().num_faces() - 8);
  const Refusal r = refusal(from_mesh(mesh));
  EXPECT_EQ(r.category, ErrorCategory::kTopology);
  EXPECT_TRUE(contains(r.message, "2 boundary loops: a hole around (10.0, -10.0) mm (8 edges)"))
      << r.message;
  EXPECT_TRUE(contains(r.message, "fill the hole")) << r.message;
}

TEST(HeightFieldCheck, RefusesTwoPiecesSayingWhereTheSecondIs) {
  // Two hills side by side: two outer boundaries.
  const Mesh a = hill();
  Mesh both{Eigen::MatrixXd(2 * a.num_vertices(), 3), Eigen::MatrixXi(2 * a.num_faces(), 3)};
  both.V << a.V, a.V.rowwise() + Eigen::RowVector3d(60.0, 0.0, 0.0);
  both.F << a.F, a.F.array() + a.num_vertices();
  const Refusal r = refusal(from_mesh(both));
  EXPECT_EQ(r.category, ErrorCategory::kTopology);
  EXPECT_TRUE(contains(r.message, "2 separate pieces, the second around (60.0, 0.0) mm"))
      << r.message;
}

TEST(HeightFieldCheck, RefusesAClosedSurfaceSayingWhere) {
  // An octahedron centred on (5, 7, 0).
  Mesh octahedron;
  octahedron.V.resize(6, 3);
  octahedron.V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  octahedron.V = (10.0 * octahedron.V).rowwise() + Eigen::RowVector3d(5.0, 7.0, 0.0);
  octahedron.F.resize(8, 3);
  octahedron.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  const Refusal r = refusal(from_mesh(octahedron));
  EXPECT_EQ(r.category, ErrorCategory::kTopology);
  EXPECT_TRUE(contains(r.message, "a closed surface (no boundary) around (5.0, 7.0) mm"))
      << r.message;
}

TEST(HeightFieldCheck, RefusesAHandle) {
  // A torus (major radius 20, minor 5 mm) with one triangle cut out: one boundary loop, one
  // piece, Euler characteristic 0 - 1 = -1.
  const int nu = 12, nv = 6;
  Mesh torus;
  torus.V.resize(nu * nv, 3);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * std::numbers::pi * i / nu, b = 2 * std::numbers::pi * j / nv;
      torus.V.row(i * nv + j) << (20 + 5 * std::cos(b)) * std::cos(a),
          (20 + 5 * std::cos(b)) * std::sin(a), 5 * std::sin(b);
    }
  }
  torus.F.resize(2 * nu * nv - 1, 3);
  int f = 0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = i * nv + (j + 1) % nv,
                d = ((i + 1) % nu) * nv + (j + 1) % nv;
      torus.F.row(f++) << a, b, d;
      if (f < torus.F.rows()) torus.F.row(f++) << a, d, c;
    }
  }
  const Refusal r = refusal(from_mesh(torus));
  EXPECT_EQ(r.category, ErrorCategory::kTopology);
  EXPECT_TRUE(
      contains(r.message, "not a disk: Euler characteristic -1 (a disk has 1), 1 handle(s)"))
      << r.message;
  EXPECT_TRUE(contains(r.message, "between (-25.0, -25.0) mm and (25.0, 25.0) mm")) << r.message;
}

TEST(HeightFieldCheck, RefusesAFoldNamingTheFirstFoldedFace) {
  // A Z fold along x: columns 0-3 run from x = 0 to 30, columns 3-6 back to 15, 6-9 on to 45,
  // rising 5 mm per column. The middle third lies under the last one seen from above.
  const double xs[] = {0, 10, 20, 30, 25, 20, 15, 25, 35, 45};
  const Mesh fold = grid_mesh(9, 3, [&](double u, double v) {
    const int i = static_cast<int>(std::lround(9 * u));
    return Eigen::Vector3d(xs[i], 20.0 * v, 5.0 * i);
  });
  const Refusal r = refusal(from_mesh(fold));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  // Face 6 is the first of square (3, 0): corners (30, 0), (25, 0), (30, 6.67); z = 15, 20, 15.
  EXPECT_TRUE(contains(r.message,
                       "an overhang (not a graph z = h(x, y)): face 6 centred at "
                       "(28.3, 2.2) mm, z = 16.7 mm, is folded under its neighbours "
                       "seen from above (18 such faces)"))
      << r.message;
}

TEST(HeightFieldCheck, RefusesAVerticalWall) {
  // A step: columns 2 and 3 share x = 20 and differ by 10 mm in height.
  const double xs[] = {0, 10, 20, 20, 30, 40};
  const Mesh step = grid_mesh(5, 2, [&](double u, double v) {
    const int i = static_cast<int>(std::lround(5 * u));
    return Eigen::Vector3d(xs[i], 20.0 * v, i >= 3 ? 10.0 : 0.0);
  });
  const Refusal r = refusal(from_mesh(step));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(
      r.message, "face 4 centred at (20.0, 3.3) mm, z = 6.7 mm, stands vertical (4 such faces)"))
      << r.message;
}

TEST(HeightFieldCheck, RefusesFacesGoingTwiceRoundAVertex) {
  // A fan of 12 faces around the origin whose rim turns twice (60 degrees per face), rising.
  const int n = 12;
  Mesh fan;
  fan.V.resize(n + 1, 3);
  fan.V.row(0) << 0, 0, 20;
  for (int k = 0; k < n; ++k) {
    const double a = 4 * std::numbers::pi * k / n, r = 10.0 + k;
    fan.V.row(k + 1) << r * std::cos(a), r * std::sin(a), k;
  }
  fan.F.resize(n, 3);
  for (int k = 0; k < n; ++k) fan.F.row(k) << 0, k + 1, (k + 1) % n + 1;
  const Refusal r = refusal(from_mesh(fan));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(r.message, "the surface winds 2 times round (0.0, 0.0) mm seen from above"))
      << r.message;
}

TEST(HeightFieldCheck, RefusesABoundaryPassingOverItself) {
  // A ramp winding 1.25 times round the z axis between radii 10 and 20 mm, rising 5 mm per
  // radian: every face and vertex is fine on its own, but the last quarter turn lies over the
  // first.
  const Mesh ramp = grid_mesh(24, 2, [](double u, double v) {
    const double a = 2.5 * std::numbers::pi * u, r = 10.0 + 10.0 * v;
    return Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 5.0 * a);
  });
  const Refusal r = refusal(from_mesh(ramp));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(r.message, "the boundary passes over itself at")) << r.message;
  // Where the overlap is: between the radii, in the first quarter turn.
  const Eigen::Vector2d p = reported_point(r.message);
  EXPECT_GE(p.norm(), 9.0) << r.message;
  EXPECT_LE(p.norm(), 20.1) << r.message;
  EXPECT_GE(p.x(), -0.05) << r.message;
  EXPECT_GE(p.y(), -0.05) << r.message;
}

TEST(HeightFieldCheck, RefusesAPitAtTheTopOfAHill) {
  // The summit pushed down to 5 mm: its lowest neighbours, the diagonal ones, stand at
  // 10 (15/16)^2 = 8.789 mm, so water stands 3.789 mm deep there.
  Mesh mesh = hill(10.0);
  mesh.V(vertex_at(mesh, 0.0, 0.0), 2) = 5.0;
  const Refusal r = refusal(from_mesh(mesh));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(r.message,
                       "a depression 3.789 mm deep at (0.0, 0.0) mm (its lowest point, "
                       "z = 5.00 mm; its rim is at z = 8.79 mm)"))
      << r.message;
  EXPECT_TRUE(contains(r.message, "fill the pit")) << r.message;
}

TEST(HeightFieldCheck, RefusesAFlatBottomedPit) {
  // The 3 x 3 vertices around the summit levelled at 3 mm; the lowest vertex around them is a
  // corner (10, 10)-type one at 16 (3/4)^2 = 9 mm. All nine are equally deep: the first is named.
  Mesh mesh = hill(16.0);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (std::abs(mesh.V(v, 0)) <= 5.0 && std::abs(mesh.V(v, 1)) <= 5.0) mesh.V(v, 2) = 3.0;
  }
  const Refusal r = refusal(from_mesh(mesh));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(r.message,
                       "a depression 6.000 mm deep at (-5.0, -5.0) mm (its lowest "
                       "point, z = 3.00 mm; its rim is at z = 9.00 mm)"))
      << r.message;
}

TEST(HeightFieldCheck, CountsSeveralPitsAndNamesTheDeepest) {
  // Two vertices halfway down, where the hill is 9 mm high and their lowest neighbours 3.06 mm,
  // pushed below those; the rims are alike (the mesh is symmetric under a half turn).
  Mesh mesh = hill(16.0);
  mesh.V(vertex_at(mesh, -10.0, 10.0), 2) = 2.0;
  mesh.V(vertex_at(mesh, 10.0, -10.0), 2) = 0.0;
  const Refusal r = refusal(from_mesh(mesh));
  EXPECT_TRUE(contains(r.message, "at (10.0, -10.0) mm")) << r.message;
  EXPECT_TRUE(contains(r.message, "the deepest of 2")) << r.message;
}

TEST(HeightFieldCheck, PitsShallowerThanTheToleranceAreLetThrough) {
  // A vertex of the flat top of a mesa lowered by half the tolerance, then by twice it.
  Mesh mesa = hill(16.0);
  for (int v = 0; v < mesa.num_vertices(); ++v) mesa.V(v, 2) = std::min(mesa.V(v, 2), 12.0);
  const int centre = vertex_at(mesa, 0.0, 0.0);
  mesa.V(centre, 2) = 12.0 - 0.5 * kDepressionToleranceMm;
  EXPECT_NO_THROW(check_height_field(from_mesh(mesa), "mesa"));
  mesa.V(centre, 2) = 12.0 - 2.0 * kDepressionToleranceMm;
  EXPECT_TRUE(
      contains(refusal(from_mesh(mesa)).message, "a depression 0.002 mm deep at (0.0, 0.0)"));
}

TEST(HeightFieldCheck, PassesOnTheMeshProblemsOfDiagnoseMesh) {
  Mesh mesh = hill();
  mesh.V(3, 0) = std::numeric_limits<double>::quiet_NaN();
  const Refusal r = refusal(from_mesh(mesh));
  EXPECT_EQ(r.category, ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(r.message, "NaN, infinite or absurdly large")) << r.message;
}

TEST(HeightFieldFromMesh, ReadsAFileWeldsSeamsAndTurnsFacesUp) {
  // The hill written with each square's vertices of its own (a "triangle soup", as an OBJ split
  // along seams) and its faces clockwise seen from above.
  const Mesh h = hill();
  Mesh soup{Eigen::MatrixXd(3 * h.num_faces(), 3), Eigen::MatrixXi(h.num_faces(), 3)};
  for (int f = 0; f < h.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) soup.V.row(3 * f + k) = h.V.row(h.F(f, 2 - k));
    soup.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  }
  const auto path = testing::scratch_dir() / "soup.obj";
  write_obj(path, soup);
  const HeightField field = height_field_from_mesh(read_mesh(path).mesh, path.string());
  EXPECT_EQ(field.V.rows(), h.num_vertices());
  EXPECT_EQ(field.F.rows(), h.num_faces());
  for (int f = 0; f < field.F.rows(); ++f) {
    const Eigen::Vector2d a = field.V.row(field.F(f, 0)).head<2>(),
                          b = field.V.row(field.F(f, 1)).head<2>(),
                          c = field.V.row(field.F(f, 2)).head<2>();
    const Eigen::Vector2d u = b - a, w = c - a;
    EXPECT_GT(u.x() * w.y() - u.y() * w.x(), 0.0) << "face " << f << " is not counter-clockwise";
  }
  EXPECT_DOUBLE_EQ(field.V.col(2).maxCoeff(), 10.0);
  EXPECT_EQ(field.colors.size(), 0);
}

TEST(HeightFieldFromMesh, RefusesAPitNamingTheFile) {
  Mesh mesh = hill(10.0);
  mesh.V(vertex_at(mesh, 0.0, 0.0), 2) = 5.0;
  try {
    height_field_from_mesh(mesh, "crater.stl");
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("crater.stl: a depression 3.789 mm deep at (0.0, 0.0) mm", 0),
        0u)
        << e.what();
  }
}

// A 9 x 7 hill image (16 bits): 65535 (1 - X^2)(1 - Y^2) rounded, X, Y in [-1, 1] across it.
GrayImage hill_image() {
  GrayImage image{9, 7, 16, {}};
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 9; ++x) {
      const double X = x / 4.0 - 1.0, Y = y / 3.0 - 1.0;
      image.samples.push_back(
          static_cast<uint16_t>(std::lround(65535 * (1 - X * X) * (1 - Y * Y))));
    }
  }
  return image;
}

TEST(HeightFieldFromImage, PixelsAreSamplesFromCornerToCorner) {
  const GrayImage image = hill_image();
  // 40 x 30 mm over 9 x 7 pixels: 5 mm per pixel both ways, the grid is the pixels.
  const HeightField field = height_field_from_image(image, 40.0, 30.0, 12.0, 5.0, "hill.png");
  ASSERT_EQ(field.V.rows(), 9 * 7);
  EXPECT_EQ(field.F.rows(), 2 * 8 * 6);
  EXPECT_DOUBLE_EQ(field.V.col(0).minCoeff(), -20.0);
  EXPECT_DOUBLE_EQ(field.V.col(0).maxCoeff(), 20.0);
  EXPECT_DOUBLE_EQ(field.V.col(1).minCoeff(), -15.0);
  EXPECT_DOUBLE_EQ(field.V.col(1).maxCoeff(), 15.0);
  for (int v = 0; v < field.V.rows(); ++v) {
    // Pixel column x = (x_mm + 20) / 5, row y = (15 - y_mm) / 5 (rows run down).
    const int px = static_cast<int>(std::lround((field.V(v, 0) + 20.0) / 5.0));
    const int py = static_cast<int>(std::lround((15.0 - field.V(v, 1)) / 5.0));
    EXPECT_NEAR(field.V(v, 2), 12.0 * image.at(px, py) / 65535.0, 1e-12) << v;
  }
  EXPECT_NEAR(field.V.col(2).maxCoeff(), 12.0, 1e-12);
  EXPECT_NO_THROW(check_height_field(field, "hill.png"));
}

TEST(HeightFieldFromImage, FinerGridIsBilinear) {
  // Two pixels, 0 and 255, over 10 x 10 mm at 2.5 mm: 5 x 5 vertices rising linearly along x.
  const GrayImage image{2, 2, 8, {0, 255, 0, 255}};
  const HeightField field = height_field_from_image(image, 10.0, 10.0, 4.0, 2.5, "ramp.png");
  ASSERT_EQ(field.V.rows(), 25);
  for (int v = 0; v < 25; ++v) {
    EXPECT_NEAR(field.V(v, 2), 4.0 * (field.V(v, 0) + 5.0) / 10.0, 1e-12) << v;
  }
}

TEST(HeightFieldFromImage, EightAndSixteenBitPngRoundTrip) {
  // The same hill written at both depths: heights scale to --height, the footprint to --size.
  const GrayImage hill16 = hill_image();
  std::vector<uint16_t> hill8;
  for (uint16_t s : hill16.samples) hill8.push_back(static_cast<uint16_t>(std::lround(s / 257.0)));
  for (int bits : {8, 16}) {
    const std::string png = testing::encode_test_png(9, 7, bits, testing::PngColor::kGray,
                                                     bits == 16 ? hill16.samples : hill8);
    const GrayImage image = read_gray_png_bytes(png, "hill.png");
    ASSERT_EQ(image.bits, bits);
    const HeightField field = height_field_from_image(image, 160.0, 120.0, 35.0, 20.0, "hill.png");
    EXPECT_DOUBLE_EQ(field.V.col(0).maxCoeff() - field.V.col(0).minCoeff(), 160.0);
    EXPECT_DOUBLE_EQ(field.V.col(1).maxCoeff() - field.V.col(1).minCoeff(), 120.0);
    EXPECT_NEAR(field.V.col(2).maxCoeff(), 35.0, 1e-12) << bits;  // the white centre pixel
    EXPECT_EQ(field.V.col(2).minCoeff(), 0.0);
    // A sample between the levels: pixel (2, 2) at X = -1/2, Y = -1/3.
    const int v = 4 * 9 + 2;  // grid row 4 from the bottom is image row 2
    EXPECT_NEAR(field.V(v, 2), 35.0 * 0.75 * (8.0 / 9.0), bits == 16 ? 35.0 / 65535 : 35.0 / 255)
        << bits;
  }
}

TEST(HeightFieldFromImage, RefusesAPitInTheImageSayingWhere) {
  GrayImage image = hill_image();
  image.samples[3 * 9 + 4] = 0;  // the centre pixel, black
  try {
    height_field_from_image(image, 40.0, 30.0, 12.0, 5.0, "pit.png");
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    EXPECT_TRUE(contains(e.what(), "pit.png: a depression")) << e.what();
    EXPECT_TRUE(contains(e.what(), "at (0.0, 0.0) mm (its lowest point, z = 0.00 mm")) << e.what();
  }
}

TEST(HeightFieldFromImage, RefusesBadSizesAndTinyImages) {
  const GrayImage image = hill_image();
  auto category = [&](const GrayImage& im, double w, double d, double h, double r) {
    try {
      height_field_from_image(im, w, d, h, r, "map.png");
    } catch (const UserError& e) {
      EXPECT_TRUE(contains(e.what(), "map.png: ")) << e.what();
      return e.category();
    }
    ADD_FAILURE() << "accepted";
    return ErrorCategory::kFile;
  };
  EXPECT_EQ(category(image, -160.0, 160.0, 30.0, 1.0), ErrorCategory::kOption);
  EXPECT_EQ(category(image, 160.0, 0.0, 30.0, 1.0), ErrorCategory::kOption);
  EXPECT_EQ(category(image, 160.0, 160.0, std::nan(""), 1.0), ErrorCategory::kOption);
  EXPECT_EQ(category(image, 160.0, 160.0, 30.0, 0.0), ErrorCategory::kOption);
  // 160 mm at 0.05 mm: 3201^2 = 10 million vertices.
  EXPECT_EQ(category(image, 160.0, 160.0, 30.0, 0.05), ErrorCategory::kOption);
  EXPECT_EQ(category(GrayImage{1, 5, 8, std::vector<uint16_t>(5, 0)}, 160.0, 160.0, 30.0, 1.0),
            ErrorCategory::kFormat);
}

}  // namespace
}  // namespace flatmorph::height_field_test
