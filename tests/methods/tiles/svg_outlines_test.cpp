// The SVG tile-outline reader (Geodesy CHI 2019 §6, notes §6.4): shapes, paths with arcs and
// transforms give the drawn outline in mm with y up (not mirrored), and every bad file is a
// UserError naming the line and what to do.
#include "methods/tiles/svg_outlines.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "common/error.h"
#include "methods/tiles/outline_checks.h"
#include "test_support.h"

namespace flatmorph::svg_outlines_test {
namespace {

using testing::error_of;
using testing::has_vertex;
using testing::radius_range;
using testing::signed_area;

std::string fixture(const std::string& name) {
  return testing::read_file(testing::test_data_dir() / "tiles" / name);
}

// An SVG of 100 x 100 mm, one user unit a mm unless `root` says otherwise; `body` starts on
// line 2.
std::string svg(const std::string& body,
                const std::string& root = R"(width="100mm" height="100mm" viewBox="0 0 100 100")") {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" " + root + ">\n" + body + "\n</svg>\n";
}

std::vector<TileOutline> read(const std::string& text, std::vector<std::string>* warnings = nullptr,
                              const OutlineReadOptions& options = {}) {
  return read_svg_outlines(text, "t.svg", options, warnings);
}

std::string message_of(const std::string& text, const OutlineReadOptions& options = {}) {
  return error_of([&] { read_svg_outlines(text, "t.svg", options); }).what();
}

ErrorCategory category_of(const std::string& text) {
  return error_of([&] { read_svg_outlines(text, "t.svg"); }).category();
}

TEST(SvgOutlines, PolygonInAMillimetreViewBox) {
  std::vector<std::string> warnings;
  const auto tiles = read_svg_outlines(fixture("polygon_mm.svg"), "p.svg", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(tiles[0].source, "p.svg: <polygon id=\"p1\"> at line 4");
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  EXPECT_EQ(p.rows(), 4);
  // 200 user units are 100 mm; SVG y 20..80 is plate y -40..-10.
  for (const auto& [x, y] : {std::pair{10.0, -10.0}, {90.0, -10.0}, {90.0, -40.0}, {10.0, -40.0}}) {
    EXPECT_TRUE(has_vertex(p, x, y)) << x << ", " << y;
  }
  EXPECT_NEAR(signed_area(p), 2400, 1e-9);
}

TEST(SvgOutlines, CircleHasItsRadiusAndArea) {
  const auto tiles = read_svg_outlines(fixture("circle.svg"), "c.svg");
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].source, "c.svg: <circle id=\"c2\"> at line 2");
  const auto [lo, hi] = radius_range(tiles[0].boundary, {30, -30});
  EXPECT_NEAR(hi, 25, 1e-9);
  EXPECT_GE(lo, 25 - 0.02 - 1e-12);
  // Chords with their ends on the circle lose at most (4/3) s / r of its area.
  EXPECT_NEAR(signed_area(tiles[0].boundary) / (kPi * 625), 1 - 0.02 / 25 * 2 / 3,
              0.02 / 25 * 2 / 3);
}

TEST(SvgOutlines, PathWithArcsAndRelativeCommands) {
  const auto tiles = read_svg_outlines(fixture("arcs_path.svg"), "a.svg");
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].source, "a.svg: <path id=\"stadium\"> at line 3");
  EXPECT_EQ(tiles[1].source, "a.svg: <path id=\"ellipse\"> at line 5");
  const Eigen::MatrixX2d& stadium = tiles[0].boundary;
  EXPECT_NEAR(signed_area(stadium) / (600 + 100 * kPi), 1, 1e-3);
  EXPECT_NEAR(stadium.col(0).minCoeff(), 0, 0.02);
  EXPECT_NEAR(stadium.col(0).maxCoeff(), 50, 0.02);
  EXPECT_NEAR(stadium.col(1).minCoeff(), -20, 1e-9);
  EXPECT_NEAR(stadium.col(1).maxCoeff(), 0, 1e-9);
  // The half circles bulge outwards: their points lie 10 mm from (10, -10) and (40, -10).
  EXPECT_TRUE(has_vertex(stadium, 10, 0) && has_vertex(stadium, 40, -20));
  const Eigen::MatrixX2d& ellipse = tiles[1].boundary;
  EXPECT_NEAR(signed_area(ellipse) / (kPi * 200), 1, 2e-3);
  EXPECT_NEAR(ellipse.col(0).minCoeff(), 80, 1e-9);
  EXPECT_NEAR(ellipse.col(0).maxCoeff(), 120, 1e-9);
  EXPECT_NEAR(ellipse.col(1).minCoeff(), -50, 0.02);
  EXPECT_NEAR(ellipse.col(1).maxCoeff(), -30, 0.02);
  for (Eigen::Index i = 0; i < ellipse.rows(); ++i) {
    const double u = (ellipse(i, 0) - 100) / 20, v = (ellipse(i, 1) + 40) / 10;
    EXPECT_NEAR(u * u + v * v, 1, 1e-9);  // on the ellipse
  }
}

