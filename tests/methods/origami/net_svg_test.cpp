// The sheet's pictures (notes §9), read back through the shared SVG reader: the crease pattern
// in Origami Simulator's colours and opacities, straight under the root as its importer looks
// for them; the printed sheet's groups, actuators by case, hinge lines by fold, the outline to
// cut around faces and actuators, and the face numbers inside their faces.
#include "methods/origami/net_svg.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <regex>

#include "common/svg_drawing.h"
#include "examples/origami_examples.h"
#include "mesh/polygon.h"
#include "methods/origami/crease_pattern_svg.h"
#include "methods/origami/unfold.h"

namespace flatmorph::net_svg_test {
namespace {

struct Drawn {
  std::string group;  // the id of the group around it ("" at the root)
  std::string name;
  std::map<std::string, std::string> attributes;
  std::vector<Eigen::Vector2d> points;  // plate mm (y up), from the viewBox's corner
  size_t depth;                         // groups around it, the root included
};

std::vector<Drawn> drawn(const std::string& text) {
  std::vector<Drawn> out;
  std::vector<std::string> warnings;
  svg::read_drawing(
      text, "n.svg", "the sheet",
      [&](const svg::Shape& shape) {
        Drawn d;
        const std::string* id = shape.groups.back().find("id");
        d.group = id != nullptr ? *id : "";
        d.name = shape.name;
        d.depth = shape.groups.size();
        for (const svg::Attribute& a : shape.element.attributes) {
          d.attributes[std::string(a.name)] = a.value;
        }
        if (d.name == "polygon") {
          svg::read_points(shape.element, "n.svg",
                           [&](const svg::Point& p) { d.points.push_back(shape.map(p)); });
        } else if (d.name == "line") {
          for (const auto& [x, y] : {std::pair{"x1", "y1"}, std::pair{"x2", "y2"}}) {
            d.points.push_back(shape.map(
                svg::Point(*svg::number(d.attributes[x]), *svg::number(d.attributes[y]))));
          }
        } else if (d.name == "path") {
          svg::PathCallbacks callbacks;
          callbacks.begin = [&](const svg::Point& p, int) { d.points.push_back(shape.map(p)); };
          callbacks.line_to = [&](const svg::Point& p) { d.points.push_back(shape.map(p)); };
          callbacks.arc_to = [](const svg::Point&, const svg::Point&, const svg::ArcCommand&) {};
          callbacks.end = [](bool) {};
          svg::read_path(shape.element, "n.svg", callbacks);
        }
        out.push_back(std::move(d));
      },
      warnings);
  EXPECT_TRUE(warnings.empty());
  return out;
}

double area(const std::vector<Eigen::Vector2d>& points) {
  Eigen::MatrixX2d p(static_cast<Eigen::Index>(points.size()), 2);
  for (size_t i = 0; i < points.size(); ++i) p.row(static_cast<Eigen::Index>(i)) = points[i];
  return signed_area(p);
}

TEST(NetSvg, TheCreasePatternInOriginamiSimulatorsColours) {
  const CreasePattern cube =
      crease_pattern_of_net(unfold(polyhedron_example("cube", 20)), 0, "net 1", kPi / 180);
  const std::string text = crease_pattern_svg(cube);
  EXPECT_EQ(text, crease_pattern_svg(cube));
  const std::vector<Drawn> lines = drawn(text);
  ASSERT_EQ(lines.size(), cube.creases.size());
  for (size_t c = 0; c < lines.size(); ++c) {
    const Drawn& line = lines[c];
    EXPECT_EQ(line.name, "line");
    EXPECT_EQ(line.depth, 1u);  // the importer takes the root's children only
    const bool mountain = cube.creases[c].kind == CreaseKind::kMountain;
    EXPECT_EQ(line.attributes.at("stroke"), mountain ? "#ff0000" : "#000000");
    EXPECT_EQ(*svg::number(line.attributes.at("stroke-opacity")), mountain ? 0.5 : 1.0);
    EXPECT_EQ(line.attributes.count("data-fold-angle"), mountain ? 1u : 0u);
    if (mountain) {
      EXPECT_EQ(*svg::number(line.attributes.at("data-fold-angle")), -90);
    }
    EXPECT_NEAR((line.points[1] - line.points[0]).norm(), 20, 1e-12);  // mm: no scaling
  }
  // The root's size in mm is its viewBox's.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      text, m,
      std::regex("width=\"([0-9.]+)mm\" height=\"([0-9.]+)mm\" viewBox=\"[-0-9.]+ "
                 "[-0-9.]+ ([0-9.]+) ([0-9.]+)\"")));
  EXPECT_EQ(m[1], m[3]);
  EXPECT_EQ(m[2], m[4]);
}

