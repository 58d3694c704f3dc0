// Colour texture of the self-rising sheet (SCF 2020 §6.5): colours read from a PLY and from an
// OBJ's UVs into a PNG land on the welded height field; colours_at reproduces a linear field; the
// screen-print image thins the ink by the area ratio, decodes back to the expected pixels, prints
// at scale (pHYs) with its registration marks off the sheet, and is byte-for-byte repeatable; a
// checkerboard printed on a dome's flattening keeps its squares' areas, and a wrong plate does not.
#include "methods/heightfield/texture.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <numbers>

#include "common/error.h"
#include "examples/height_field_examples.h"
#include "mesh/io.h"
#include "mesh/mesh_fixtures.h"
#include "methods/heightfield/png_fixtures.h"
#include "test_support.h"

namespace flatmorph::texture_test {
namespace {

using testing::encode_test_png;
using testing::PngColor;

template <typename Call>
UserError error_of(Call call) {
  try {
    call();
  } catch (const UserError& e) {
    return e;
  }
  ADD_FAILURE() << "no UserError";
  return UserError(ErrorCategory::kFile, "");
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A 6 x 6 RGB image whose red rises 51 per column to the right and green 51 per row upwards, blue
// 128: bilinear sampling gives exactly (u, v, 128 / 255) at every (u, v) in [0, 1]^2.
std::string gradient_png() {
  std::vector<uint16_t> samples;
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 6; ++x) {
      samples.insert(samples.end(),
                     {static_cast<uint16_t>(51 * x), static_cast<uint16_t>(51 * (5 - y)), 128});
    }
  }
  return encode_test_png(6, 6, 8, PngColor::kRgb, samples);
}

// ---------------------------------------------------------------------------------------------
// Colour PNG reader

TEST(ColorImage, ReadsRgbGrayAlphaAndSixteenBits) {
  const ColorImage rgb = read_color_png_bytes(
      encode_test_png(2, 1, 8, PngColor::kRgb, {255, 0, 10, 1, 2, 3}), "rgb.png");
  ASSERT_EQ(rgb.width, 2);
  ASSERT_EQ(rgb.height, 1);
  EXPECT_EQ(rgb.rgb, (std::vector<uint16_t>{255, 0, 10, 1, 2, 3}));
  EXPECT_DOUBLE_EQ(rgb.at(0, 0).x(), 1.0);

  const ColorImage gray =
      read_color_png_bytes(encode_test_png(1, 2, 8, PngColor::kGray, {7, 200}), "gray.png");
  EXPECT_EQ(gray.rgb, (std::vector<uint16_t>{7, 7, 7, 200, 200, 200}));

  // Transparent on white: alpha 0 is white, opaque keeps the colour, half alpha halfway.
  const ColorImage rgba = read_color_png_bytes(
      encode_test_png(3, 1, 8, PngColor::kRgba, {0, 0, 0, 0, 10, 20, 30, 255, 0, 100, 255, 128}),
      "rgba.png");
  // 255 - (128 / 255) (255 - c): 127 for c = 0, 177.2 for c = 100.
  EXPECT_EQ(rgba.rgb, (std::vector<uint16_t>{255, 255, 255, 10, 20, 30, 127, 177, 255}));

  const ColorImage deep = read_color_png_bytes(
      encode_test_png(1, 1, 16, PngColor::kRgb, {1, 40001, 65535}), "deep.png");
  EXPECT_EQ(deep.bits, 16);
  EXPECT_EQ(deep.rgb, (std::vector<uint16_t>{1, 40001, 65535}));
}

TEST(ColorImage, BilinearSamplingIsUpRightAndRepeatsOutside) {
  const ColorImage image = read_color_png_bytes(gradient_png(), "gradient.png");
  for (const auto& [u, v] : std::vector<std::pair<double, double>>{
           {0, 0}, {1, 1}, {0.5, 0.25}, {0.13, 0.87}, {1.0 + 1e-9, -1e-9}}) {
    const Eigen::Vector3d c = sample_bilinear(image, u, v);
    EXPECT_NEAR(c.x(), std::clamp(u, 0.0, 1.0), 1e-12) << u << ", " << v;
    EXPECT_NEAR(c.y(), std::clamp(v, 0.0, 1.0), 1e-12) << u << ", " << v;
    EXPECT_NEAR(c.z(), 128.0 / 255.0, 1e-12);
  }
  // (0, 0) is the bottom-left pixel: the image's last row.
  EXPECT_EQ(sample_bilinear(image, 0, 0), image.at(0, 5));
  // Outside [0, 1] the image repeats.
  EXPECT_NEAR(sample_bilinear(image, 1.25, -0.75).x(), 0.25, 1e-12);
  EXPECT_NEAR(sample_bilinear(image, 1.25, -0.75).y(), 0.25, 1e-12);
}

TEST(ColorImage, BadFilesAreUserErrorsNamingThem) {
  const UserError jpeg =
      error_of([] { read_color_png_bytes(std::string("\xff\xd8\xff\xe0 JFIF", 10), "photo.jpg"); });
  EXPECT_EQ(jpeg.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(jpeg.what(), "photo.jpg: not a PNG")) << jpeg.what();
  const std::string png = gradient_png();
  const UserError cut = error_of([&] { read_color_png_bytes(png.substr(0, 40), "cut.png"); });
  EXPECT_EQ(cut.category(), ErrorCategory::kFormat);
  const UserError missing =
      error_of([] { read_color_png(testing::scratch_dir() / "no_such_texture.png"); });
  EXPECT_EQ(missing.category(), ErrorCategory::kFile);
  EXPECT_TRUE(contains(missing.what(), "no_such_texture.png: no such file")) << missing.what();
}

// ---------------------------------------------------------------------------------------------
// Colour input

// A 2 x 2 mm square of two triangles, one colour per corner, as an ASCII PLY.
std::string colored_ply(const std::string& type, const std::vector<std::string>& colors) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty " +
      type + " red\nproperty " + type + " green\nproperty " + type +
      " blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const char* xyz[4] = {"0 0 0", "2 0 0", "2 2 0", "0 2 0"};
  for (int v = 0; v < 4; ++v) ply += std::string(xyz[v]) + " " + colors[v] + "\n";
  return ply + "3 0 1 2\n3 0 2 3\n";
}

