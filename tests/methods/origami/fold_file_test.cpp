// The FOLD file of a crease pattern (notes §9): what the spec asks for, read back with a JSON
// parser: counts, assignments, signed angles in degrees, counter-clockwise faces whose sides are
// edges, the hinge designs under flatmorph's prefix, and the folded frame landing on the solid.
#include "methods/origami/fold_file.h"
#include "common/angles.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "examples/origami_examples.h"
#include "methods/origami/unfold.h"

namespace flatmorph::fold_file_test {
namespace {

struct Cube {
  Unfolding unfolding = unfold(polyhedron_example("cube", 20));
  CreasePattern pattern = crease_pattern_of_net(unfolding, 0, "net 1", kPi / 180);
};

// Every mountain and valley of the tree as a hinge on an arc of 5 mm (W = r|θ|), case A.
std::vector<HingeDesign> hinges_of(const CreasePattern& pattern) {
  std::vector<HingeDesign> hinges;
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    if (!pattern.is_hinge(c)) continue;
    HingeDesign h;
    h.crease = c;
    h.fold_angle = pattern.creases[c].fold_angle;
    h.radius = 5;
    h.width = 5 * std::abs(h.fold_angle);
    h.pla_on_bed = true;
    h.pla_speed = 150;
    hinges.push_back(h);
  }
  return hinges;
}

TEST(FoldFile, TheCubesNetAsTheSpecAsks) {
  const Cube cube;
  const nlohmann::json j = nlohmann::json::parse(fold_json(cube.pattern));
  EXPECT_EQ(j.at("file_spec").get<double>(), 1.2);
  EXPECT_EQ(j.at("file_creator"), "flatmorph");
  EXPECT_EQ(j.at("frame_classes"), nlohmann::json::array({"creasePattern"}));
  EXPECT_EQ(j.at("frame_attributes"), nlohmann::json::array({"2D"}));
  EXPECT_EQ(j.at("frame_unit"), "mm");
  EXPECT_FALSE(j.contains("file_frames"));
  EXPECT_FALSE(j.contains("edges_flatmorph:actuatorWidth"));
  const auto& coords = j.at("vertices_coords");
  const auto& edges = j.at("edges_vertices");
  const auto& assignment = j.at("edges_assignment");
  const auto& angle = j.at("edges_foldAngle");
  const auto& faces = j.at("faces_vertices");
  ASSERT_EQ(coords.size(), 14u);
  ASSERT_EQ(edges.size(), 19u);
  ASSERT_EQ(assignment.size(), 19u);
  ASSERT_EQ(angle.size(), 19u);
  ASSERT_EQ(faces.size(), 6u);
  // The coordinates are the pattern's to the bit.
  for (size_t v = 0; v < coords.size(); ++v) {
    ASSERT_EQ(coords[v].size(), 2u);
    EXPECT_EQ(coords[v][0].get<double>(), cube.pattern.V(v, 0));
    EXPECT_EQ(coords[v][1].get<double>(), cube.pattern.V(v, 1));
  }
  int mountains = 0, borders = 0;
  for (size_t e = 0; e < edges.size(); ++e) {
    if (assignment[e] == "M") {
      ++mountains;
      EXPECT_NEAR(angle[e].get<double>(), -90, 1e-9);  // degrees, a mountain negative
    } else {
      EXPECT_EQ(assignment[e], "B");
      ++borders;
      EXPECT_EQ(angle[e].get<double>(), 0);
    }
  }
  EXPECT_EQ(mountains, 5);
  EXPECT_EQ(borders, 14);
  // Faces counter-clockwise seen from +z, each side an edge: borders once, folds from both sides.
  std::vector<int> uses(edges.size(), 0);
  double total = 0;
  for (const auto& face : faces) {
    double twice = 0;
    for (size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      twice += coords[a][0].get<double>() * coords[b][1].get<double>() -
               coords[b][0].get<double>() * coords[a][1].get<double>();
      int found = 0;
      for (size_t e = 0; e < edges.size(); ++e) {
        if ((edges[e][0] == a && edges[e][1] == b) || (edges[e][0] == b && edges[e][1] == a)) {
          ++uses[e];
          ++found;
        }
      }
      EXPECT_EQ(found, 1);
    }
    EXPECT_NEAR(twice / 2, 400, 1e-9);
    total += twice / 2;
  }
  EXPECT_NEAR(total, 2400, 1e-9);
  for (size_t e = 0; e < edges.size(); ++e) EXPECT_EQ(uses[e], assignment[e] == "B" ? 1 : 2);
}

TEST(FoldFile, HingeDesignsAndTheFoldedFrame) {
  const Cube cube;
  const std::vector<HingeDesign> hinges = hinges_of(cube.pattern);
  ASSERT_EQ(hinges.size(), 5u);
  // Per face of the sheet, its corners folded (fold_net numbers faces as the solid does).
  const std::vector<Eigen::MatrixX3d> by_solid = fold_net(cube.unfolding, 0, 1.0);
  std::vector<Eigen::MatrixX3d> folded;
  for (int f : cube.pattern.solid_face) folded.push_back(by_solid[f]);
  const std::string text = fold_json(cube.pattern, &hinges, &folded);
  EXPECT_EQ(text, fold_json(cube.pattern, &hinges, &folded));  // the same bytes every time
  const nlohmann::json j = nlohmann::json::parse(text);
  const auto& width = j.at("edges_flatmorph:actuatorWidth");
  const auto& stacking = j.at("edges_flatmorph:case");
  ASSERT_EQ(width.size(), 19u);
  for (int c = 0; c < 19; ++c) {
    if (cube.pattern.is_hinge(c)) {
      EXPECT_NEAR(width[c].get<double>(), 5 * kPi / 2, 1e-12);  // W = r|θ|
      EXPECT_EQ(j.at("edges_flatmorph:radius")[c].get<double>(), 5);
      EXPECT_EQ(j.at("edges_flatmorph:speed")[c].get<double>(), 150);
      EXPECT_EQ(stacking[c], "A");
    } else {
      EXPECT_TRUE(width[c].is_null());
      EXPECT_TRUE(stacking[c].is_null());
    }
  }
  ASSERT_EQ(j.at("file_frames").size(), 1u);
  const auto& frame = j.at("file_frames")[0];
  EXPECT_EQ(frame.at("frame_classes"), nlohmann::json::array({"foldedForm"}));
  EXPECT_EQ(frame.at("frame_attributes"), nlohmann::json::array({"3D"}));
  EXPECT_EQ(frame.at("frame_parent"), 0);
  EXPECT_EQ(frame.at("frame_inherit"), true);
  const auto& at = frame.at("vertices_coords");
  ASSERT_EQ(at.size(), 14u);
  // The 14 corners of the sheet close onto the cube's 8, a 20 mm box.
  std::vector<Eigen::Vector3d> corners;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const auto& p : at) {
    ASSERT_EQ(p.size(), 3u);
    const Eigen::Vector3d x(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    bool seen = false;
    for (const Eigen::Vector3d& c : corners) seen = seen || (c - x).norm() < 1e-9;
    if (!seen) corners.push_back(x);
  }
  EXPECT_EQ(corners.size(), 8u);
  EXPECT_NEAR((hi - lo).minCoeff(), 20, 1e-9);
  EXPECT_NEAR((hi - lo).maxCoeff(), 20, 1e-9);
}

TEST(FoldFile, AValleyIsPositiveAndAFlatCreaseZero) {
  CreasePattern p = Cube().pattern;
  int flipped = -1, flattened = -1;
  for (int c = 0; c < static_cast<int>(p.creases.size()); ++c) {
    if (p.creases[c].kind != CreaseKind::kMountain) continue;
    if (flipped < 0) {
      flipped = c;
      p.creases[c].kind = CreaseKind::kValley;
      p.creases[c].fold_angle = kPi / 3;
    } else if (flattened < 0) {
      flattened = c;
      p.creases[c].kind = CreaseKind::kFlat;
      p.creases[c].fold_angle = 0;
    }
  }
  const nlohmann::json j = nlohmann::json::parse(fold_json(p));
  EXPECT_EQ(j.at("edges_assignment")[flipped], "V");
  EXPECT_NEAR(j.at("edges_foldAngle")[flipped].get<double>(), 60, 1e-12);
  EXPECT_EQ(j.at("edges_assignment")[flattened], "F");
  EXPECT_EQ(j.at("edges_foldAngle")[flattened].get<double>(), 0);
}

TEST(FoldFile, InputsThatDoNotMatchThePatternAreBugs) {
  const Cube cube;
  std::vector<HingeDesign> hinges = hinges_of(cube.pattern);
  hinges.push_back(hinges[0]);
  EXPECT_THROW(fold_json(cube.pattern, &hinges), std::invalid_argument);
  hinges.back().crease = 99;
  EXPECT_THROW(fold_json(cube.pattern, &hinges), std::invalid_argument);
  std::vector<Eigen::MatrixX3d> folded(5);
  EXPECT_THROW(fold_json(cube.pattern, nullptr, &folded), std::invalid_argument);
}

}  // namespace
}  // namespace flatmorph::fold_file_test
