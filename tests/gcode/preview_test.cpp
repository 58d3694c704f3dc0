// Previews: SVG per layer and the PNG overview, checked by reading them back.
#include "gcode/preview.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <sstream>

#include "gcode_fixtures.h"
#include "test_support.h"

namespace flatmorph::preview_test {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

Toolpath three_lines() {
  Toolpath toolpath;
  ToolpathLayer layer;
  layer.z = layer.height = 0.2;
  for (int i = 0; i < 3; ++i) {
    layer.paths.push_back(
        testing::line_path({0, 10.0 * i}, {40, 10.0 * i}, 0.2, 0.2, 10, 0, PathType::kSolidInfill));
  }
  toolpath.layers.push_back(layer);
  return toolpath;
}

TEST(Preview, SvgShowsPathsInPrintOrderAndTravels) {
  const Toolpath toolpath = three_lines();
  PreviewOptions options;
  options.outline.push_back((Eigen::MatrixX2d(4, 2) << -1, -1, 41, -1, 41, 21, -1, 21).finished());
  const std::string svg = layer_svg(toolpath, 0, options);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_EQ(count(svg, "<polyline"), 3u);
  // First path dark blue, last yellow (the ends of the colour ramp).
  EXPECT_LT(svg.find("stroke=\"#440154\""), svg.find("stroke=\"#fde725\""));
  EXPECT_EQ(count(svg, "<line "), 2u);  // travels between the 3 paths
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
  EXPECT_EQ(count(svg, "<path fill=\"#eeeeee\""), 1u);  // the outline
  EXPECT_NE(svg.find("points=\"0.000,0.000 10.000,0.000 20.000,0.000"), std::string::npos);
  EXPECT_NE(svg.find("<title>layer 1 of 1"), std::string::npos);
  options.travels = false;
  EXPECT_EQ(count(layer_svg(toolpath, 0, options), "<line "), 0u);
}

TEST(Preview, EveryLayerSharesTheDrawingArea) {
  const Toolpath toolpath = testing::disk_toolpath(20, 4);
  auto view_box = [](const std::string& svg) {
    const size_t at = svg.find("viewBox=\"");
    EXPECT_NE(at, std::string::npos);
    return svg.substr(at, svg.find('"', at + 9) - at);
  };
  const std::string first = view_box(layer_svg(toolpath, 0));
  for (size_t k = 1; k < toolpath.layers.size(); ++k) {
    EXPECT_EQ(view_box(layer_svg(toolpath, k)), first);
  }
  const std::filesystem::path dir = testing::scratch_dir() / "layers";
  write_layer_svgs(dir, toolpath);
  for (const char* name : {"layer_001.svg", "layer_002.svg", "layer_003.svg", "layer_004.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "layer_005.svg"));
}

TEST(Preview, OverviewLayersIncludeFirstAndLast) {
  EXPECT_EQ(overview_layers(10, 12), (std::vector<size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(overview_layers(10, 4), (std::vector<size_t>{0, 3, 6, 9}));
  EXPECT_EQ(overview_layers(10, 1), (std::vector<size_t>{0}));
}

// Decodes the 8-bit RGB PNG that overview_png writes (filter type 0 on every row).
struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};
Image decode(const std::vector<unsigned char>& png) {
  Image image;
  EXPECT_EQ(std::string(png.begin() + 1, png.begin() + 4), "PNG");
  auto be32 = [&](size_t at) {
    return uint32_t(png[at]) << 24 | uint32_t(png[at + 1]) << 16 | uint32_t(png[at + 2]) << 8 |
           png[at + 3];
  };
  std::vector<unsigned char> idat;
  for (size_t at = 8; at < png.size();) {
    const uint32_t length = be32(at);
    const std::string type(png.begin() + at + 4, png.begin() + at + 8);
    const uint32_t crc = be32(at + 8 + length);
    EXPECT_EQ(crc, crc32(0, &png[at + 4], length + 4)) << type;
    if (type == "IHDR") {
      image.width = int(be32(at + 8));
      image.height = int(be32(at + 12));
      EXPECT_EQ(png[at + 16], 8);  // bits
      EXPECT_EQ(png[at + 17], 2);  // RGB
    } else if (type == "IDAT") {
      idat.insert(idat.end(), png.begin() + at + 8, png.begin() + at + 8 + length);
    }
    at += 12 + length;
  }
  std::vector<unsigned char> raw(size_t(image.height) * (image.width * 3 + 1));
  uLongf size = raw.size();
  EXPECT_EQ(uncompress(raw.data(), &size, idat.data(), idat.size()), Z_OK);
  EXPECT_EQ(size, raw.size());
  for (int y = 0; y < image.height; ++y) {
    EXPECT_EQ(raw[size_t(y) * (image.width * 3 + 1)], 0);
    const auto row = raw.begin() + long(y) * (image.width * 3 + 1) + 1;
    image.rgb.insert(image.rgb.end(), row, row + image.width * 3);
  }
  return image;
}

TEST(Preview, PngOverviewDrawsThePaths) {
  const Toolpath toolpath = three_lines();
  PreviewOptions options;
  options.panel_pixels = 200;
  options.travels = false;
  const std::vector<unsigned char> png = overview_png(toolpath, options);
  const Image image = decode(png);
  // One panel of 200 pixels with 4-pixel gaps around it.
  EXPECT_EQ(image.width, 208);
  EXPECT_EQ(image.height, 208);
  // The drawing spans 40 mm plus margins: the middle line (y = 10 mm) crosses the panel centre in
  // the middle colour of the ramp; a point between lines stays white.
  const int cx = 4 + 100, cy = 4 + 100;
  const unsigned char* mid = image.at(cx, cy);
  EXPECT_NEAR(mid[0], 33, 20);
  EXPECT_NEAR(mid[1], 145, 20);
  EXPECT_NEAR(mid[2], 140, 20);
  const double pixels_per_mm = (200 - 4) / (40 + 2 * 1.2);
  const unsigned char* between = image.at(cx, cy - int(5 * pixels_per_mm));
  EXPECT_EQ(between[0], 255);
  EXPECT_EQ(between[1], 255);
  EXPECT_EQ(between[2], 255);
  // Deterministic bytes.
  EXPECT_EQ(png, overview_png(toolpath, options));
}

// A layer's singularities are marked where they are (mm, y mirrored by the group transform), and
// the caption counts them; a layer without an entry gets no marks.
TEST(Preview, SingularitiesAreMarkedOnTheirLayer) {
  const Toolpath toolpath = three_lines();
  PreviewOptions options;
  options.singularities.push_back({{Eigen::Vector2d(20, 5)}, {Eigen::Vector2d(30, 15)}});
  const std::string svg = layer_svg(toolpath, 0, options);
  EXPECT_EQ(count(svg, "<circle "), 1u);
  EXPECT_NE(svg.find("<circle cx=\"20.000\" cy=\"5.000\""), std::string::npos);
  EXPECT_EQ(count(svg, "<rect "), 1u);
  EXPECT_NE(svg.find("1 direction singularities (red circles), 1 stripe forks"), std::string::npos);
  EXPECT_EQ(count(layer_svg(toolpath, 0), "<circle "), 0u);
  // In the PNG, a red ring around (20, 5) mm: its pixels near the ring's radius are red.
  options.panel_pixels = 200;
  options.travels = false;
  const Image image = decode(overview_png(toolpath, options));
  const double pixels_per_mm = (200 - 4) / (40 + 2 * 1.2);
  const int cx = 4 + 100, cy = 4 + 100;                                               // (20, 10) mm
  const int rx = cx, ry = cy + static_cast<int>(std::lround(5 * pixels_per_mm)) - 4;  // 4 px above
  bool red = false;
  for (int dy = -1; dy <= 1; ++dy) {
    const unsigned char* p = image.at(rx, ry + dy);
    red = red || (p[0] > 180 && p[1] < 120 && p[2] < 120);
  }
  EXPECT_TRUE(red);
}

TEST(Preview, PngOverviewHasAPanelPerShownLayer) {
  const Toolpath toolpath = testing::disk_toolpath(20, 5);
  PreviewOptions options;
  options.panel_pixels = 100;
  const Image image = decode(overview_png(toolpath, options));
  // 5 layers: a 3 x 2 grid.
  EXPECT_EQ(image.width, 3 * 100 + 4 * 4);
  EXPECT_EQ(image.height, 2 * 100 + 3 * 4);
  // The sixth cell is empty (background grey), the fifth holds a drawing.
  EXPECT_EQ(image.at(4 + 2 * 104 + 50, 4 + 104 + 50)[0], 200);
  const std::filesystem::path path = testing::scratch_dir() / "overview.png";
  write_overview_png(path, toolpath, options);
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
}

}  // namespace
}  // namespace flatmorph::preview_test