HeightField field_of(const std::filesystem::path& mesh) {
  return height_field_from_mesh(read_mesh(mesh).mesh, mesh.string());
}

TEST(Texture, PlyVertexColoursReachTheField) {
  const auto dir = testing::scratch_dir();
  const auto bytes = dir / "bytes.ply";
  write_text(bytes, colored_ply("uchar", {"255 0 0", "0 255 0", "0 0 255", "51 102 204"}));
  const HeightField field = with_texture(field_of(bytes), bytes);
  ASSERT_EQ(field.colors.rows(), 4);
  for (int v = 0; v < 4; ++v) {
    const Eigen::Vector2d p(field.V(v, 0), field.V(v, 1));
    Eigen::Vector3d expected(51, 102, 204);
    if (p == Eigen::Vector2d(0, 0)) expected = {255, 0, 0};
    if (p == Eigen::Vector2d(2, 0)) expected = {0, 255, 0};
    if (p == Eigen::Vector2d(2, 2)) expected = {0, 0, 255};
    EXPECT_TRUE(field.colors.row(v).transpose().isApprox(expected / 255.0, 1e-15)) << v;
  }

  const auto floats = dir / "floats.ply";
  write_text(floats, colored_ply("float", {"0.25 0.5 1", "0 0 0", "1 1 1", "0.125 0 0"}));
  const ColorSamples samples = read_ply_vertex_colors(floats);
  EXPECT_EQ(samples.colors.row(0), Eigen::RowVector3d(0.25, 0.5, 1.0));

  const auto bright = dir / "bright.ply";
  write_text(bright, colored_ply("float", {"255 0 0", "0 0 0", "1 1 1", "0 0 0"}));
  const UserError out_of_range = error_of([&] { read_ply_vertex_colors(bright); });
  EXPECT_EQ(out_of_range.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(out_of_range.what(), "vertex 0")) << out_of_range.what();

  const auto plain = dir / "plain.ply";
  write_mesh(plain, read_mesh(bytes).mesh);
  const UserError none = error_of([&] { read_ply_vertex_colors(plain); });
  EXPECT_EQ(none.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(none.what(), "no vertex colours")) << none.what();
  EXPECT_EQ(error_of([&] { with_texture(field_of(bytes), bytes, dir / "t.png"); }).category(),
            ErrorCategory::kOption);
}

