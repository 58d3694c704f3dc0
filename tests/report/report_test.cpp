// The report module (src/report/) and the toolpath file it reads: the toolpath as data, the report
// page of a run folder, the pictures and the view server. The browser acceptance test is
// report_browser_test.mjs.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "report/pictures.h"
#include "report/report.h"
#include "report/server.h"
#include "test_support.h"
#include "toolpath/toolpath_file.h"

// After Eigen: httplib.h brings <resolv.h>, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace flatmorph::report_test {
namespace {

using testing::run_cli;

PathPolyline polyline(std::initializer_list<Eigen::Vector3d> points) {
  PathPolyline p;
  p.points.resize(static_cast<Eigen::Index>(points.size()), 3);
  Eigen::Index i = 0;
  for (const Eigen::Vector3d& q : points) p.points.row(i++) = q.transpose();
  p.segments.resize(points.size() - 1);
  return p;
}

// toolpath.json holds what the G-code prints (each path's points to 1 µm, type, tool, width, the
// layer's z and height) and the G-code header's figures as data, for the report.
TEST(ToolpathFile, ReadsBackWhatTheGcodePrints) {
  Toolpath toolpath;
  for (int k = 1; k <= 2; ++k) {
    ToolpathLayer layer;
    layer.z = 0.08 * k;
    layer.height = 0.08;
    layer.paths.push_back(polyline({{0, 0, layer.z}, {20, 0, layer.z}, {20, 1, layer.z}}));
    layer.paths.push_back(polyline({{20, 5, layer.z}, {0, 5, layer.z}}));
    layer.paths.push_back(polyline({{0, 10, layer.z}, {15.12345678, 12, layer.z}}));
    layer.paths.back().type = PathType::kPerimeter;
    for (SegmentStyle& s : layer.paths.back().segments) s.tool = 1;
    toolpath.layers.push_back(layer);
  }
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const GcodeResult gcode =
      make_gcode(toolpath, printer, {load_material("pla-paper"), load_material("tpu-generic")});
  const auto path = testing::scratch_dir() / "toolpath.json";
  write_toolpath_file(path, toolpath, gcode.summary);
  const ToolpathFile read = read_toolpath_file(path);
  EXPECT_FALSE(summary_value(read, "estimated printing time (normal mode)").empty());
  EXPECT_EQ(summary_value(read, "printer"), "prusa-xl-2t");
  ASSERT_EQ(read.toolpath.layers.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const ToolpathLayer& a = toolpath.layers[k];
    const ToolpathLayer& b = read.toolpath.layers[k];
    EXPECT_NEAR(b.z, a.z, 5e-4);
    ASSERT_EQ(b.paths.size(), a.paths.size()) << k;
    for (size_t p = 0; p < a.paths.size(); ++p) {
      ASSERT_EQ(b.paths[p].points.rows(), a.paths[p].points.rows());
      EXPECT_LT(
          (b.paths[p].points.leftCols(2) - a.paths[p].points.leftCols(2)).cwiseAbs().maxCoeff(),
          5e-4);
      EXPECT_EQ(b.paths[p].segments.size(), a.paths[p].segments.size());
      EXPECT_EQ(b.paths[p].type, a.paths[p].type);
      EXPECT_EQ(b.paths[p].segments.front().tool, a.paths[p].segments.front().tool);
    }
  }
  // Same toolpath, same bytes.
  const std::string text = testing::read_file(path);
  write_toolpath_file(path, read.toolpath, read.summary);
  EXPECT_EQ(testing::read_file(path), text);
}

TEST(ToolpathFile, RefusesAnotherFile) {
  const auto path = testing::scratch_dir() / "other.json";
  std::ofstream(path) << "{\"layers\": []}";
  try {
    read_toolpath_file(path);
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kFormat);
    EXPECT_NE(std::string(e.what()).find("other.json"), std::string::npos);
  }
}

TEST(ReportRunFolder, AFolderWithoutRunFilesIsAUserError) {
  const auto dir = testing::scratch_dir();
  try {
    read_run_folder(dir);
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kFile);
  }
  const auto r = run_cli({"report", (dir / "absent").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "absent" / "report.html"));
}

// The drawings design.json lists are read from the folder and go into the page; names that point
// out of the folder or are not SVG are not read, and a listed drawing that is not there is missing.
TEST(ReportRunFolder, ReadsTheDrawingsDesignJsonListsAndNothingElse) {
  const auto dir = testing::scratch_dir();
  const std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg' width='10mm' height='10mm'><rect width='5' "
      "height='5'/></svg>";
  std::ofstream(dir / "net.svg") << svg;
  std::ofstream(dir / "secret.txt") << "not a drawing";
  std::ofstream(dir / "design.json")
      << R"({"input": "x", "drawings": ["net.svg", "absent.svg", "../net.svg", "secret.txt", 3]})";
  const RunFolder run = read_run_folder(dir);
  ASSERT_EQ(run.drawings.size(), 1u);
  EXPECT_EQ(run.drawings[0].first, "net.svg");
  EXPECT_EQ(run.drawings[0].second, svg);
  EXPECT_NE(std::find(run.missing.begin(), run.missing.end(), "absent.svg"), run.missing.end());
  const std::string html = report_html(run);
  EXPECT_NE(html.find("\"drawings\""), std::string::npos);
  EXPECT_NE(html.find("net.svg"), std::string::npos);
  EXPECT_EQ(html.find("not a drawing"), std::string::npos);
}

