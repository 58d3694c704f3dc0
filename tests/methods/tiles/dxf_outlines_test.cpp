// The DXF tile-outline reader (Geodesy CHI 2019 §6, notes §6.4): every entity read gives the
// shape drawn (radii, areas, units, the mirrored object coordinate system), loops nest even-odd,
// and every bad drawing is a UserError naming the line and what to do.
#include "methods/tiles/dxf_outlines.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "methods/tiles/outline_checks.h"
#include "methods/tiles/outline_file.h"
#include "test_support.h"

namespace flatmorph::dxf_outlines_test {
namespace {

namespace fs = std::filesystem;
using testing::error_of;
using testing::has_vertex;
using testing::radius_range;
using testing::signed_area;

std::string fixture(const std::string& name) {
  return testing::read_file(testing::test_data_dir() / "tiles" / name);
}

// An ASCII DXF: `entities` are group lines ("0", "CIRCLE", "10", "5", ...) joined one a line;
// $INSUNITS 4 (mm) unless `units` says otherwise ("" for no HEADER).
std::string dxf(const std::vector<std::string>& entities, const std::string& units = "4") {
  std::string text;
  if (!units.empty()) text += "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n" + units + "\n0\nENDSEC\n";
  text += "0\nSECTION\n2\nENTITIES\n";
  for (const std::string& line : entities) text += line + "\n";
  return text + "0\nENDSEC\n0\nEOF\n";
}

std::vector<std::string> circle(double x, double y, const std::string& radius) {
  return {"0", "CIRCLE", "8", "0", "10", std::to_string(x), "20", std::to_string(y), "40", radius};
}

std::vector<std::string> line(double x0, double y0, double x1, double y1) {
  return {"0",  "LINE",
          "10", std::to_string(x0),
          "20", std::to_string(y0),
          "11", std::to_string(x1),
          "21", std::to_string(y1)};
}

// A closed LWPOLYLINE through (x, y) pairs.
std::vector<std::string> lwpolyline(const std::vector<double>& xy) {
  std::vector<std::string> e = {"0", "LWPOLYLINE", "90", std::to_string(xy.size() / 2), "70", "1"};
  for (size_t i = 0; i + 1 < xy.size(); i += 2) {
    e.insert(e.end(), {"10", std::to_string(xy[i]), "20", std::to_string(xy[i + 1])});
  }
  return e;
}

std::vector<std::string> join(std::initializer_list<std::vector<std::string>> parts) {
  std::vector<std::string> all;
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

// The line (from 1) of the n-th line that reads `value` exactly.
long long line_of(const std::string& text, const std::string& value, int n = 1) {
  std::istringstream in(text);
  std::string l;
  for (long long number = 1; std::getline(in, l); ++number) {
    if (l == value && --n == 0) return number;
  }
  return -1;
}

std::string message_of(const std::string& text, const OutlineReadOptions& options = {}) {
  return error_of([&] { read_dxf_outlines(text, "t.dxf", options); }).what();
}

TEST(DxfOutlines, CircleIsAPolygonOfItsRadiusWithinTheChordTolerance) {
  const std::string text = fixture("circle.dxf");
  std::vector<std::string> warnings;
  const auto tiles = read_dxf_outlines(text, "circle.dxf", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(tiles[0].holes.empty());
  EXPECT_EQ(tiles[0].source, fmt::format("circle.dxf: CIRCLE at line {}", line_of(text, "CIRCLE")));
  const auto [lo, hi] = radius_range(tiles[0].boundary, {10, 20});
  EXPECT_NEAR(hi, 40, 1e-9);         // vertices on the circle
  EXPECT_GE(lo, 40 - 0.02 - 1e-12);  // chords within the tolerance
  EXPECT_LT(lo, 40 - 0.005);         // and not needlessly fine
  const double area = signed_area(tiles[0].boundary);
  EXPECT_GT(area, 0);  // counter-clockwise
  EXPECT_NEAR(area / (kPi * 40 * 40), 1, 1e-3);
}

TEST(DxfOutlines, FinerChordToleranceGivesMorePointsAndCloserArea) {
  OutlineReadOptions fine;
  fine.chord_tolerance = 0.001;
  const auto coarse = read_dxf_outlines(fixture("circle.dxf"), "c.dxf");
  const auto precise = read_dxf_outlines(fixture("circle.dxf"), "c.dxf", fine);
  EXPECT_GT(precise[0].boundary.rows(), 3 * coarse[0].boundary.rows());
  EXPECT_GE(radius_range(precise[0].boundary, {10, 20}).first, 40 - 0.001 - 1e-12);
  EXPECT_NEAR(signed_area(precise[0].boundary) / (kPi * 1600), 1, 1e-4);
}

TEST(DxfOutlines, RoundedSquareFromBulges) {
  const auto tiles = read_dxf_outlines(fixture("rounded_square.dxf"), "r.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  EXPECT_GT(p.rows(), 8);
  EXPECT_NEAR(p.col(0).minCoeff(), 0, 1e-12);
  EXPECT_NEAR(p.col(0).maxCoeff(), 20, 1e-12);
  EXPECT_NEAR(p.col(1).minCoeff(), 0, 1e-12);
  EXPECT_NEAR(p.col(1).maxCoeff(), 20, 1e-12);
  // Every vertex is on a side or on a corner's quarter circle of radius 3.
  const Eigen::RowVector2d centres[4] = {{17, 3}, {17, 17}, {3, 17}, {3, 3}};
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const bool on_side = p(i, 0) == 0 || p(i, 0) == 20 || p(i, 1) == 0 || p(i, 1) == 20;
    double nearest = INFINITY;
    for (const auto& c : centres) nearest = std::min(nearest, std::abs((p.row(i) - c).norm() - 3));
    EXPECT_TRUE(on_side || nearest < 1e-9) << p.row(i);
  }
  EXPECT_NEAR(signed_area(p), 400 - (4 - kPi) * 9, 0.02 * 4 * 3);
}

TEST(DxfOutlines, LinesAndArcsChainInAnyOrderAndDirection) {
  const std::string text = fixture("line_arc_chain.dxf");
  const auto tiles = read_dxf_outlines(text, "chain.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  EXPECT_NEAR(signed_area(p) / (600 + 100 * kPi), 1, 1e-3);
  // The half circles' extremes in x fall between vertices: within the chord tolerance.
  EXPECT_NEAR(p.col(0).minCoeff(), -10 + 0.01, 0.01);
  EXPECT_NEAR(p.col(0).maxCoeff(), 40 - 0.01, 0.01);
  EXPECT_NEAR(p.col(1).minCoeff(), -10, 1e-9);
  EXPECT_NEAR(p.col(1).maxCoeff(), 10, 1e-9);
  EXPECT_EQ(tiles[0].source, fmt::format("chain.dxf: chain of 4 pieces from the LINE at line {}",
                                         line_of(text, "LINE")));
}

TEST(DxfOutlines, ChainToleratesGapsBelowTheJoinTolerance) {
  // A triangle whose ends miss each other by 0.0005 mm.
  const std::string text =
      dxf(join({line(0, 0, 10, 0), line(10.0005, 0, 0, 10), line(0, 10.0005, 0, 0.0004)}));
  const auto tiles = read_dxf_outlines(text, "t.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].boundary.rows(), 3);
  EXPECT_NEAR(signed_area(tiles[0].boundary), 50, 0.01);
}

TEST(DxfOutlines, SquareWithCircularHole) {
  const auto tiles = read_dxf_outlines(fixture("square_hole.dxf"), "h.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_NEAR(signed_area(tiles[0].boundary), 2500, 1e-9);  // drawn clockwise, read CCW
  ASSERT_EQ(tiles[0].holes.size(), 1u);
  const double hole = signed_area(tiles[0].holes[0]);
  EXPECT_LT(hole, 0);  // clockwise
  EXPECT_NEAR(-hole / (kPi * 100), 1, 3e-3);
  EXPECT_NEAR(radius_range(tiles[0].holes[0], {25, 25}).second, 10, 1e-9);
}

TEST(DxfOutlines, InchesAreScaledToMillimetres) {
  std::vector<std::string> warnings;
  const auto tiles = read_dxf_outlines(fixture("inches.dxf"), "i.dxf", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_TRUE(warnings.empty());
  EXPECT_NEAR(signed_area(tiles[0].boundary), 25.4 * 25.4, 1e-9);
  EXPECT_TRUE(has_vertex(tiles[0].boundary, 25.4, 25.4));
}

TEST(DxfOutlines, OtherUnitsScale) {
  for (const auto& [code, mm] :
       {std::pair<std::string, double>{"5", 10.0}, {"6", 1000.0}, {"2", 304.8}, {"4", 1.0}}) {
    const auto tiles = read_dxf_outlines(dxf(lwpolyline({0, 0, 1, 0, 1, 1}), code), "u.dxf");
    EXPECT_NEAR(signed_area(tiles[0].boundary), mm * mm / 2, 1e-9 * mm * mm) << code;
  }
}

TEST(DxfOutlines, NoUnitsReadAsMillimetresWithAWarning) {
  for (const std::string& units : {std::string(), std::string("0")}) {
    std::vector<std::string> warnings;
    const auto tiles = read_dxf_outlines(dxf(circle(0, 0, "5"), units), "n.dxf", {}, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("n.dxf: the drawing has no units"), std::string::npos);
    EXPECT_NE(warnings[0].find("read as millimetres"), std::string::npos);
    EXPECT_NEAR(radius_range(tiles[0].boundary, {0, 0}).second, 5, 1e-9);
  }
}

TEST(DxfOutlines, MirroredObjectCoordinatesFlipX) {
  const auto tiles = read_dxf_outlines(fixture("ocs_mirror.dxf"), "o.dxf");
  ASSERT_EQ(tiles.size(), 2u);
  // The CIRCLE at (10, 5) with extrusion (0, 0, -1) is at (-10, 5) in the world.
  EXPECT_NEAR(tiles[0].boundary.col(0).mean(), -10, 1e-9);
  EXPECT_NEAR(tiles[0].boundary.col(1).mean(), 5, 1e-9);
  EXPECT_NEAR(radius_range(tiles[0].boundary, {-10, 5}).second, 3, 1e-9);
  // The half disc (bulge 1 from (0, 0) to (10, 0): below the chord) lands at x in [-10, 0].
  const Eigen::MatrixX2d& half = tiles[1].boundary;
  EXPECT_NEAR(half.col(0).minCoeff(), -10, 1e-9);
  EXPECT_NEAR(half.col(0).maxCoeff(), 0, 1e-9);
  EXPECT_NEAR(half.col(1).minCoeff(), -5, 1e-9);
  EXPECT_NEAR(half.col(1).maxCoeff(), 0, 1e-9);
  // Chords on the circle lose at most (4/3) s / r of its area: 0.53 % at r = 5 mm.
  EXPECT_NEAR(signed_area(half) / (kPi * 12.5), 1 - 0.0053 / 2, 0.0053 / 2);
}

TEST(DxfOutlines, PolylineWithVerticesAndBulge) {
  // A 2D POLYLINE: (0,0) to (10,0) straight, (10,0) to (10,10) a half circle bulging outwards
  // (bulge -1: clockwise seen from the right), then back to (0,10) and closed.
  const std::string text =
      dxf({"0",  "POLYLINE", "66", "1",      "70", "1", "0",  "VERTEX", "10", "0",      "20", "0",
           "0",  "VERTEX",   "10", "10",     "20", "0", "42", "1",      "0",  "VERTEX", "10", "10",
           "20", "10",       "0",  "VERTEX", "10", "0", "20", "10",     "0",  "SEQEND"});
  const auto tiles = read_dxf_outlines(text, "p.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_NEAR(tiles[0].boundary.col(0).maxCoeff(), 15, 1e-9);
  EXPECT_NEAR(signed_area(tiles[0].boundary), 100 + kPi * 12.5, 0.0053 * kPi * 12.5);
  EXPECT_EQ(tiles[0].source, fmt::format("p.dxf: POLYLINE at line {}", line_of(text, "POLYLINE")));
}

TEST(DxfOutlines, EvenOddNestingAndFileOrder) {
  // Outer square, a square hole in it, a tile inside the hole; then a circle elsewhere, drawn
  // first in the file.
  const std::string text =
      dxf(join({circle(200, 0, "5"), lwpolyline({0, 0, 100, 0, 100, 100, 0, 100}),
                lwpolyline({20, 20, 80, 20, 80, 80, 20, 80}),
                lwpolyline({40, 40, 60, 40, 60, 60, 40, 60})}));
  const auto tiles = read_dxf_outlines(text, "n.dxf");
  ASSERT_EQ(tiles.size(), 3u);
  EXPECT_EQ(tiles[0].source, fmt::format("n.dxf: CIRCLE at line {}", line_of(text, "CIRCLE")));
  EXPECT_EQ(tiles[1].source,
            fmt::format("n.dxf: LWPOLYLINE at line {}", line_of(text, "LWPOLYLINE", 1)));
  EXPECT_EQ(tiles[2].source,
            fmt::format("n.dxf: LWPOLYLINE at line {}", line_of(text, "LWPOLYLINE", 3)));
  ASSERT_EQ(tiles[1].holes.size(), 1u);
  EXPECT_NEAR(signed_area(tiles[1].holes[0]), -3600, 1e-9);
  EXPECT_TRUE(tiles[2].holes.empty());
  EXPECT_NEAR(signed_area(tiles[2].boundary), 400, 1e-9);
}

TEST(DxfOutlines, TilesSharingAnEdgeAreTwoTiles) {
  // Direct connections (§6.3): neighbours share an edge, and a T-junction.
  const auto tiles = read_dxf_outlines(dxf(join({lwpolyline({0, 0, 10, 0, 10, 10, 0, 10}),
                                                 lwpolyline({10, 0, 20, 0, 20, 20, 10, 20, 10, 10}),
                                                 lwpolyline({0, 10, 10, 10, 10, 20, 0, 20})})),
                                       "s.dxf");
  ASSERT_EQ(tiles.size(), 3u);
  for (const TileOutline& t : tiles) EXPECT_TRUE(t.holes.empty());
}

TEST(DxfOutlines, RepeatedPointsAreMerged) {
  const auto tiles = read_dxf_outlines(
      dxf(lwpolyline({0, 0, 0, 0, 10, 0, 10, 0.0001, 10, 10, 0, 10, 0, 0})), "r.dxf");
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].boundary.rows(), 4);
}

TEST(DxfOutlines, ZeroAreaLoopsAreDroppedWithAWarning) {
  const std::string text = dxf(join({lwpolyline({0, 0, 10, 0, 20, 0}), circle(50, 50, "5")}));
  std::vector<std::string> warnings;
  const auto tiles = read_dxf_outlines(text, "z.dxf", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], fmt::format("z.dxf:{}: the LWPOLYLINE at line {} encloses no area (its "
                                     "points repeat or lie on a line); it is not read",
                                     line_of(text, "LWPOLYLINE"), line_of(text, "LWPOLYLINE")));
  // Nothing else left: refused.
  EXPECT_NE(message_of(dxf(lwpolyline({0, 0, 10, 0, 20, 0}))).find("no closed outline"),
            std::string::npos);
}

TEST(DxfOutlines, PaperSpaceAndViewportsAreNotRead) {
  std::vector<std::string> warnings;
  const auto tiles =
      read_dxf_outlines(dxf(join({{"0", "VIEWPORT", "67", "1", "10", "0", "20", "0"},
                                  {"0", "CIRCLE", "67", "1", "10", "0", "20", "0", "40", "1"},
                                  circle(0, 0, "5")})),
                        "p.dxf", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 entities in paper space"), std::string::npos);
}

// --- Refusals ------------------------------------------------------------------------------------

TEST(DxfOutlines, EmptyBinaryAndGarbageFiles) {
  EXPECT_EQ(message_of(""), "t.dxf: empty file: export the outlines as ASCII DXF");
  EXPECT_EQ(message_of(" \n\r\n"), "t.dxf: empty file: export the outlines as ASCII DXF");
  const UserError binary = error_of(
      [] { read_dxf_outlines(std::string("AutoCAD Binary DXF\r\n\x1a\0\0\x01", 25), "b.dxf"); });
  EXPECT_EQ(binary.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(binary.what()).find("save the drawing as ASCII DXF"), std::string::npos);
  const std::string garbage("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\xff\xfe", 19);
  EXPECT_EQ(message_of(garbage),
            "t.dxf:1: not an ASCII DXF file (the first line should be a group code such as 0, it "
            "is \"\\x89PNG\"): save the drawing as ASCII DXF");
}

TEST(DxfOutlines, EveryTruncationIsRefused) {
  const std::string text = fixture("circle.dxf");
  const size_t end = text.find("EOF");
  for (size_t n = 1; n < end; ++n) {
    SCOPED_TRACE(n);
    error_of([&] { read_dxf_outlines(text.substr(0, n), "t.dxf"); });
  }
  EXPECT_NE(message_of(text.substr(0, text.find("ENDSEC", text.find("CIRCLE")))).find("truncated"),
            std::string::npos);
}

TEST(DxfOutlines, NonFiniteAndFarCoordinates) {
  EXPECT_EQ(message_of(dxf({"0", "CIRCLE", "10", "nan", "20", "0", "40", "1"})),
            "t.dxf:18: \"nan\" (group code 10) is not a finite number a drawing can hold: fix the "
            "coordinates in the drawing");
  EXPECT_NE(message_of(dxf({"0", "LINE", "10", "inf"})).find("not a finite number"),
            std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "LINE", "10", "1e400"})).find("not a finite number"),
            std::string::npos);
  EXPECT_EQ(message_of(dxf(lwpolyline({0, 0, 1e300, 0, 0, 1}))),
            "t.dxf:16: vertex 2 of the LWPOLYLINE lies at (1e+300, 0.0000) mm, more than 1e+06 mm "
            "(1 km) from the origin: check the drawing's units and coordinates");
  EXPECT_NE(message_of(dxf(circle(0, 0, "1e300"))).find("more than 1e+06 mm"), std::string::npos);
  // Centre near, radius far.
  EXPECT_NE(
      message_of(dxf(circle(-999000, 0, "5000"))).find("the CIRCLE reaches x = -1.004e+06 mm"),
      std::string::npos);
}

TEST(DxfOutlines, HugeBulgeIsRefused) {
  const std::string text = dxf({"0", "LWPOLYLINE", "70", "1", "10", "0", "20", "0", "42", "1e300",
                                "10", "10", "20", "0", "10", "0", "20", "10"});
  const UserError e = error_of([&] { read_dxf_outlines(text, "t.dxf"); });
  EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
  EXPECT_NE(std::string(e.what()).find("t.dxf:16: the arc of bulge 1e+300 after vertex 1 of the "
                                       "LWPOLYLINE reaches"),
            std::string::npos);
  // A tiny bulge is its chord.
  const auto flat = read_dxf_outlines(dxf({"0", "LWPOLYLINE", "70", "1", "10", "0", "20", "0", "42",
                                           "1e-300", "10", "10", "20", "0", "10", "0", "20", "10"}),
                                      "t.dxf");
  EXPECT_EQ(flat[0].boundary.rows(), 3);
}

TEST(DxfOutlines, BadRadiiAndZeroSweep) {
  EXPECT_EQ(message_of(dxf(circle(1, 2, "0"))),
            "t.dxf:16: the CIRCLE at (1, 2) has the radius 0: give it a positive radius or delete "
            "it, and save again");
  EXPECT_NE(message_of(dxf(circle(1, 2, "-5"))).find("has the radius -5"), std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "CIRCLE", "10", "0", "20", "0"})).find("has no radius"),
            std::string::npos);
  const UserError sweep = error_of([] {
    read_dxf_outlines(dxf({"0", "ARC", "10", "0", "20", "0", "40", "5", "50", "30", "51", "390"}),
                      "t.dxf");
  });
  EXPECT_EQ(sweep.category(), ErrorCategory::kGeometry);
  EXPECT_EQ(std::string(sweep.what()),
            "t.dxf:16: the ARC at (0, 0) has zero sweep (it starts and ends at 30 degrees): draw a "
            "CIRCLE for a full circle, or delete it, and save again");
}

TEST(DxfOutlines, UnitsOutsideTheReadOnesAreRefusedByName) {
  EXPECT_EQ(message_of(dxf(circle(0, 0, "1"), "13")),
            "t.dxf:8: the drawing's units are microns ($INSUNITS 13), which flatmorph does not "
            "read: set the drawing units to millimetres (or centimetres, metres, inches or feet) "
            "and save again");
  EXPECT_EQ(message_of(dxf(circle(0, 0, "1"), "99999")),
            "t.dxf:8: $INSUNITS 99999 is not a DXF unit code: set the drawing units to millimetres "
            "and save again");
  EXPECT_NE(message_of(dxf(circle(0, 0, "1"), "-3")).find("$INSUNITS -3 is not"),
            std::string::npos);
  EXPECT_NE(message_of(dxf(circle(0, 0, "1"), "four")).find("is not a whole number"),
            std::string::npos);
}

TEST(DxfOutlines, OtherEntitiesAreRefusedByNameWithWhatToDo) {
  EXPECT_EQ(message_of(dxf(join({circle(0, 0, "5"), {"0", "SPLINE", "70", "8"}}))),
            "t.dxf:26: SPLINE entities are not read: convert the outline to a polyline (explode / "
            "'convert to polyline' in most CAD tools) and save again");
  EXPECT_NE(message_of(dxf({"0", "ELLIPSE"})).find("ELLIPSE entities are not read: convert"),
            std::string::npos);
  EXPECT_EQ(message_of(dxf({"0", "INSERT", "2", "TILE"})),
            "t.dxf:16: INSERT entities are not read: explode the block (EXPLODE in most CAD tools) "
            "so that its outlines are drawn directly, and save again");
  for (const std::string type : {"TEXT", "MTEXT", "HATCH", "DIMENSION", "POINT"}) {
    EXPECT_EQ(message_of(dxf({"0", type})),
              "t.dxf:16: " + type +
                  " entities are not read: the drawing must hold only the tile outlines; delete "
                  "texts, dimensions, hatches and points (or leave their layers out of the "
                  "export) and save again");
  }
  EXPECT_NE(message_of(dxf({"0", "3DSOLID"}))
                .find("3DSOLID entities are not read: only LWPOLYLINE, POLYLINE, LINE, ARC and "
                      "CIRCLE entities are"),
            std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "POLYLINE", "70", "64", "0", "SEQEND"})).find("polyface mesh"),
            std::string::npos);
}

