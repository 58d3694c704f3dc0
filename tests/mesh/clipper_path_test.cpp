#include "mesh/clipper_path.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace flatmorph::clipper_path_test {
namespace {

namespace cl = ClipperLib;

cl::Path square(cl::cInt x0, cl::cInt y0, cl::cInt side) {
  return {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
}

// Ends of a piece, from lower to higher x.
std::pair<cl::IntPoint, cl::IntPoint> ends(const cl::Path& piece) {
  cl::IntPoint a = piece.front(), b = piece.back();
  if (b.X < a.X) std::swap(a, b);
  return {a, b};
}

// A horizontal line across a 10 x 10 square keeps its part inside, from side to side.
TEST(ClipperPath, ClipOpenPathKeepsThePartInside) {
  const cl::Paths pieces = clip_open_path({{-5, 4}, {15, 4}}, {square(0, 0, 10)});
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(ends(pieces[0]).first, cl::IntPoint(0, 4));
  EXPECT_EQ(ends(pieces[0]).second, cl::IntPoint(10, 4));
}

// Two squares side by side with a gap: two pieces; a square with a hole (clockwise): the line is
// cut around it; a line wholly outside: nothing.
TEST(ClipperPath, ClipOpenPathCutsAtGapsAndHoles) {
  cl::Paths pieces = clip_open_path({{-5, 4}, {35, 4}}, {square(0, 0, 10), square(20, 0, 10)});
  ASSERT_EQ(pieces.size(), 2u);
  std::sort(pieces.begin(), pieces.end(),
            [](const cl::Path& a, const cl::Path& b) { return ends(a).first.X < ends(b).first.X; });
  EXPECT_EQ(ends(pieces[0]).first, cl::IntPoint(0, 4));
  EXPECT_EQ(ends(pieces[0]).second, cl::IntPoint(10, 4));
  EXPECT_EQ(ends(pieces[1]).first, cl::IntPoint(20, 4));
  EXPECT_EQ(ends(pieces[1]).second, cl::IntPoint(30, 4));

  cl::Path hole = square(4, 2, 2);
  std::reverse(hole.begin(), hole.end());
  pieces = clip_open_path({{-5, 3}, {15, 3}}, {square(0, 0, 10), hole});
  ASSERT_EQ(pieces.size(), 2u);
  for (const cl::Path& piece : pieces) {
    EXPECT_GE(piece.size(), 2u);
    const auto [a, b] = ends(piece);
    EXPECT_TRUE((a.X == 0 && b.X == 4) || (a.X == 6 && b.X == 10)) << a.X << " " << b.X;
  }

  EXPECT_TRUE(clip_open_path({{-5, 20}, {15, 20}}, {square(0, 0, 10)}).empty());
}

}  // namespace
}  // namespace flatmorph::clipper_path_test