// A flat 20 x 20 mm square of 2 x 2 quads, split along x = 10 into two UV islands as an exporter
// splits a seam: the middle column is written twice, the left copy with u = 0.4, the right one
// with u = 0.6; elsewhere u = x / 20, v = y / 20.
std::string seam_obj() {
  std::string obj = "# seam\n";
  // Vertices 1-9: columns x = 0, 10, 20 (left copy of the middle); 10-12: the middle again.
  for (double x : {0.0, 10.0, 20.0}) {
    for (double y : {0.0, 10.0, 20.0}) obj += fmt::format("v {} {} 0\n", x, y);
  }
  for (double y : {0.0, 10.0, 20.0}) obj += fmt::format("v 10 {} 0\n", y);
  // Texture coordinates 1-9 like the vertices, 10-12 for the right copy.
  for (double x : {0.0, 10.0, 20.0}) {
    for (double y : {0.0, 10.0, 20.0}) {
      obj += fmt::format("vt {} {}\n", x == 10.0 ? 0.4 : x / 20.0, y / 20.0);
    }
  }
  for (double y : {0.0, 10.0, 20.0}) obj += fmt::format("vt 0.6 {}\n", y / 20.0);
  // Vertex (column c, row r) is 3 c + r + 1 (columns 0..2); the right copy of (1, r) is 10 + r.
  auto corner = [](int c, int r, bool right) {
    const int v = (c == 1 && right) ? 10 + r : 3 * c + r + 1;
    return fmt::format("{}/{}", v, v);
  };
  for (int c = 0; c < 2; ++c) {
    for (int r = 0; r < 2; ++r) {
      const bool right = c == 1;
      obj += fmt::format("f {} {} {} {}\n", corner(c, r, right), corner(c + 1, r, right),
                         corner(c + 1, r + 1, right), corner(c, r + 1, right));
    }
  }
  return obj;
}

TEST(Texture, ObjUvsSampleTheImageOnTheWeldedField) {
  const auto dir = testing::scratch_dir();
  const auto obj = dir / "seam.obj";
  const auto png = dir / "gradient.png";
  write_text(obj, seam_obj());
  write_text(png, gradient_png());
  const HeightField plain = field_of(obj);
  ASSERT_EQ(plain.V.rows(), 9) << "the seam is welded";
  const HeightField field = with_texture(plain, obj, png);
  ASSERT_EQ(field.colors.rows(), 9);
  for (int v = 0; v < 9; ++v) {
    // Red = u: x / 20 off the seam, and on it the mean of the two sides' 0.4 and 0.6. Not
    // mirrored: the left edge (u = 0) is the image's left column, red 0.
    const double x = field.V(v, 0), y = field.V(v, 1);
    EXPECT_NEAR(field.colors(v, 0), x / 20.0, 1e-12) << x << ", " << y;
    EXPECT_NEAR(field.colors(v, 1), y / 20.0, 1e-12) << x << ", " << y;
    EXPECT_NEAR(field.colors(v, 2), 128.0 / 255.0, 1e-12);
  }
  const ColorSamples samples = read_obj_texture_colors(obj, read_color_png(png));
  EXPECT_EQ(samples.points.rows(), 12) << "one sample per (v, vt) pair";
}