TEST(DxfOutlines, TiltedExtrusionIsRefused) {
  EXPECT_EQ(message_of(dxf({"0", "CIRCLE", "10", "0", "20", "0", "40", "1", "210", "1", "220", "0",
                            "230", "0"})),
            "t.dxf:16: the CIRCLE is drawn in a tilted plane (extrusion direction (1, 0, 0)): only "
            "outlines in the XY plane are read; draw it in the top view and save again");
}

TEST(DxfOutlines, OpenChainNamesTheGap) {
  // Three sides of a square.
  const std::string text = dxf(join({line(0, 0, 10, 0), line(10, 0, 10, 10), line(10, 10, 0, 10)}));
  const UserError e = error_of([&] { read_dxf_outlines(text, "t.dxf"); });
  EXPECT_EQ(e.category(), ErrorCategory::kTopology);
  EXPECT_EQ(std::string(e.what()),
            "t.dxf:16: the outline is open: the LINE ends at (0.0000, 0.0000) mm and no other line "
            "or arc ends within 0.001 mm of it (the nearest loose end is 10 mm away, at (0.0000, "
            "10.0000) mm): close the gap in the drawing (join the pieces into one closed polyline) "
            "and save again");
  // An open LWPOLYLINE alone.
  std::vector<std::string> open = lwpolyline({0, 0, 10, 0, 10, 10});
  open[5] = '0';  // a char: GCC 12 misreads the C-string assignment (-Wrestrict)
  EXPECT_NE(message_of(dxf(open)).find("the outline is open: the LWPOLYLINE ends at (0.0000, "
                                       "0.0000) mm and no other line or arc ends within 0.001 "
                                       "mm of it (the nearest loose end is 14.14 mm away, at "
                                       "(10.0000, 10.0000) mm)"),
            std::string::npos);
}