TEST(SvgOutlines, RotatedEllipticalArcs) {
  // An ellipse of semi-axes 20 and 10 turned by 30 degrees about (50, 50), as two half arcs
  // between the ends of its major axis.
  const double c = std::cos(kPi / 6) * 20, s = std::sin(kPi / 6) * 20;
  const std::string d = fmt::format("M {} {} A 20 10 30 0 1 {} {} A 20 10 30 0 1 {} {} Z", 50 - c,
                                    50 - s, 50 + c, 50 + s, 50 - c, 50 - s);
  const auto tiles = read(svg("<path d=\"" + d + "\"/>"));
  ASSERT_EQ(tiles.size(), 1u);
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  EXPECT_NEAR(signed_area(p) / (kPi * 200), 1, 3e-3);
  // Back in the ellipse's own frame (plate y = -SVG y turns the angle to -30 degrees).
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const double x = p(i, 0) - 50, y = p(i, 1) + 50;
    const double a = -kPi / 6;
    const double u = (std::cos(a) * x + std::sin(a) * y) / 20;
    const double v = (-std::sin(a) * x + std::cos(a) * y) / 10;
    EXPECT_NEAR(u * u + v * v, 1, 1e-9);
  }
}

TEST(SvgOutlines, ArcRadiiTooSmallAreScaledUp) {
  // Radius 1 cannot span 20 units: SVG scales it to 10, giving a circle of radius 10.
  const auto tiles = read(svg(R"(<path d="M 40 50 A 1 1 0 0 1 60 50 A 1 1 0 0 1 40 50 z"/>)"));
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_NEAR(radius_range(tiles[0].boundary, {50, -50}).second, 10, 1e-9);
  // A zero radius is a straight line.
  const auto square = read(svg(R"(<path d="M 0 0 A 0 5 0 0 1 10 0 V 10 H 0 z"/>)"));
  EXPECT_EQ(square[0].boundary.rows(), 4);
}

TEST(SvgOutlines, GroupTransformsCompose) {
  const auto tiles = read_svg_outlines(fixture("group_transform.svg"), "g.svg");
  ASSERT_EQ(tiles.size(), 1u);
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  ASSERT_EQ(p.rows(), 3);
  // rotate(90) takes (x, y) to (-y, x), translate(30 10) moves it, then y turns up.
  EXPECT_TRUE(has_vertex(p, 30, -10, 1e-12));
  EXPECT_TRUE(has_vertex(p, 30, -20, 1e-12));
  EXPECT_TRUE(has_vertex(p, 25, -20, 1e-12));
  EXPECT_NEAR(signed_area(p), 25, 1e-12);
}

TEST(SvgOutlines, EveryTransformFunction) {
  const auto first_point = [](const std::string& transform) {
    const auto tiles =
        read(svg("<polygon transform=\"" + transform + "\" points=\"1,0 2,0 1,1\"/>"));
    return Eigen::RowVector2d(tiles[0].boundary.row(0));
  };
  // The point (1, 0) of SVG, as plate coordinates (y = -SVG y).
  EXPECT_TRUE(first_point("translate(5)").isApprox(Eigen::RowVector2d(6, 0)));
  EXPECT_TRUE(first_point("scale(3, 2)").isApprox(Eigen::RowVector2d(3, 0)));
  EXPECT_TRUE(first_point("rotate(90, 1, 1)").isApprox(Eigen::RowVector2d(2, -1)));
  EXPECT_TRUE(first_point("matrix(1 2 3 4 5 6)").isApprox(Eigen::RowVector2d(6, -8)));
  EXPECT_TRUE(first_point("skewY(45)").isApprox(Eigen::RowVector2d(1, -1)));
  EXPECT_TRUE(first_point("translate(1,1) ,scale(2)").isApprox(Eigen::RowVector2d(3, -1)));
  const auto skew = read(svg(R"svg(<polygon transform="skewX(45)" points="0,0 1,0 0,1"/>)svg"));
  EXPECT_TRUE(has_vertex(skew[0].boundary, 1, -1, 1e-12));  // SVG (0, 1) -> (1, 1)
}