TEST(Texture, ObjWithoutUvsOrImageIsRefused) {
  const auto dir = testing::scratch_dir();
  const auto png = dir / "gradient.png";
  write_text(png, gradient_png());
  const auto bare = dir / "bare.obj";
  write_text(bare, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const UserError no_uv = error_of([&] { read_obj_texture_colors(bare, read_color_png(png)); });
  EXPECT_EQ(no_uv.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(no_uv.what(), "bare.obj: no texture coordinates")) << no_uv.what();

  const auto partial = dir / "partial.obj";
  write_text(partial,
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
             "f 1/1 2/2 3/3\nf 2 4 3\n");
  const UserError corner = error_of([&] { read_obj_texture_colors(partial, read_color_png(png)); });
  EXPECT_TRUE(contains(corner.what(), "partial.obj:9:")) << corner.what();

  const auto dangling = dir / "dangling.obj";
  write_text(dangling, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/7\n");
  const UserError ref = error_of([&] { read_obj_texture_colors(dangling, read_color_png(png)); });
  EXPECT_EQ(ref.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(ref.what(), "dangling.obj:5:")) << ref.what();

  const auto obj = dir / "seam.obj";
  write_text(obj, seam_obj());
  EXPECT_EQ(error_of([&] { with_texture(field_of(obj), obj); }).category(), ErrorCategory::kOption);
  const UserError missing = error_of([&] { with_texture(field_of(obj), obj, dir / "gone.png"); });
  EXPECT_EQ(missing.category(), ErrorCategory::kFile);
  EXPECT_TRUE(contains(missing.what(), "gone.png")) << missing.what();

  // Colours from another mesh do not fit the field.
  ColorSamples elsewhere = read_obj_texture_colors(obj, read_color_png(png));
  elsewhere.points *= 2.0;
  const UserError mismatch = error_of([&] { with_colors(field_of(obj), elsewhere, "x.obj"); });
  EXPECT_EQ(mismatch.category(), ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(mismatch.what(), "has no colour")) << mismatch.what();
}

// colour = (a + b x + c y) per channel: barycentric interpolation reproduces it exactly.
Eigen::RowVector3d linear_color(double x, double y) {
  return Eigen::RowVector3d(0.5 + 0.004 * x, 0.5 - 0.003 * y, 0.2 + 0.001 * x + 0.002 * y);
}

TEST(Texture, ColorsAtReproducesALinearField) {
  HeightField field = height_field_example("island", {100.0, 20.0, 5.0});
  field.colors.resize(field.V.rows(), 3);
  for (int v = 0; v < field.V.rows(); ++v) {
    field.colors.row(v) = linear_color(field.V(v, 0), field.V(v, 1));
  }
  // Points inside, vertices themselves (boundary ones included) and edge midpoints.
  Eigen::MatrixXd points(0, 2);
  auto add = [&](double x, double y) {
    points.conservativeResize(points.rows() + 1, 2);
    points.row(points.rows() - 1) << x, y;
  };
  for (int i = 0; i < 200; ++i) {
    const double r = 49.0 * std::sqrt((i % 17) / 17.0), a = 2.399963 * i;
    add(r * std::cos(a), r * std::sin(a));
  }
  for (int v = 0; v < field.V.rows(); v += 7) add(field.V(v, 0), field.V(v, 1));
  for (int f = 0; f < field.F.rows(); f += 11) {
    add(0.5 * (field.V(field.F(f, 0), 0) + field.V(field.F(f, 1), 0)),
        0.5 * (field.V(field.F(f, 0), 1) + field.V(field.F(f, 1), 1)));
  }
  const Eigen::MatrixXd colors = colors_at(field, points);
  for (int i = 0; i < points.rows(); ++i) {
    EXPECT_TRUE(colors.row(i).isApprox(linear_color(points(i, 0), points(i, 1)), 1e-12)) << i;
  }
  // A hair outside the boundary still has the boundary's colour; far outside is a caller's bug.
  Eigen::MatrixXd rim(1, 2);
  rim << 50.0 + 1e-6, 0.0;
  EXPECT_TRUE(colors_at(field, rim).row(0).isApprox(linear_color(50.0, 0.0), 1e-9));
  rim << 60.0, 0.0;
  EXPECT_THROW(colors_at(field, rim), std::invalid_argument);
  field.colors.resize(0, 3);
  EXPECT_THROW(colors_at(field, points), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Screen print

// A flat 60 x 40 mm target of 6 x 4 squares at the origin, and its colours (linear).
struct FlatSheet {
  Mesh mesh;
  Eigen::MatrixXd colors;
};
FlatSheet flat_sheet() {
  FlatSheet sheet;
  sheet.mesh = testing::grid_mesh(
      6, 4, [](double u, double v) { return Eigen::Vector3d(60.0 * u, 40.0 * v, 0.0); });
  sheet.colors.resize(sheet.mesh.num_vertices(), 3);
  for (int v = 0; v < sheet.mesh.num_vertices(); ++v) {
    sheet.colors.row(v) = linear_color(sheet.mesh.V(v, 0), sheet.mesh.V(v, 1));
  }
  return sheet;
}

ColorImage decode(const ScreenPrint& print) {
  const std::vector<unsigned char> png = screen_print_png(print);
  return read_color_png_bytes(std::string(png.begin(), png.end()), "print.png");
}

// The pixel of `print` whose centre is nearest plate point (x, y), in [0, 1].
Eigen::Vector3d pixel_at(const ScreenPrint& print, const ColorImage& image, double x, double y,
                         Eigen::Vector2d* centre = nullptr) {
  const RasterPlacement& at = print.placement;
  const int px = static_cast<int>(std::floor((x - at.left_mm) / at.pixel_mm));
  const int py = static_cast<int>(std::floor((at.top_mm - y) / at.pixel_mm));
  if (centre) *centre = at.pixel_center(px, py);
  return image.at(px, py);
}

TEST(ScreenPrint, NoShrinkMeansFullInkAndTheColoursAsDesigned) {
  const FlatSheet sheet = flat_sheet();
  const Eigen::MatrixXd plate = sheet.mesh.V.leftCols<2>();
  const ScreenPrint print = render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, sheet.colors);
  EXPECT_TRUE((print.opacity.array() == 1.0).all());
  const ColorImage image = decode(print);
  ASSERT_EQ(image.width, print.placement.width);
  EXPECT_NEAR(print.placement.pixel_mm, 25.4 / 300.0, 1e-15);
  EXPECT_NEAR(image.width * print.placement.pixel_mm, 60.0 + 2 * 15.0, print.placement.pixel_mm);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {1.0, 1.0}, {30.3, 20.7}, {59.0, 39.0}, {12.5, 33.3}}) {
    Eigen::Vector2d c;
    const Eigen::Vector3d got = pixel_at(print, image, x, y, &c);
    const Eigen::Vector3d want = linear_color(c.x(), c.y()).transpose();
    EXPECT_LE((got - want).cwiseAbs().maxCoeff(), 0.5 / 255 + 1e-12) << x << ", " << y;
  }
  // Off the sheet, inside the margin and away from the marks: white.
  EXPECT_EQ(pixel_at(print, image, 30.0, -7.0), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(pixel_at(print, image, 70.0, 20.0), Eigen::Vector3d(1, 1, 1));
}

TEST(ScreenPrint, InkIsThinnedByTheAreaRatio) {
  // The plate is the target grown by 1.25: every face shrinks to 1 / 1.5625 of its area as it
  // rises, so α = 0.64 and c' = 1 - 0.64 (1 - c).
  const FlatSheet sheet = flat_sheet();
  const Eigen::MatrixXd plate = 1.25 * sheet.mesh.V.leftCols<2>();
  ScreenPrintOptions options;
  options.dpi = 100;
  options.registration_marks = false;
  options.margin_mm = 2.0;
  const ScreenPrint print =
      render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, sheet.colors, options);
  for (int f = 0; f < print.opacity.size(); ++f) EXPECT_NEAR(print.opacity[f], 0.64, 1e-12);
  EXPECT_TRUE(print.marks.empty());
  const ColorImage image = decode(print);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{10.0, 10.0}, {60.0, 40.0}}) {
    Eigen::Vector2d c;
    const Eigen::Vector3d got = pixel_at(print, image, x, y, &c);
    const Eigen::Vector3d designed = linear_color(c.x() / 1.25, c.y() / 1.25).transpose();
    const Eigen::Vector3d want = (1.0 - 0.64 * (1.0 - designed.array())).matrix();
    EXPECT_LE((got - want).cwiseAbs().maxCoeff(), 0.5 / 255 + 1e-12) << x << ", " << y;
  }
}