TEST(DxfOutlines, ThreeEndsMeetingAreRefused) {
  const std::string text =
      dxf(join({line(0, 0, 10, 0), line(10, 0, 0, 10), line(0, 10, 0, 0), line(0, 0, -5, -5)}));
  const UserError e = error_of([&] { read_dxf_outlines(text, "t.dxf"); });
  EXPECT_EQ(e.category(), ErrorCategory::kTopology);
  EXPECT_NE(std::string(e.what()).find("three or more ends of lines and arcs meet at (0.0000, "
                                       "0.0000) mm"),
            std::string::npos);
}

TEST(DxfOutlines, CrossingOutlinesAreRefusedWithThePlace) {
  const std::string bow_tie = dxf(lwpolyline({0, 0, 10, 10, 10, 0, 0, 10}));
  const UserError self = error_of([&] { read_dxf_outlines(bow_tie, "t.dxf"); });
  EXPECT_EQ(self.category(), ErrorCategory::kGeometry);
  EXPECT_EQ(std::string(self.what()),
            "t.dxf:16: the LWPOLYLINE crosses itself at (5.0000, 5.0000) mm: a tile outline must "
            "be a simple closed loop; fix the drawing");
  const std::string overlap =
      dxf(join({lwpolyline({0, 0, 10, 0, 10, 10, 0, 10}), lwpolyline({5, 2, 15, 2, 15, 8, 5, 8})}));
  EXPECT_EQ(message_of(overlap),
            fmt::format("t.dxf:16: the LWPOLYLINE and the LWPOLYLINE at line {} cross at "
                        "(10.0000, 2.0000) mm: tile outlines must not overlap, and a hole must lie "
                        "inside its tile; fix the drawing",
                        line_of(overlap, "LWPOLYLINE", 2)));
  EXPECT_NE(message_of(dxf(join({circle(0, 0, "10"), circle(5, 0, "10")}))).find("cross at"),
            std::string::npos);
}