// Two faces, 12 and 10 mm wide and 10 mm tall, joined by a mountain of 90°, as Algorithm 1 prints
// them with r = 5 mm: each face cut back by L/2 = 5 mm, the child moved back by δ = L − W, the
// actuator W = 5π/2 wide between them.
struct TwoFaces {
  CreasePattern pattern = read_crease_pattern_svg(
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="30mm" height="30mm" viewBox="0 0 30 30">
<polygon points="0,0 22,0 22,10 0,10" stroke="#000"/>
<line x1="12" y1="0" x2="12" y2="10" stroke="#f00" stroke-opacity="0.5"/></svg>)",
      "two.svg");
  ActuatedSheet sheet;
  double width = 5 * kPi / 2, shift = 10 - 5 * kPi / 2;

  static Eigen::MatrixX2d box(double x0, double x1, double y0, double y1) {
    Eigen::MatrixX2d p(4, 2);
    p << x0, y0, x1, y0, x1, y1, x0, y1;
    return p;
  }

  TwoFaces() {
    // The reader measures from the viewBox's top left corner: the sheet spans y from −10 to 0.
    const int root = pattern.root, child = 1 - root;
    sheet.name = "two";
    sheet.faces.resize(2);
    sheet.faces[root] = box(0, 7, -10, 0);
    sheet.faces[child] = box(17 - shift, 22 - shift, -10, 0);
    Actuator a;
    for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
      if (pattern.is_hinge(c)) a.hinge.crease = c;
    }
    a.hinge.fold_angle = -kPi / 2;
    a.hinge.radius = 5;
    a.hinge.width = width;
    a.hinge.pla_on_bed = true;
    a.parent_face = root;
    a.child_face = child;
    a.quad << 7, 0, 7, -10, 7 + width, -10, 7 + width, 0;
    a.across = Eigen::Vector2d(1, 0);
    sheet.actuators.push_back(a);
  }
};

TEST(NetSvg, ThePrintedSheetsGroups) {
  const TwoFaces two;
  ASSERT_NEAR(signed_area(two.sheet.faces[two.pattern.root]), 70, 1e-12);  // the left face
  const std::string text = net_svg(two.pattern, two.sheet);
  std::map<std::string, std::vector<Drawn>> by_group;
  for (Drawn& d : drawn(text)) by_group[d.group].push_back(std::move(d));
  for (const char* id : {"faces", "actuators", "hinges", "cut", "legend"}) {
    EXPECT_EQ(by_group.count(id), 1u) << id;
  }
  ASSERT_EQ(by_group["faces"].size(), 2u);
  ASSERT_EQ(by_group["actuators"].size(), 1u);
  const Drawn& actuator = by_group["actuators"][0];
  EXPECT_EQ(actuator.attributes.at("data-case"), "A");
  EXPECT_NEAR(area(actuator.points), 10 * two.width, 1e-3);
  // The hinge line runs down the middle of the strip, red for a mountain.
  ASSERT_EQ(by_group["hinges"].size(), 1u);
  const Drawn& hinge = by_group["hinges"][0];
  EXPECT_EQ(hinge.attributes.at("stroke"), "#ff0000");
  // The outline to cut: one loop around faces and actuator, its area theirs.
  ASSERT_EQ(by_group["cut"].size(), 1u);
  const std::vector<Eigen::Vector2d>& cut = by_group["cut"][0].points;
  EXPECT_NEAR(std::abs(area(cut)), 70 + 10 * two.width + 50, 1e-3);
  double left = 1e9, right = -1e9;
  for (const Eigen::Vector2d& p : cut) {
    left = std::min(left, p.x());
    right = std::max(right, p.x());
  }
  EXPECT_NEAR(right - left, 7 + two.width + 5, 1e-3);
  // Seen from above: the root (wider) face on the left, the hinge 7 + W/2 from the left end.
  EXPECT_NEAR(hinge.points[0].x() - left, 7 + two.width / 2, 1e-3);
  EXPECT_NEAR(hinge.points[1].x() - left, 7 + two.width / 2, 1e-3);
  EXPECT_NEAR(std::abs(hinge.points[1].y() - hinge.points[0].y()), 10, 1e-3);
  // Face numbers: index + 1, inside their faces, away from their sides.
  std::vector<double> number_x(2, 0);
  for (int f = 0; f < 2; ++f) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        text, m,
        std::regex("<text data-face=\"" + std::to_string(f) +
                   "\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" font-size=\"[0-9.]+\">([0-9]+)</text>")));
    EXPECT_EQ(m[3], std::to_string(f + 1));
    number_x[f] = std::stod(m[1]);
  }
  EXPECT_LT(number_x[two.pattern.root], number_x[1 - two.pattern.root]);
  EXPECT_NEAR(number_x[1 - two.pattern.root] - number_x[two.pattern.root],
              (17 - two.shift + 22 - two.shift) / 2 - 3.5, 0.1);
}

TEST(NetSvg, ASheetNotMadeFromThePatternIsABug) {
  TwoFaces two;
  two.sheet.faces.pop_back();
  EXPECT_THROW(net_svg(two.pattern, two.sheet), std::invalid_argument);
}

}  // namespace
}  // namespace flatmorph::net_svg_test
