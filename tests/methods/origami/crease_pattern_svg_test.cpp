// Crease patterns drawn as SVG (issue 27, item 5): flatmorph's own pattern SVG reads back to the
// same sheet (exactly with data-fold-angle, to Origami Simulator's opacity otherwise); a pattern
// drawn by hand in Origami Simulator's style gives its faces and folds; the drawing is not
// mirrored; lines are cut at crossings and T-junctions; every bad drawing is a UserError naming
// its line.
#include "methods/origami/crease_pattern_svg.h"
#include "common/angles.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <regex>

#include "common/error.h"
#include "examples/origami_examples.h"
#include "mesh/polygon.h"
#include "methods/origami/net_svg.h"
#include "methods/origami/unfold.h"

namespace flatmorph::crease_pattern_svg_test {
namespace {

CreasePattern net_of(const std::string& solid) {
  return crease_pattern_of_net(unfold(polyhedron_example(solid, 20)), 0, "net 1", kDegree);
}

// A drawing of 100 × 100 mm, one user unit a mm, `body` from line 2.
std::string drawing(const std::string& body) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100mm\" height=\"100mm\" "
         "viewBox=\"0 0 100 100\">\n" +
         body + "\n</svg>\n";
}

constexpr const char* kSquare =
    R"(<rect x="0" y="0" width="100" height="100" fill="none" stroke="#000000"/>)";

CreasePattern read(const std::string& text, std::vector<std::string>* warnings = nullptr) {
  return read_crease_pattern_svg(text, "p.svg", {}, warnings);
}

UserError error_of(const std::string& text) {
  try {
    read(text);
  } catch (const UserError& e) {
    return e;
  }
  ADD_FAILURE() << "no UserError";
  return UserError(ErrorCategory::kFile, "");
}

Eigen::MatrixX2d polygon(const CreasePattern& p, int f) {
  Eigen::MatrixX2d out(static_cast<Eigen::Index>(p.faces[f].size()), 2);
  for (size_t k = 0; k < p.faces[f].size(); ++k) out.row(k) = p.V.row(p.faces[f][k]);
  return out;
}

std::vector<double> sorted_areas(const CreasePattern& p) {
  std::vector<double> areas;
  for (int f = 0; f < p.num_faces(); ++f) areas.push_back(signed_area(polygon(p, f)));
  std::sort(areas.begin(), areas.end());
  return areas;
}

// What every pattern the reader gives must satisfy: faces counter-clockwise; each crease runs
// v0 → v1 around its left face (and back around its right one); every side of every face is one
// crease; the tree reaches every face through folds, each after its parent.
void expect_consistent(const CreasePattern& p) {
  std::vector<int> sides(static_cast<size_t>(p.num_faces()), 0);
  for (int f = 0; f < p.num_faces(); ++f) EXPECT_GT(signed_area(polygon(p, f)), 0) << f;
  const auto runs = [&](int f, int a, int b) {
    const std::vector<int>& face = p.faces[f];
    for (size_t k = 0; k < face.size(); ++k) {
      if (face[k] == a && face[(k + 1) % face.size()] == b) return true;
    }
    return false;
  };
  for (const Crease& c : p.creases) {
    EXPECT_TRUE(runs(c.left, c.v0, c.v1));
    ++sides[c.left];
    if (c.right >= 0) {
      EXPECT_TRUE(runs(c.right, c.v1, c.v0));
      ++sides[c.right];
      EXPECT_NE(c.kind, CreaseKind::kBorder);
    } else {
      EXPECT_EQ(c.kind, CreaseKind::kBorder);
    }
  }
  for (int f = 0; f < p.num_faces(); ++f) EXPECT_EQ(sides[f], static_cast<int>(p.faces[f].size()));
  ASSERT_EQ(p.fold_order.size(), static_cast<size_t>(p.num_faces()));
  EXPECT_EQ(p.fold_order[0], p.root);
  std::vector<bool> seen(static_cast<size_t>(p.num_faces()), false);
  for (int f : p.fold_order) {
    if (f != p.root) {
      ASSERT_GE(p.parent_crease[f], 0);
      EXPECT_TRUE(seen[p.other_face(p.parent_crease[f], f)]);
    }
    seen[f] = true;
    EXPECT_EQ(p.solid_face[f], -1);
  }
}

// How many creases of `a`, moved by the translation that matches the two sheets' lower left
// corners, are creases of `b` (the same ends), checking each pair's kind and angle.
int matching_creases(const CreasePattern& a, const CreasePattern& b, double angle_tolerance = 0) {
  const Eigen::RowVector2d shift = b.V.colwise().minCoeff() - a.V.colwise().minCoeff();
  int matches = 0;
  for (const Crease& c : a.creases) {
    const Eigen::RowVector2d p = a.V.row(c.v0) + shift, q = a.V.row(c.v1) + shift;
    for (const Crease& d : b.creases) {
      const Eigen::RowVector2d r = b.V.row(d.v0), s = b.V.row(d.v1);
      if (((p - r).norm() < 1e-9 && (q - s).norm() < 1e-9) ||
          ((p - s).norm() < 1e-9 && (q - r).norm() < 1e-9)) {
        ++matches;
        if (angle_tolerance > 0) {
          EXPECT_EQ(c.kind, d.kind);
          EXPECT_NEAR(c.fold_angle, d.fold_angle, angle_tolerance);
        }
      }
    }
  }
  return matches;
}

// `b` is `a` moved by one translation (the reader measures from the drawing's corner): the same
// faces, and every crease of `a` is one of `b` with the same kind and its angle within
// `angle_tolerance` rad.
void expect_same_sheet(const CreasePattern& a, const CreasePattern& b, double angle_tolerance) {
  ASSERT_EQ(a.num_faces(), b.num_faces());
  ASSERT_EQ(a.creases.size(), b.creases.size());
  ASSERT_EQ(a.V.rows(), b.V.rows());
  const std::vector<double> areas_a = sorted_areas(a), areas_b = sorted_areas(b);
  for (size_t f = 0; f < areas_a.size(); ++f) EXPECT_NEAR(areas_a[f], areas_b[f], 1e-9);
  EXPECT_EQ(matching_creases(a, b, angle_tolerance), static_cast<int>(a.creases.size()));
}

// --- Round trips
// -----------------------------------------------------------------------------------

TEST(CreasePatternSvg, TheCubesNetReadsBackExactlyFromItsOwnSvg) {
  const CreasePattern cube = net_of("cube");
  const CreasePattern back = read(crease_pattern_svg(cube));
  expect_consistent(back);
  expect_same_sheet(cube, back, 1e-12);
  EXPECT_EQ(back.name, "p.svg");
  int mountains = 0;
  for (const Crease& c : back.creases) mountains += c.kind == CreaseKind::kMountain;
  EXPECT_EQ(mountains, 5);
  // The tree spans the sheet through its five folds.
  EXPECT_EQ(std::count(back.parent_crease.begin(), back.parent_crease.end(), -1), 1);
}

TEST(CreasePatternSvg, OpacityAloneGivesTheAnglesToHalfADegree) {
  for (const std::string solid : {"tetrahedron", "dodecahedron"}) {
    SCOPED_TRACE(solid);
    const CreasePattern net = net_of(solid);
    const std::string svg =
        std::regex_replace(crease_pattern_svg(net), std::regex(" data-fold-angle=\"[^\"]*\""), "");
    ASSERT_EQ(svg.find("data-fold-angle"), std::string::npos);
    const CreasePattern back = read(svg);
    expect_consistent(back);
    expect_same_sheet(net, back, 0.5 * kDegree);
  }
}

TEST(CreasePatternSvg, ASquareWithARedDiagonalAtHalfOpacityIsTwoTrianglesAndAMountain) {
  // Drawn as Origami Simulator's users draw: colours and opacity only, no size.
  const std::string svg = R"(<svg xmlns="http://www.w3.org/2000/svg">
<rect x="0" y="0" width="100" height="100" fill="none" stroke="black"/>
<line x1="0" y1="0" x2="100" y2="100" style="stroke: #f00; stroke-opacity: 0.5"/>
</svg>)";
  std::vector<std::string> warnings;
  const CreasePattern p = read(svg, &warnings);
  expect_consistent(p);
  EXPECT_EQ(p.num_faces(), 2);
  EXPECT_EQ(p.V.rows(), 4);
  ASSERT_EQ(p.creases.size(), 5u);
  for (double area : sorted_areas(p)) EXPECT_NEAR(area, 5000, 1e-9);
  int mountains = 0;
  for (int c = 0; c < 5; ++c) {
    if (p.creases[c].kind != CreaseKind::kMountain) continue;
    ++mountains;
    EXPECT_NEAR(p.creases[c].fold_angle, -kPi / 2, 1e-12);
    EXPECT_TRUE(p.is_hinge(c));
  }
  EXPECT_EQ(mountains, 1);
  ASSERT_EQ(warnings.size(), 1u);  // no size: a user unit is a mm
  EXPECT_NE(warnings[0].find("one user unit read as 1 mm"), std::string::npos);
}