TEST(DxfOutlines, CrossingsThroughAVertexAreRefused) {
  // A figure eight through its own vertex (5, 5): no two segments cross, the lobes turn opposite
  // ways.
  EXPECT_EQ(message_of(dxf(lwpolyline({0, 0, 5, 5, 10, 10, 10, 0, 5, 5, 0, 10}))),
            "t.dxf:16: the LWPOLYLINE crosses itself at (5.0000, 5.0000) mm: a tile outline must "
            "be a simple closed loop; fix the drawing");
  // A triangle through two corners of a square, along the square's diagonal and top edge.
  const std::string text =
      dxf(join({lwpolyline({0, 0, 10, 0, 10, 10, 0, 10}), lwpolyline({10, 10, 0, 0, -5, 10})}));
  EXPECT_NE(message_of(text).find(fmt::format("t.dxf:16: the LWPOLYLINE and the LWPOLYLINE at "
                                              "line {} cross at (",
                                              line_of(text, "LWPOLYLINE", 2))),
            std::string::npos);
  // A rectangle over the left half of a square, along its bottom and top edges: every place
  // where they meet runs along an edge; the middle of the edge at x = 5 is inside the square.
  const std::string half = dxf(
      join({lwpolyline({0, 0, 10, 0, 10, 10, 0, 10}), lwpolyline({-5, 0, 5, 0, 5, 10, -5, 10})}));
  EXPECT_NE(message_of(half).find("cross at ("), std::string::npos);
}