TEST(SvgOutlines, YIsTurnedUpSoTheShapeIsNotMirrored) {
  const auto tiles = read_svg_outlines(fixture("triangle.svg"), "t.svg");
  ASSERT_EQ(tiles.size(), 1u);
  const Eigen::MatrixX2d& p = tiles[0].boundary;
  // On screen the short side goes down from the right angle: on the plate too.
  EXPECT_TRUE(has_vertex(p, 0, 0) && has_vertex(p, 30, 0) && has_vertex(p, 0, -10));
  EXPECT_NEAR(signed_area(p), 150, 1e-9);  // counter-clockwise
}

TEST(SvgOutlines, EditorFilesWithHiddenLayersAndHoles) {
  std::vector<std::string> warnings;
  const auto tiles = read_svg_outlines(fixture("inkscape.svg"), "i.svg", {}, &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_NE(tiles[0].source.find("<rect id=\"square\">"), std::string::npos);
  EXPECT_NEAR(signed_area(tiles[0].boundary), 3600 - (4 - kPi) * 25, 0.02 * 4 * 5 * 1.1);
  ASSERT_EQ(tiles[0].holes.size(), 1u);
  EXPECT_NEAR(signed_area(tiles[0].holes[0]) / (-kPi * 100), 1, 3e-3);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "i.svg: 1 hidden elements (display:none) are not read");
}

TEST(SvgOutlines, Units) {
  const std::string square = R"(<rect x="0" y="0" width="96" height="96"/>)";
  // width in px (or unitless) and a viewBox: a CSS px is 25.4/96 mm.
  for (const std::string width : {"96px", "96"}) {
    const auto tiles =
        read(svg(square, "width=\"" + width + "\" height=\"" + width + "\" viewBox=\"0 0 96 96\""));
    EXPECT_NEAR(signed_area(tiles[0].boundary), 25.4 * 25.4, 1e-9) << width;
  }
  // Inches, centimetres and points.
  EXPECT_NEAR(
      signed_area(read(svg(square, R"(width="2in" height="2in" viewBox="0 0 96 96")"))[0].boundary),
      50.8 * 50.8, 1e-9);
  EXPECT_NEAR(
      signed_area(read(svg(square, R"(width="2cm" height="2cm" viewBox="0 0 96 96")"))[0].boundary),
      400, 1e-9);
  EXPECT_NEAR(
      signed_area(
          read(svg(square, R"(width="72pt" height="72pt" viewBox="0 0 96 96")"))[0].boundary),
      25.4 * 25.4, 1e-9);
  // No viewBox: user units are CSS px whatever the width's unit.
  EXPECT_NEAR(signed_area(read(svg(square, R"(width="50mm" height="50mm")"))[0].boundary),
              25.4 * 25.4, 1e-9);
  // Lengths with units inside the drawing.
  const auto mm = read(svg(R"(<circle cx="0" cy="0" r="5mm"/>)", R"(width="100" height="100")"));
  EXPECT_NEAR(radius_range(mm[0].boundary, {0, 0}).second, 5, 1e-9);
  // Neither width nor viewBox: a user unit is a mm, with a warning.
  std::vector<std::string> warnings;
  const auto plain = read(svg(square, ""), &warnings);
  EXPECT_NEAR(signed_area(plain[0].boundary), 96 * 96, 1e-9);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "t.svg: the drawing has no width, height or viewBox: one user unit read "
            "as 1 mm");
}

TEST(SvgOutlines, PreserveAspectRatio) {
  // A 100 x 50 viewBox in a 100 x 100 mm viewport: meet scales by 1 and centres vertically.
  const std::string square = R"(<rect x="0" y="0" width="10" height="10"/>)";
  const auto meet = read(svg(square, R"(width="100mm" height="100mm" viewBox="0 0 100 50")"));
  EXPECT_TRUE(has_vertex(meet[0].boundary, 0, -25));
  EXPECT_NEAR(signed_area(meet[0].boundary), 100, 1e-9);
  const auto none = read(svg(square, R"(width="100mm" height="100mm" viewBox="0 0 100 50" )"
                                     R"(preserveAspectRatio="none")"));
  EXPECT_NEAR(signed_area(none[0].boundary), 200, 1e-9);
}