// pHYs: (pixels per metre x, y, unit) from a PNG's bytes; zeros when absent.
std::array<uint32_t, 3> phys(const std::vector<unsigned char>& png) {
  size_t at = 8;
  auto be32 = [&](size_t i) {
    return uint32_t(png[i]) << 24 | uint32_t(png[i + 1]) << 16 | uint32_t(png[i + 2]) << 8 |
           uint32_t(png[i + 3]);
  };
  while (at + 8 <= png.size()) {
    const uint32_t length = be32(at);
    if (std::string(png.begin() + at + 4, png.begin() + at + 8) == "pHYs") {
      return {be32(at + 8), be32(at + 12), png[at + 16]};
    }
    at += 12 + length;
  }
  return {0, 0, 0};
}

TEST(ScreenPrint, PrintsAtScaleWithMarksOffTheSheetAndRepeatableBytes) {
  const FlatSheet sheet = flat_sheet();
  const Eigen::MatrixXd plate = sheet.mesh.V.leftCols<2>();
  Eigen::MatrixXd white = Eigen::MatrixXd::Ones(sheet.colors.rows(), 3);
  for (double dpi : {300.0, 150.0}) {
    ScreenPrintOptions options;
    options.dpi = dpi;
    const ScreenPrint print =
        render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, white, options);
    const std::vector<unsigned char> png = screen_print_png(print);
    const auto [x_ppm, y_ppm, unit] = phys(png);
    EXPECT_EQ(unit, 1u);
    EXPECT_EQ(x_ppm, static_cast<uint32_t>(std::lround(dpi / 0.0254)));
    EXPECT_EQ(y_ppm, x_ppm);
    // Whole pixels per metre: the printed scale is off by at most 0.5 / 11811 (17 µm over 400 mm).
    EXPECT_NEAR(x_ppm * 0.0254 / dpi, 1.0, 0.5 / x_ppm);

    // Three marks, each clear of the sheet's bounding box [0, 60] x [0, 40] with its arms.
    ASSERT_EQ(print.marks.size(), 3u);
    for (const Eigen::Vector2d& m : print.marks) {
      const double dx = std::max({0.0 - m.x(), m.x() - 60.0, 0.0});
      const double dy = std::max({0.0 - m.y(), m.y() - 40.0, 0.0});
      EXPECT_GE(std::min(dx, dy), kMarkArmMm + kMarkGapMm - 1e-9);
    }
    // Every black pixel lies outside the sheet and within reach of a mark; each mark's centre is
    // black.
    const ColorImage image = read_color_png_bytes(std::string(png.begin(), png.end()), "marks.png");
    int black = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        if (image.at(x, y) != Eigen::Vector3d::Zero()) continue;
        ++black;
        const Eigen::Vector2d c = print.placement.pixel_center(x, y);
        EXPECT_FALSE(c.x() >= 0 && c.x() <= 60 && c.y() >= 0 && c.y() <= 40);
        double nearest = 1e9;
        for (const Eigen::Vector2d& m : print.marks) nearest = std::min(nearest, (c - m).norm());
        EXPECT_LE(nearest, kMarkArmMm + kMarkLineMm);
      }
    }
    EXPECT_GT(black, 0);
    for (const Eigen::Vector2d& m : print.marks) {
      EXPECT_EQ(pixel_at(print, image, m.x(), m.y()), Eigen::Vector3d::Zero());
    }
    // The same input gives the same bytes, in memory and on disk.
    const auto again = render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, white, options);
    EXPECT_EQ(screen_print_png(again), png);
    const auto file = testing::scratch_dir() / "print.png";
    write_screen_print_png(file, again);
    EXPECT_EQ(testing::read_file(file), std::string(png.begin(), png.end()));
  }
  ScreenPrintOptions narrow;
  narrow.margin_mm = 5.0;
  EXPECT_EQ(error_of([&] {
              render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, white, narrow);
            }).category(),
            ErrorCategory::kOption);
  narrow.dpi = 0.0;
  narrow.registration_marks = false;
  EXPECT_EQ(error_of([&] {
              render_screen_print(plate, sheet.mesh.V, sheet.mesh.F, white, narrow);
            }).category(),
            ErrorCategory::kOption);
}