TEST(DxfOutlines, TouchingWithoutCrossingIsRead) {
  // Two lobes turning the same way, pinched at (5, 5): one tile.
  const auto pinched =
      read_dxf_outlines(dxf(lwpolyline({0, 0, 10, 0, 5, 5, 10, 10, 0, 10, 5, 5})), "t.dxf");
  ASSERT_EQ(pinched.size(), 1u);
  EXPECT_NEAR(signed_area(pinched[0].boundary), 50, 1e-9);
  // Tangent circles (a vertex of each at (5, 0)), and a hole touching its tile's corner.
  const auto tiles = read_dxf_outlines(
      dxf(join({circle(0, 0, "5"), circle(10, 0, "5"), lwpolyline({20, 0, 30, 0, 30, 10, 20, 10}),
                lwpolyline({20, 0, 25, 2, 22, 5})})),
      "t.dxf");
  ASSERT_EQ(tiles.size(), 3u);
  ASSERT_EQ(tiles[2].holes.size(), 1u);
  EXPECT_NEAR(signed_area(tiles[2].holes[0]), -10.5, 1e-9);
}

TEST(DxfOutlines, TheSameOutlineTwiceIsRefused) {
  const std::string text = dxf(join({circle(0, 0, "10"), circle(0, 0, "10")}));
  EXPECT_EQ(message_of(text),
            fmt::format("t.dxf:16: the CIRCLE and the CIRCLE at line {} are the same outline "
                        "drawn twice: delete one of them",
                        line_of(text, "CIRCLE", 2)));
}