TEST(SvgOutlines, SubpathsEllipsesAndRoundedRects) {
  const auto tiles = read(svg(R"(<path id="two" d="M0 0h10v10h-10z m 20 0 h 10 v 10 h -10 z"/>
<ellipse cx="70" cy="20" rx="10" ry="5"/>
<rect x="0" y="40" width="40" height="20" rx="5" ry="3"/>)"));
  ASSERT_EQ(tiles.size(), 4u);
  EXPECT_EQ(tiles[0].source, "t.svg: <path id=\"two\"> at line 2");
  EXPECT_EQ(tiles[1].source, "t.svg: <path id=\"two\"> subpath 2 at line 2");
  EXPECT_TRUE(has_vertex(tiles[1].boundary, 30, -10));  // m relative to the first subpath's start
  EXPECT_NEAR(signed_area(tiles[2].boundary) / (kPi * 50), 1, 5e-3);
  EXPECT_NEAR(signed_area(tiles[3].boundary), 800 - (4 - kPi) * 15, 0.5);
  EXPECT_TRUE(has_vertex(tiles[3].boundary, 5, -40) && has_vertex(tiles[3].boundary, 40, -43));
}

TEST(SvgOutlines, ClosedPolylineAndRepeatedPoints) {
  const auto tiles = read(svg(R"(<polyline points="0,0 10,0 10,0 10,10 0,10 0,0.0005"/>)"));
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].boundary.rows(), 4);
}

TEST(SvgOutlines, ZeroAreaShapesAreDroppedWithAWarning) {
  std::vector<std::string> warnings;
  const auto tiles = read(svg(R"(<polygon points="0,0 10,0 20,0"/>
<polygon points="50,50 60,50 60,60"/>)"),
                          &warnings);
  ASSERT_EQ(tiles.size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "t.svg:2: the <polygon> at line 2 encloses no area (its points repeat or "
            "lie on a line); it is not read");
  // Degenerate transforms flatten shapes too.
  EXPECT_NE(
      message_of(svg(R"svg(<circle transform="scale(1 0)" r="5"/>)svg")).find("no closed outline"),
      std::string::npos);
}

// --- Refusals ------------------------------------------------------------------------------------

TEST(SvgOutlines, EmptyGarbageAndOtherXml) {
  EXPECT_EQ(message_of(""), "t.svg: empty file: save the outlines as SVG");
  EXPECT_EQ(message_of(std::string("\x89PNG\r\n\x1a\n\0\0", 10)),
            "t.svg:1: text before the first element: not an SVG file; save the drawing as SVG");
  EXPECT_EQ(message_of("<html><body/></html>"),
            "t.svg:1: the root element is <html>, not <svg>: not an SVG file; save the drawing as "
            "SVG");
  EXPECT_NE(message_of(std::string("\x1f\x8b\x08\0", 4)).find("compressed SVG"), std::string::npos);
  EXPECT_NE(message_of("\xff\xfe<\0s\0").find("UTF-16"), std::string::npos);
}

TEST(SvgOutlines, MalformedXmlNamesTheLine) {
  EXPECT_EQ(message_of(svg("<g>\n<polygon points=\"0,0 1,0 0,1\"/>\n</polygon>")),
            "t.svg:4: </polygon> closes <g> (opened at line 2): the file is not well-formed XML; "
            "save it again as SVG");
  EXPECT_EQ(message_of("<svg width=\"10mm"),
            "t.svg:1: the value of the attribute width of <svg> is never closed (no \"): the file "
            "is truncated or damaged");
  EXPECT_EQ(message_of("<svg>\n<rect width=\"10mm height='5'/>\n<circle r=\"1\"/></svg>"),
            "t.svg:2: the value of the attribute width of <rect> holds a <: the file is not "
            "well-formed XML (a quote missing?)");
  EXPECT_NE(message_of("<svg a='1' a='2'/>").find("the attribute a appears twice"),
            std::string::npos);
  EXPECT_NE(message_of("<svg width=10/>").find("is not in quotes"), std::string::npos);
  EXPECT_NE(message_of("<svg>\n<!-- never closed").find("t.svg:2: a comment that is never closed"),
            std::string::npos);
  EXPECT_NE(message_of("<svg/><svg/>").find("a second root element"), std::string::npos);
  EXPECT_NE(message_of("<svg>\n<g>\n").find("the file ends inside <g> (opened at line 2)"),
            std::string::npos);
}