TEST(ReportPictures, PlateAndShapeAreDrawnWithTheirColourBars) {
  Eigen::MatrixXd plate(4, 2);
  plate << 0, 0, 10, 0, 10, 5, 0, 5;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  const Eigen::VectorXd theta1 = Eigen::Vector2d(0.2, 1.4);
  const Eigen::VectorXd theta2 = Eigen::Vector4d(-0.1, 0, 0.05, 0.1);
  const Canvas c = plate_picture(plate, F, theta1, PlateField::kTheta1, 200);
  EXPECT_EQ(c.width, 200);
  // 10 x 5 mm plate: about half as high as wide, plus the colour bar.
  EXPECT_GT(c.height, 100);
  EXPECT_LT(c.height, 200);
  const auto pixel = [&](int x, int y) {
    const size_t i = (static_cast<size_t>(y) * c.width + x) * 3;
    return Rgb{c.rgb[i], c.rgb[i + 1], c.rgb[i + 2]};
  };
  // Lower-right triangle (face 0) and upper-left (face 1) have different directions.
  EXPECT_EQ(pixel(150, 80), to_rgb(cyclic_color(0.2 / 3.141592653589793)));
  EXPECT_NE(pixel(150, 80), pixel(40, 20));
  Eigen::MatrixXd V(4, 3);
  V << 0, 0, 0, 10, 0, 1, 10, 5, 2, 0, 5, 1;
  const Canvas s = shape_picture(V, F, Eigen::Vector4d(0, 1, 2, 3), 200);
  EXPECT_EQ(plate_picture(plate, F, theta2, PlateField::kTheta2, 200).width, 200);
  EXPECT_EQ(s.width, 200);
  const std::vector<unsigned char> png = encode_png(s);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png[1], 'P');
}

// A small run folder made by the command line: flatten, simulate, toolpaths.
std::filesystem::path small_run() {
  const auto dir = testing::scratch_dir() / "saddle";
  const std::string d = dir.string();
  EXPECT_EQ(run_cli({"flatten", "--example", "saddle", "--width", "40", "--faces", "1", "--layers",
                     "4", "-o", d})
                .exit_code,
            0);
  EXPECT_EQ(run_cli({"simulate", d + "/flat.ply", "--target", d + "/target.ply", "-o",
                     d + "/simulated.ply"})
                .exit_code,
            0);
  EXPECT_EQ(
      run_cli({"toolpaths", d + "/flat.ply", "--printer", "generic-marlin", "-o", d}).exit_code, 0);
  return dir;
}

TEST(ReportPage, IsSelfContainedDeterministicAndHoldsEverySection) {
  const auto dir = small_run();
  const auto r = run_cli({"report", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = testing::read_file(dir / "report.html");
  for (const char* name : {"plate_theta1.png", "predicted.png", "layers.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  EXPECT_EQ(html.find("__FLATMORPH_"), std::string::npos);
  // Offline: nothing is loaded from elsewhere.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  for (const char* key : {"\"plate\"", "\"target\"", "\"predicted\"", "\"deviation_mm\"",
                          "\"toolpath\"", "estimated print time", "design.json"}) {
    EXPECT_NE(html.find(key), std::string::npos) << key;
  }
  // Same folder, same bytes.
  const RunFolder run = read_run_folder(dir);
  EXPECT_EQ(report_html(run), html);
  const std::string png = testing::read_file(dir / "predicted.png");
  write_report_pictures(run);
  EXPECT_EQ(testing::read_file(dir / "predicted.png"), png);
  ASSERT_TRUE(run.print);
  EXPECT_EQ(run.print->toolpath.layers.size(), 4u);
}

TEST(ReportView, ServesTheViewerOnLoopback) {
  const auto dir = small_run();
  std::atomic<bool> stop = false;
  std::atomic<int> port = 0;
  std::thread server([&] {
    ViewServerOptions options;
    options.port = 0;
    serve_run_folder(
        dir, options,
        [&](const std::string& url) {
          EXPECT_EQ(url.rfind("http://127.0.0.1:", 0), 0u);
          port = std::stoi(url.substr(std::string("http://127.0.0.1:").size()));
        },
        [&] { return stop.load(); });
  });
  for (int i = 0; i < 100 && port == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_NE(port, 0);
  httplib::Client client("127.0.0.1", port);
  const auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(page->body, report_html(read_run_folder(dir)));
  const auto missing = client.Get("/predicted.png");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);  // no report written yet
  const auto other = client.Get("/../flat.ply");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 404);
  stop = true;
  server.join();
}

}  // namespace
}  // namespace flatmorph::report_test