TEST(DxfOutlines, LimitsAreResources) {
  OutlineReadOptions few;
  few.max_points = 1000;
  const UserError points =
      error_of([&] { read_dxf_outlines(dxf(circle(0, 0, "1e5")), "t.dxf", few); });
  EXPECT_EQ(points.category(), ErrorCategory::kResource);
  EXPECT_EQ(std::string(points.what()),
            "t.dxf:16: the drawing has more than 1000 points (curves included, cut into chords): "
            "simplify it, or draw fewer tiles per file");
  OutlineReadOptions small;
  small.max_bytes = 10;
  EXPECT_EQ(error_of([&] { read_dxf_outlines(dxf(circle(0, 0, "1")), "t.dxf", small); }).category(),
            ErrorCategory::kResource);
  OutlineReadOptions bad;
  bad.chord_tolerance = 0;
  EXPECT_EQ(error_of([&] { read_dxf_outlines(dxf(circle(0, 0, "1")), "t.dxf", bad); }).category(),
            ErrorCategory::kOption);
}

TEST(DxfOutlines, DamagedStructure) {
  EXPECT_NE(message_of("0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n10\n").find("without its value"),
            std::string::npos);
  EXPECT_NE(
      message_of("0\nSECTION\n2\nENTITIES\n0\nEOF\n").find("ENTITIES\" section has no ENDSEC"),
      std::string::npos);
  EXPECT_NE(message_of("0\nSECTION\n2\nHEADER\n0\nENDSEC\n0\nEOF\n").find("no ENTITIES section"),
            std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "LWPOLYLINE", "20", "5"})).find("without a vertex x"),
            std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "VERTEX"})).find("VERTEX without a POLYLINE"), std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "POLYLINE", "70", "1", "0", "VERTEX", "10", "0", "20", "0"}))
                .find("has no SEQEND"),
            std::string::npos);
  EXPECT_NE(message_of(dxf({"0", "CIRCLE", "10", "1,5"})).find("\"1,5\" is not a number"),
            std::string::npos);
}

