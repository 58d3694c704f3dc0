// The SVG reading shared by the drawn-input readers: which elements draw, their map to plate mm
// (viewport, group and element transforms, y up), inherited styles, numbers, points and path data
// command by command, and messages with the line. The tile-outline and crease-pattern readers'
// own tests cover the rest through them.
#include "common/svg_drawing.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace flatmorph::svg_drawing_test {
namespace {

struct Seen {
  std::string name;
  long long line;
  svg::Point origin;  // where the element's user (0, 0) lands, mm
  svg::Point unit_x;  // where its user (1, 0) lands
  size_t groups;
  std::optional<std::string> stroke, stroke_own, width;
};

std::vector<Seen> shapes_of(const std::string& text, std::vector<std::string>* warnings = nullptr) {
  std::vector<Seen> seen;
  std::vector<std::string> found;
  svg::read_drawing(
      text, "d.svg", "the drawing",
      [&](const svg::Shape& shape) {
        seen.push_back({std::string(shape.name), shape.element.line, shape.map({0, 0}),
                        shape.map({1, 0}), shape.groups.size(),
                        svg::property(shape, "stroke", true), svg::property(shape, "stroke", false),
                        svg::property(shape, "stroke-width", true)});
      },
      found);
  if (warnings != nullptr) *warnings = found;
  return seen;
}

std::string message_of(const std::string& text) {
  try {
    shapes_of(text);
  } catch (const UserError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no UserError";
  return "";
}

TEST(SvgDrawing, OnlyDrawingElementsComeWithTheirMapsInDocumentOrder) {
  const std::string text =
      R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="100mm"
     viewBox="0 0 100 50" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape">
<defs><path id="hidden-in-defs" d="M0 0 L1 1"/></defs>
<g transform="translate(10 5)" stroke="red" style="stroke-width: 2">
  <line x2="1"/>
  <g transform="rotate(90)"><rect width="1" height="1" style="stroke:#00f"/></g>
</g>
<text x="3">label</text>
<circle r="1" display="none"/>
<inkscape:thing/>
<svg:path d="M0 0" stroke="inherit"/>
</svg>)svg";
  std::vector<std::string> warnings;
  const std::vector<Seen> seen = shapes_of(text, &warnings);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].name, "line");
  EXPECT_EQ(seen[0].line, 5);
  // Two mm per user unit; (10, 5) user units right and down: (20, −10) mm with y up.
  EXPECT_TRUE(seen[0].origin.isApprox(svg::Point(20, -10)));
  EXPECT_TRUE(seen[0].unit_x.isApprox(svg::Point(22, -10)));
  EXPECT_EQ(seen[0].groups, 2u);  // the root and the group
  EXPECT_EQ(seen[0].stroke, "red");
  EXPECT_FALSE(seen[0].stroke_own.has_value());
  EXPECT_EQ(seen[0].width, "2");  // from the group's style
  // rotate(90) turns user x to SVG's y (down on screen): down on the plate.
  EXPECT_EQ(seen[1].name, "rect");
  EXPECT_TRUE(seen[1].unit_x.isApprox(svg::Point(20, -12)));
  EXPECT_EQ(seen[1].stroke, "#00f");  // its own style wins over the group's attribute
  EXPECT_EQ(seen[1].groups, 3u);
  EXPECT_EQ(seen[2].name, "path");           // "svg:" prefix dropped
  EXPECT_FALSE(seen[2].stroke.has_value());  // "inherit" up to a root that sets none
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "d.svg: 1 hidden elements (display:none) are not read");
}