TEST(SvgOutlines, EveryTruncationIsRefused) {
  const std::string text = fixture("polygon_mm.svg");
  const size_t end = text.find("</svg>") + 5;
  for (size_t n = 1; n < end; ++n) {
    SCOPED_TRACE(n);
    error_of([&] { read_svg_outlines(text.substr(0, n), "t.svg"); });
  }
}

TEST(SvgOutlines, DeepNestingIsRefused) {
  std::string deep = "<svg>";
  for (int i = 0; i < 10000; ++i) deep += "<g>";
  const UserError e = error_of([&] { read_svg_outlines(deep, "t.svg"); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_EQ(std::string(e.what()),
            "t.svg:1: elements are nested more than 256 deep: flatten the groups of the drawing");
}

TEST(SvgOutlines, TenMillionPointsAreAResource) {
  std::string text = "<svg>\n<path d=\"M0 0l";
  text.reserve(50'000'100);
  for (int i = 0; i < 5'000'000; ++i) text += "1 1 -1 -1 ";
  text += "\"/>\n</svg>\n";
  const UserError e = error_of([&] { read(text); });
  EXPECT_EQ(e.category(), ErrorCategory::kResource);
  EXPECT_EQ(std::string(e.what()),
            "t.svg:2: the drawing has more than 2000000 points (curves included, cut into "
            "chords): simplify it, or draw fewer tiles per file");
}

TEST(SvgOutlines, PathErrors) {
  EXPECT_EQ(message_of(svg(R"(<path id="p" d="M 0 0 L 10"/>)")),
            "t.svg:2: the <path id=\"p\">'s L command at character 7 of d needs 2 numbers, found "
            "1: fix the path, and save again");
  EXPECT_NE(message_of(svg(R"(<path d="M 0 0 A 5 5 0 2 1 10 0 z"/>)"))
                .find("A command at character 7 of d needs 7 numbers (rx ry rotation large-arc "
                      "sweep x y), found 3"),
            std::string::npos);
  EXPECT_EQ(message_of(svg(R"(<path d="M0 0 C 1 1 2 2 3 3 z"/>)")),
            "t.svg:2: the <path> has curves (C command at character 6 of d): convert curves to "
            "line segments, e.g. Inkscape Extensions > Modify Path > Flatten Beziers, and save "
            "again");
  for (const std::string c : {"c", "S", "s", "Q", "q", "T", "t"}) {
    EXPECT_NE(message_of(svg("<path d=\"M0 0 " + c + " 1 1 2 2 z\"/>")).find("has curves"),
              std::string::npos);
  }
  EXPECT_NE(message_of(svg(R"(<path d="L 1 1"/>)")).find("do not begin with a moveto"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<path d="M 0 0 X 1 1"/>)")).find("unknown command X"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<path d="M 0 0 L 1 1 Z 5"/>)")).find("a number after Z"),
            std::string::npos);
}

TEST(SvgOutlines, OpenShapesAreRefusedWithWhereTheyEnd) {
  const UserError polyline = error_of([] { read(svg(R"(<polyline points="0,0 10,0 10,10"/>)")); });
  EXPECT_EQ(polyline.category(), ErrorCategory::kTopology);
  EXPECT_EQ(std::string(polyline.what()),
            "t.svg:2: the <polyline> is open: it ends at (10.0000, -10.0000) mm, not where it "
            "starts, (0.0000, 0.0000) mm: make it a polygon, or end it at its first point, and "
            "save again");
  EXPECT_EQ(message_of(svg(R"(<path d="M0 0 h10 v10 z M 20 0 h 10 v 10"/>)")),
            "t.svg:2: the <path> subpath 2 is open: it ends at (30.0000, -10.0000) mm, not where "
            "it starts, (20.0000, 0.0000) mm: close it (Z) or end it at its first point in the "
            "drawing, and save again");
}