// --- The file wrapper ----------------------------------------------------------------------------

TEST(TileOutlineFile, ChoosesTheReaderByExtensionInAnyCase) {
  const fs::path dir = testing::scratch_dir();
  fs::copy_file(testing::test_data_dir() / "tiles" / "circle.dxf", dir / "CIRCLE.DXF");
  fs::copy_file(testing::test_data_dir() / "tiles" / "circle.svg", dir / "circle.Svg");
  EXPECT_EQ(read_tile_outlines(dir / "CIRCLE.DXF").size(), 1u);
  const auto svg = read_tile_outlines(dir / "circle.Svg");
  ASSERT_EQ(svg.size(), 1u);
  EXPECT_EQ(svg[0].source, (dir / "circle.Svg").string() + ": <circle id=\"c2\"> at line 2");
}

TEST(TileOutlineFile, RefusesOtherExtensionsAndMissingFiles) {
  const fs::path dir = testing::scratch_dir();
  const UserError other = error_of([&] { read_tile_outlines(dir / "tiles.ai"); });
  EXPECT_EQ(other.category(), ErrorCategory::kFormat);
  EXPECT_EQ(std::string(other.what()),
            (dir / "tiles.ai").string() +
                ": tile outlines are read from .dxf (ASCII DXF) and .svg files, not '.ai': export "
                "the outlines from the drawing program as DXF or SVG");
  const UserError missing = error_of([&] { read_tile_outlines(dir / "missing.dxf"); });
  EXPECT_EQ(missing.category(), ErrorCategory::kFile);
  EXPECT_EQ(std::string(missing.what()), (dir / "missing.dxf").string() +
                                             ": cannot open the file: check the path and its "
                                             "permissions");
  fs::create_directories(dir / "folder.svg");
  EXPECT_EQ(error_of([&] { read_tile_outlines(dir / "folder.svg"); }).category(),
            ErrorCategory::kFile);
}

}  // namespace
}  // namespace flatmorph::dxf_outlines_test