TEST(ScreenPrint, PixelsOnSharedEdgesAreCountedOnce) {
  // Pixels of 1/8 mm, the sheet's corners a quarter pixel off the centres and its diagonals
  // through pixel centres: each pixel centre inside is claimed by exactly one face, so the
  // labelled pixels are exactly the (8 * 12)^2 centres inside.
  const double p = 0.125;
  const Mesh grid = testing::grid_mesh(3, 3, [&](double u, double v) {
    return Eigen::Vector3d(0.25 * p + 4.0 * std::round(3 * u), -0.25 * p - 4.0 * std::round(3 * v),
                           0.0);
  });
  RasterPlacement at;
  at.pixel_mm = p;
  at.left_mm = -1.0;
  at.top_mm = 1.0;
  at.width = at.height = 8 * 14;
  const Eigen::MatrixXd plate = grid.V.leftCols<2>();
  const SquareLabels labels = checkerboard_labels(at, plate, grid.V, grid.F, 1000.0);
  const Eigen::VectorXd areas = risen_label_areas(labels, plate, grid.V, grid.F);
  EXPECT_DOUBLE_EQ(areas.sum(), 96.0 * 96.0 * p * p);
  // Rising into a sheet half as wide, each pixel counts a quarter of its area.
  const Eigen::MatrixXd half = 0.5 * grid.V;
  EXPECT_DOUBLE_EQ(risen_label_areas(labels, plate, half, grid.F).sum(), 0.25 * areas.sum());
}

// ---------------------------------------------------------------------------------------------
// Checkerboard acceptance