TEST(SvgDrawing, NumbersAndLengths) {
  EXPECT_EQ(svg::number(" 1.5 "), 1.5);
  EXPECT_EQ(svg::number("-2e3"), -2000);
  EXPECT_EQ(svg::number(".5"), 0.5);
  EXPECT_FALSE(svg::number("1.5px").has_value());
  EXPECT_FALSE(svg::number("1 2").has_value());
  EXPECT_FALSE(svg::number("nan").has_value());
  EXPECT_FALSE(svg::number("").has_value());
  svg::Element element;
  element.line = 7;
  element.name = "rect";
  element.attributes = {{"width", "2mm"}, {"height", "3"}, {"x", "1em"}};
  EXPECT_NEAR(*svg::length(element, "width", "d.svg"), 2 * 96 / 25.4, 1e-12);
  EXPECT_EQ(*svg::length(element, "height", "d.svg"), 3);
  EXPECT_FALSE(svg::length(element, "y", "d.svg").has_value());
  try {
    svg::length(element, "x", "d.svg");
    ADD_FAILURE() << "no UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()),
              "d.svg:7: x=\"1em\" of the <rect> has a unit flatmorph cannot turn into "
              "millimetres: give it in mm, cm, in, pt, pc or px");
  }
}

TEST(SvgDrawing, PathDataCommandByCommand) {
  svg::Element element;
  element.name = "path";
  element.attributes = {{"d", "M0 0 L10 0 10 10 Z l 5 5 m 1 1 h 2 A 3 4 30 1 0 9 9 M 20 20"}};
  std::vector<std::string> calls;
  svg::PathCallbacks callbacks;
  callbacks.begin = [&](const svg::Point& p, int k) {
    calls.push_back(fmt::format("begin {} {} #{}", p.x(), p.y(), k));
  };
  callbacks.line_to = [&](const svg::Point& p) {
    calls.push_back(fmt::format("line {} {}", p.x(), p.y()));
  };
  callbacks.arc_to = [&](const svg::Point& from, const svg::Point& to, const svg::ArcCommand& a) {
    calls.push_back(fmt::format("arc {} {} to {} {} r {} {} {} {}{}", from.x(), from.y(), to.x(),
                                to.y(), a.rx, a.ry, a.rotation, a.large, a.sweep));
  };
  callbacks.end = [&](bool closed) { calls.push_back(closed ? "end closed" : "end open"); };
  svg::read_path(element, "d.svg", callbacks);
  const std::vector<std::string> expected = {
      "begin 0 0 #1", "line 10 0", "line 10 10", "end closed",
      // After Z a drawing command starts a new subpath from the last start.
      "begin 0 0 #2", "line 5 5", "end open",
      // m is relative to the current point; pairs after it are linetos.
      "begin 6 6 #3", "line 8 6", "arc 8 6 to 9 9 r 3 4 30 truefalse", "end open", "begin 20 20 #4",
      "end open"};
  EXPECT_EQ(calls, expected);
}

TEST(SvgDrawing, PointsAndTheirErrors) {
  svg::Element element;
  element.name = "polyline";
  element.line = 3;
  element.attributes = {{"points", "0,0 1e1-2 3 4"}};
  std::vector<svg::Point> points;
  svg::read_points(element, "d.svg", [&](const svg::Point& p) { points.push_back(p); });
  ASSERT_EQ(points.size(), 3u);  // "1e1-2" is two numbers
  EXPECT_EQ(points[1], svg::Point(10, -2));
  element.attributes = {{"points", "0,0 1"}};
  try {
    svg::read_points(element, "d.svg", [](const svg::Point&) {});
    ADD_FAILURE() << "no UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kFormat);
    EXPECT_NE(std::string(e.what()).find("d.svg:3: the <polyline>'s points hold an odd number"),
              std::string::npos);
  }
}

TEST(SvgDrawing, ProblemsNameTheLine) {
  EXPECT_EQ(message_of("<svg>\n<g>\n<line/>\n</svg>"),
            "d.svg:4: </svg> closes <g> (opened at line 2): the file is not well-formed XML; "
            "save it again as SVG");
  EXPECT_EQ(message_of("<svg>\n\n<g transform=\"spin(3)\"/></svg>"),
            "d.svg:3: transform=\"spin(3)\" of the <g> is not a transform list (matrix, "
            "translate, scale, rotate, skewX, skewY): fix it, and save again");
  EXPECT_EQ(message_of("  "), "d.svg: empty file: save the drawing as SVG");
}

}  // namespace
}  // namespace flatmorph::svg_drawing_test