TEST(SvgOutlines, ElementsNotReadAreRefusedByName) {
  EXPECT_EQ(message_of(svg(R"(<use href="#a"/>)")),
            "t.svg:2: <use> elements (clones) are not read: unlink the clone (Inkscape: Edit > "
            "Clone > Unlink Clone) or draw the shape itself, and save again");
  EXPECT_NE(message_of(svg(R"(<image href="a.png"/>)")).find("<image> elements are not read"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<line x2="5"/>)")).find("a <line> is one segment"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<blob/>)")).find("<blob> elements are not read"), std::string::npos);
}

TEST(SvgOutlines, BadNumbersRadiiAndCoordinates) {
  EXPECT_EQ(message_of(svg(R"(<circle id="c" cx="1" cy="1" r="0"/>)")),
            "t.svg:2: the <circle id=\"c\"> has r = 0: give it a positive r, or delete it, and "
            "save again");
  EXPECT_EQ(category_of(svg(R"(<circle r="-1"/>)")), ErrorCategory::kGeometry);
  EXPECT_NE(message_of(svg(R"(<circle cx="1"/>)")).find("has no r"), std::string::npos);
  EXPECT_NE(message_of(svg(R"(<rect width="0" height="5"/>)")).find("has width = 0"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<polygon points="nan 0 1 0 0 1"/>)"))
                .find("the <polygon>'s points hold \"nan 0 1 0 0 1\", which is not a number"),
            std::string::npos);
  EXPECT_NE(
      message_of(svg(R"(<polygon points="0 0 1 0 0"/>)")).find("odd number of coordinates (5)"),
      std::string::npos);
  EXPECT_EQ(message_of(svg(R"(<polygon points="0 0 1e300 0 0 1"/>)")),
            "t.svg:2: a point of the <polygon> lies at (1e+300, 0.0000) mm, more than 1e+06 mm (1 "
            "km) from the origin: check the drawing's units and coordinates");
  EXPECT_NE(message_of(svg(R"(<circle r="1e300"/>)")).find("more than 1e+06 mm"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<circle r="5em"/>)")).find("has a unit flatmorph cannot turn into"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<circle r="5" transform="rotate(45"/>)"))
                .find("is not a transform "
                      "list"),
            std::string::npos);
  EXPECT_NE(message_of(svg("", R"(viewBox="0 0 0 10")")).find("viewBox=\"0 0 0 10\" is not four"),
            std::string::npos);
  // Huge arc radii: the short way is the chord, the long way leaves the drawing.
  EXPECT_EQ(read(svg(R"(<path d="M0 0 A 1e300 1e300 0 0 1 10 0 L 10 10 z"/>)"))[0].boundary.rows(),
            3);
  EXPECT_NE(message_of(svg(R"(<path d="M0 0 A 1e300 1e300 0 1 1 10 0 L 10 10 z"/>)"))
                .find("its long way round leaves the drawing"),
            std::string::npos);
  EXPECT_NE(message_of(svg(R"(<path d="M0 0 A 1e6 1e6 0 1 1 10 0 L 10 10 z"/>)")).find("reaches"),
            std::string::npos);
}

TEST(SvgOutlines, SelfIntersectionAndCrossingsAreRefusedWithThePlace) {
  EXPECT_EQ(message_of(svg(R"(<polygon id="bow" points="0,0 10,10 10,0 0,10"/>)")),
            "t.svg:2: the <polygon id=\"bow\"> crosses itself at (5.0000, -5.0000) mm: a tile "
            "outline must be a simple closed loop; fix the drawing");
  // The circle's vertices at 90 and 270 degrees lie on the rectangle's edge: no chord crosses
  // it, yet the two overlap.
  EXPECT_EQ(message_of(svg(R"(<rect width="10" height="10"/>
<circle cx="10" cy="5" r="3"/>)")),
            "t.svg:2: the <rect> and the <circle> at line 3 cross at (10.0000, -8.0000) mm: tile "
            "outlines must not overlap, and a hole must lie inside its tile; fix the drawing");
}

TEST(SvgOutlines, EntitiesAndCharacterReferencesAreDecoded) {
  // &#x2C; is a comma, &#32; a space.
  const auto tiles = read(svg(R"(<polygon id="a&amp;b" points="0&#x2C;0&#32;10,0 0,10"/>)"));
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].source, "t.svg: <polygon id=\"a&b\"> at line 2");
}

}  // namespace
}  // namespace flatmorph::svg_outlines_test