// A spherical cap (sphere radius R = 72.5 mm, 100 mm across, 20 mm high) on the hill example's
// ring lattice, and a flattening of it that keeps the meridians' lengths: a point at polar angle
// φ goes to radius R φ on the plate (azimuthal equidistant), so the sheet shrinks only along the
// parallels, by sin φ / φ, as the paper's dome (Fig. 3b).
struct Dome {
  HeightField field;
  Eigen::MatrixXd plate;
};
Dome dome() {
  constexpr double a = 50.0, h = 20.0, R = (a * a + h * h) / (2 * h);
  Dome d;
  d.field = height_field_example("hill", {2 * a, h, 2.5});
  d.plate.resize(d.field.V.rows(), 2);
  for (int v = 0; v < d.field.V.rows(); ++v) {
    const double x = d.field.V(v, 0), y = d.field.V(v, 1), r = std::hypot(x, y);
    d.field.V(v, 2) = std::sqrt(std::max(R * R - r * r, 0.0)) - (R - h);
    const double scale = r > 0 ? R * std::asin(std::min(r / R, 1.0)) / r : 1.0;
    d.plate.row(v) << scale * x, scale * y;
  }
  return d;
}

TEST(Checkerboard, DomeKeepsItsSquaresAndAWrongPlateDoesNot) {
  const Dome d = dome();
  const Eigen::MatrixXd& target = d.field.V;
  const Eigen::MatrixXi& F = d.field.F;
  constexpr double kSquare = 20.0;
  // The target's squares add up to the mesh's area, close to the cap's 2 π R h.
  const double R = (50.0 * 50.0 + 20.0 * 20.0) / 40.0;
  std::vector<Eigen::Vector2i> squares;
  for (int i = -3; i <= 2; ++i) {
    for (int j = -3; j <= 2; ++j) squares.emplace_back(i, j);
  }
  double mesh_area = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = target.row(F(f, 0)), b = target.row(F(f, 1)), c = target.row(F(f, 2));
    mesh_area += 0.5 * (b - a).cross(c - a).norm();
  }
  EXPECT_NEAR(target_square_areas(target, F, kSquare, squares).sum(), mesh_area, 1e-9 * mesh_area);
  EXPECT_NEAR(mesh_area, 2 * std::numbers::pi * R * 20.0, 0.01 * mesh_area);

  // Checkerboard colours per vertex, rendered with the real plate at 100 dpi (0.25 mm pixels: a
  // square of 20 mm loses or gains about 1 % along its edges), with its labels.
  Eigen::MatrixXd colors(target.rows(), 3);
  for (int v = 0; v < target.rows(); ++v) {
    const int parity =
        static_cast<int>(std::floor(target(v, 0) / kSquare) + std::floor(target(v, 1) / kSquare)) &
        1;
    colors.row(v).setConstant(parity ? 0.1 : 0.9);
  }
  ScreenPrintOptions options;
  options.dpi = 100;
  const ScreenPrint print = render_screen_print(d.plate, target, F, colors, options);
  // The dome's sheet shrinks everywhere but at the centre: α < 1, down to about sin φ / φ at the
  // rim (0.92).
  EXPECT_LT(print.opacity.maxCoeff(), 1.0);
  EXPECT_GT(print.opacity.minCoeff(), 0.85);
  const SquareLabels labels = checkerboard_labels(print.placement, d.plate, target, F, kSquare);
  const CheckerboardCheck good =
      check_checkerboard(labels, d.plate, target, /*risen=*/target, F, kSquare);
  EXPECT_GE(good.squares_compared, 16);
  EXPECT_LT(good.worst_relative_error, 0.10)
      << "square " << good.worst_square.transpose() << ": " << good.worst_risen_mm2 << " mm2 vs "
      << good.worst_target_mm2;

  // The design rendered for a plate 1.3 times too wide, printed on the real sheet: the squares
  // land in the wrong places and grow.
  Eigen::MatrixXd wide = d.plate;
  wide.col(0) *= 1.3;
  const ScreenPrint wrong_print = render_screen_print(wide, target, F, colors, options);
  const SquareLabels wrong = checkerboard_labels(wrong_print.placement, wide, target, F, kSquare);
  const CheckerboardCheck bad = check_checkerboard(wrong, d.plate, target, target, F, kSquare);
  EXPECT_GT(bad.worst_relative_error, 0.10);
}

}  // namespace
}  // namespace flatmorph::texture_test