TEST(CreasePatternSvg, TheDrawingIsSeenFromAboveNotMirrored) {
  // On screen: the right angle at the top left, the long side to the right, the short side
  // down; a blue (valley) fold from the corner to the middle of the long slope, at 45°.
  const CreasePattern p = read(drawing(R"(<polygon points="0,0 40,0 0,20" stroke="#000"/>
<line x1="0" y1="0" x2="20" y2="10" stroke="blue" opacity="0.25"/>)"));
  expect_consistent(p);
  ASSERT_EQ(p.num_faces(), 2);
  // Plate y = −SVG y: the short side goes down on the plate too.
  const auto index_of = [&](double x, double y) {
    for (Eigen::Index v = 0; v < p.V.rows(); ++v) {
      if ((p.V.row(v) - Eigen::RowVector2d(x, y)).norm() < 1e-12) return static_cast<int>(v);
    }
    return -1;
  };
  const int o = index_of(0, 0), a = index_of(40, 0), b = index_of(0, -20), m = index_of(20, -10);
  ASSERT_TRUE(o >= 0 && a >= 0 && b >= 0 && m >= 0);
  // The face with the far corner runs o → m → a counter-clockwise: the drawn handedness.
  for (const std::vector<int>& face : p.faces) {
    if (std::find(face.begin(), face.end(), a) == face.end()) continue;
    const auto at = std::find(face.begin(), face.end(), o) - face.begin();
    EXPECT_EQ(face[(at + 1) % 3], m);
    EXPECT_EQ(face[(at + 2) % 3], a);
  }
  for (const Crease& c : p.creases) {
    if (c.kind == CreaseKind::kValley) {
      EXPECT_NEAR(c.fold_angle, kPi / 4, 1e-12);
    }
  }
}

TEST(CreasePatternSvg, TheWritersPictureIsTheSheetFromAbove) {
  // An L of three squares has no mirror symmetry in y: read back through flatmorph's own SVG it
  // is itself moved, not its mirror image.
  const CreasePattern l = read(drawing(R"(<polygon points="0,0 20,0 20,10 10,10 10,20 0,20"
  stroke="#000"/>
<polyline points="10,0 10,10 0,10" stroke="#00f" stroke-opacity="0.5"/>)"));
  expect_consistent(l);
  ASSERT_EQ(l.num_faces(), 3);
  const CreasePattern back = read(crease_pattern_svg(l));
  expect_same_sheet(l, back, 1e-12);
  CreasePattern mirror = l;
  mirror.V.col(1) *= -1;
  for (std::vector<int>& face : mirror.faces) std::reverse(face.begin(), face.end());
  for (Crease& c : mirror.creases) std::swap(c.v0, c.v1);
  EXPECT_LT(matching_creases(mirror, back), static_cast<int>(l.creases.size()));
}

// --- The arrangement
// ---------------------------------------------------------------------------------

TEST(CreasePatternSvg, LinesAreCutAtCrossingsAndTJunctions) {
  // Two diagonals: four triangles meeting in the middle.
  const CreasePattern x = read(drawing(std::string(kSquare) + R"(
<line x1="0" y1="0" x2="100" y2="100" stroke="#ff0000" stroke-opacity="0.5"/>
<line x1="100" y1="0" x2="0" y2="100" stroke="#0000ff" stroke-opacity="0.5"/>)"));
  expect_consistent(x);
  EXPECT_EQ(x.num_faces(), 4);
  EXPECT_EQ(x.creases.size(), 8u);
  for (double area : sorted_areas(x)) EXPECT_NEAR(area, 2500, 1e-9);
  // A fold down the middle and one from the left side ending on it (0.004 mm short: snapped),
  // and a path whose segments overshoot the outline by 2 mm.
  std::vector<std::string> warnings;
  const CreasePattern t = read(drawing(std::string(kSquare) + R"(
<path d="M 50 -2 V 102" stroke="#0000ff" stroke-opacity="0.5" id="middle"/>
<line x1="0" y1="50" x2="49.996" y2="50" stroke="#ff0000" stroke-opacity="1"/>)"),
                               &warnings);
  expect_consistent(t);
  EXPECT_EQ(t.num_faces(), 3);
  EXPECT_EQ(t.creases.size(), 3u + 7u);  // the middle in two, the side fold; seven outline sides
  const std::vector<double> areas = sorted_areas(t);
  // The side fold's end moved onto the middle one: that stays straight.
  EXPECT_NEAR(areas[0], 2500, 1e-9);
  EXPECT_NEAR(areas[1], 2500, 1e-9);
  EXPECT_NEAR(areas[2], 5000, 1e-9);
  // The root is the largest face.
  EXPECT_NEAR(signed_area(polygon(t, t.root)), 5000, 1e-9);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("p.svg:3: a piece of the blue (valley) <path id=\"middle\"> outside "
                              "the sheet (around",
                              0),
            0u);
}

TEST(CreasePatternSvg, TheTreeTakesTheLongestFoldsFromTheLargestFace) {
  // A 40 × 30 face, and right of it a 20 × 20 face over a 20 × 10 one: the mountain between
  // the left face and the right ones is cut in two (20 and 10 mm) where the valley meets it.
  const CreasePattern p = read(drawing(R"(<polygon points="0,0 60,0 60,30 0,30" stroke="#000"/>
<line x1="40" y1="0" x2="40" y2="30" stroke="#f00" stroke-opacity="0.5"/>
<line x1="40" y1="10" x2="60" y2="10" stroke="#00f" stroke-opacity="0.5"/>)"));
  expect_consistent(p);
  ASSERT_EQ(p.num_faces(), 3);
  EXPECT_NEAR(signed_area(polygon(p, p.root)), 1200, 1e-9);
  // The 20 × 20 face hangs on the 20 mm mountain; the small one on the 20 mm valley rather than
  // on the 10 mm mountain.
  for (int f = 0; f < 3; ++f) {
    if (f == p.root) continue;
    const Crease& c = p.creases[p.parent_crease[f]];
    const double length = (p.V.row(c.v1) - p.V.row(c.v0)).norm();
    EXPECT_NEAR(length, 20, 1e-9);
    const double area = signed_area(polygon(p, f));
    EXPECT_EQ(c.kind, area > 300 ? CreaseKind::kMountain : CreaseKind::kValley);
  }
  EXPECT_EQ(p.other_face(p.parent_crease[p.fold_order[1]], p.fold_order[1]), p.root);
}

TEST(CreasePatternSvg, RandomChordsCutTheSquareIntoFacesThatTileIt) {
  // Chords from side to side of a square, crossing each other anywhere: whatever the
  // arrangement, its faces are consistent and cover the square exactly once.
  std::mt19937 random(27);
  std::uniform_real_distribution<double> along(1, 99);
  for (int drawing_index = 0; drawing_index < 20; ++drawing_index) {
    SCOPED_TRACE(drawing_index);
    std::string body = kSquare;
    const auto on_side = [&](int side) {
      const double t = along(random);
      const double xy[4][2] = {{t, 0}, {100, t}, {t, 100}, {0, t}};
      return std::pair{xy[side][0], xy[side][1]};
    };
    for (int k = 0; k < 8; ++k) {
      const int s = static_cast<int>(random() % 4),
                t = (s + 1 + static_cast<int>(random() % 3)) % 4;
      const auto [x1, y1] = on_side(s);
      const auto [x2, y2] = on_side(t);
      body += fmt::format(
          "\n<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" "
          "stroke-opacity=\"0.5\"/>",
          x1, y1, x2, y2, k % 2 == 0 ? "#f00" : "#00f");
    }
    const CreasePattern p = read(drawing(body));
    expect_consistent(p);
    double total = 0;
    for (double area : sorted_areas(p)) total += area;
    EXPECT_NEAR(total, 10000, 1e-6);
    EXPECT_GE(p.num_faces(), 9);  // eight chords cut at least eight times
  }
}

// --- Refusals
// -------------------------------------------------------------------------------------

TEST(CreasePatternSvg, BadDrawingsAreRefusedNamingTheLine) {
  const auto message = [](const std::string& body) {
    return std::string(error_of(drawing(body)).what());
  };
  EXPECT_EQ(
      message(R"(<line x1="0" y1="0" x2="10" y2="10" stroke="#ff0000"/>)"),
      "p.svg: no closed outline: draw the sheet's outline as a closed black path, polygon or "
      "rectangle (or black lines that meet), its folds red (mountain) and blue (valley) from side "
      "to side, and save again");
  EXPECT_EQ(message(std::string(kSquare) + "\n" +
                    R"(<line id="short" x1="0" y1="0" x2="50" y2="50" stroke="#ff0000"/>)"),
            "p.svg:3: the red (mountain) <line id=\"short\"> ends inside a face around (25.0000, "
            "-25.0000) mm, short of the outline or another crease: a fold runs from side to side "
            "of its face; extend it to meet a line (within 0.01 mm), or delete it, and save again");
  EXPECT_EQ(message(std::string(kSquare) + "\n" + R"(<line x2="100" stroke="#123456"/>)"),
            "p.svg:3: the <line> has stroke \"#123456\", which is no crease colour: use Origami "
            "Simulator's black #000000 (outline), red #ff0000 (mountain), blue #0000ff (valley), "
            "yellow #ffff00 (flat) or green #00ff00 (cut), and save again");
  EXPECT_NE(message(std::string(kSquare) + "\n\n" + R"(<line x2="100" stroke="#f0f"/>)")
                .find("p.svg:4: the <line> is magenta, Origami Simulator's undriven hinge"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<rect x="20" y="20" width="10" height="10" stroke="#f00"/>)")
                .find("p.svg:3: the red (mountain) <rect> lies inside a face (around"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<rect x="200" y="20" width="10" height="10" stroke="#000"/>)")
                .find("p.svg:3: the black (outline) <rect> belongs to a second sheet, apart from "
                      "the one drawn at line 2 (2 sheets in all)"),
            std::string::npos);
  EXPECT_NE(message(R"(<polyline points="0,0 100,0 100,100 0,100" stroke="#000"/>
<line x1="0" y1="100" x2="0" y2="0" stroke="#00f"/>)")
                .find("p.svg:3: the blue (valley) <line> lies on the sheet's outline around "
                      "(0.0000, -50.0000) mm"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<line x1="50" y1="0" x2="50" y2="100" stroke="#000"/>)")
                .find("p.svg:3: the black (outline) <line> runs between two faces"),
            std::string::npos);
  // A fold joining the outline to a closed loop inside: the loop is a face, the fold cuts
  // nothing.
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<polygon points="40,40 60,40 50,60" stroke="#f00"/>
<line x1="0" y1="40" x2="40" y2="40" stroke="#00f"/>)")
                .find("p.svg:4: the blue (valley) <line> runs inside a face around (20.0000, "
                      "-40.0000) mm without cutting it in two"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<line x2="100" y2="100" stroke="#f00" data-fold-angle="30"/>)")
                .find("p.svg:3: the <line> is red (mountain) but its data-fold-angle is 30°"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<line x2="100" y2="100" stroke="#f00" data-fold-angle="200"/>)")
                .find("data-fold-angle=\"200\" of the <line> is not an angle"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<line x2="100" y2="100" stroke="#f00" stroke-opacity="1.5"/>)")
                .find("p.svg:3: the <line>'s opacity \"1.5\" is not a number from 0 to 1"),
            std::string::npos);
  EXPECT_NE(message(std::string(kSquare) + "\n" + R"(<circle r="5" stroke="#f00"/>)")
                .find("p.svg:3: <circle> elements are not read"),
            std::string::npos);
  EXPECT_NE(
      message(std::string(kSquare) + "\n" + R"(<path d="M0 0 A 5 5 0 0 1 10 10" stroke="#f00"/>)")
          .find("p.svg:3: the <path> has an arc"),
      std::string::npos);
  // A triangle touching the outline at one corner: the face around it touches itself there.
  EXPECT_NE(
      message(std::string(kSquare) + "\n" + R"(<polygon points="10,30 20,10 0,30" stroke="#00f"/>)")
          .find("touches itself at (0.0000, -30.0000) mm"),
      std::string::npos);
  // Two squares meeting at a corner only.
  EXPECT_NE(message(R"(<polygon points="0,0 10,0 10,10 0,10" stroke="#000"/>
<polygon points="10,10 20,10 20,20 10,20" stroke="#000"/>)")
                .find("meet only at corners"),
            std::string::npos);
  // Lines drawn over each other that disagree.
  EXPECT_NE(message(std::string(kSquare) + "\n" +
                    R"(<line x2="100" y2="100" stroke="#f00" stroke-opacity="0.5"/>
<line x1="25" y1="25" x2="75" y2="75" stroke="#f00" stroke-opacity="0.4"/>)")
                .find("p.svg:4: the red (mountain) <line> lies on the red (mountain) <line> at "
                      "line 3"),
            std::string::npos);
}

TEST(CreasePatternSvg, CategoriesAndOptions) {
  EXPECT_EQ(error_of(drawing(std::string(kSquare) + "\n" + R"(<line x2="100" stroke="#123"/>)"))
                .category(),
            ErrorCategory::kFormat);
  EXPECT_EQ(error_of(drawing(R"(<line x2="10" y2="10" stroke="#ff0000"/>)")).category(),
            ErrorCategory::kTopology);
  CreasePatternReadOptions options;
  options.snap_tolerance = 0;
  try {
    read_crease_pattern_svg(drawing(kSquare), "p.svg", options);
    ADD_FAILURE() << "no UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
  }
  // Few segments allowed: a resource.
  options = {};
  options.max_segments = 3;
  try {
    read_crease_pattern_svg(drawing(kSquare), "p.svg", options);
    ADD_FAILURE() << "no UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kResource);
  }
  // A fold under the flat angle is a flat crease, and a fill without a stroke is left out.
  std::vector<std::string> warnings;
  const CreasePattern flat = read(drawing(std::string(kSquare) + "\n" +
                                          R"(<rect width="100" height="100" fill="white"/>
<line x2="100" y2="100" stroke="#00f" data-fold-angle="0.5"/>)"),
                                  &warnings);
  EXPECT_EQ(flat.num_faces(), 2);
  int flats = 0;
  for (const Crease& c : flat.creases) flats += c.kind == CreaseKind::kFlat && c.fold_angle == 0;
  EXPECT_EQ(flats, 1);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "p.svg: 1 elements without a stroke (fills, backgrounds) are not read");
}

}  // namespace
}  // namespace flatmorph::crease_pattern_svg_test
