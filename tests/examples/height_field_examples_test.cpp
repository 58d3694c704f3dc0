// The built-in height fields: the sizes asked for, the number of peaks their names promise, and
// valid input for the self-rising method at the paper's sizes (Table 1: 146-181 mm across,
// 26-42 mm high) and at other resolutions.
#include "examples/height_field_examples.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/error.h"
#include "mesh/topology.h"

namespace flatmorph::height_field_examples_test {
namespace {

// Interior vertices higher than every neighbour.
std::vector<int> peaks(const HeightField& field) {
  const EdgeTopology topology = edge_topology(field.F);
  std::vector<char> is_peak(field.V.rows(), 1);
  for (const auto& loop : boundary_loops(field.F)) {
    for (int v : loop) is_peak[v] = 0;
  }
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int a = topology.edges(e, 0), b = topology.edges(e, 1);
    if (field.V(a, 2) <= field.V(b, 2)) is_peak[a] = 0;
    if (field.V(b, 2) <= field.V(a, 2)) is_peak[b] = 0;
  }
  std::vector<int> out;
  for (int v = 0; v < field.V.rows(); ++v) {
    if (is_peak[v]) out.push_back(v);
  }
  return out;
}

void expect_size(const HeightField& field, double diameter, double height,
                 const std::string& name) {
  const Eigen::VectorXd r = field.V.leftCols<2>().rowwise().norm();
  EXPECT_NEAR(2.0 * r.maxCoeff(), diameter, 1e-9) << name;
  EXPECT_EQ(field.V.col(2).maxCoeff(), height) << name;
  EXPECT_GE(field.V.col(2).minCoeff(), 0.0) << name;
  const auto loops = boundary_loops(field.F);
  ASSERT_EQ(loops.size(), 1u) << name;
  for (int v : loops.front()) {
    EXPECT_EQ(field.V(v, 2), 0.0) << name << ": boundary vertex " << v;
    EXPECT_NEAR(r[v], 0.5 * diameter, 1e-9) << name;
  }
}

TEST(HeightFieldExamples, NamesInOrder) {
  EXPECT_EQ(height_field_example_names(),
            (std::vector<std::string>{"hill", "saddle", "island", "ridge"}));
}

struct PaperSize {
  const char* name;
  double diameter, height;
  size_t peaks;
};

// Within the acceptance's 150-180 mm and 25-45 mm; hill, saddle and ridge are Table 1's Starfish,
// Hawaii and Bear.
TEST(HeightFieldExamples, AtThePaperSizesTheyHaveTheirPeaksAndPassTheCheck) {
  for (const PaperSize& p :
       {PaperSize{"hill", 175.2, 33.4, 1}, PaperSize{"saddle", 159.0, 34.7, 2},
        PaperSize{"island", 150.0, 37.5, 3}, PaperSize{"ridge", 176.8, 26.3, 1}}) {
    const HeightField field = height_field_example(p.name, {p.diameter, p.height, 2.0});
    expect_size(field, p.diameter, p.height, p.name);
    EXPECT_EQ(peaks(field).size(), p.peaks) << p.name;
    EXPECT_NO_THROW(check_height_field(field, p.name)) << p.name;
    EXPECT_EQ(field.colors.size(), 0);
  }
}

TEST(HeightFieldExamples, DefaultIsHawaiiSized) {
  const HeightField field = height_field_example("hill");
  expect_size(field, 160.0, 35.0, "hill");
  // 40 rings of 2 mm: 1 + 3 * 40 * 41 vertices.
  EXPECT_EQ(field.V.rows(), 1 + 3 * 40 * 41);
}

TEST(HeightFieldExamples, ValidAtEveryResolutionAndSizeTried) {
  for (const std::string& name : height_field_example_names()) {
    for (double resolution : {0.75, 1.0, 3.0, 5.0, 10.0}) {
      for (double diameter : {150.0, 180.0}) {
        const HeightField field = height_field_example(name, {diameter, 45.0, resolution});
        EXPECT_NO_THROW(check_height_field(field, name))
            << name << " at " << resolution << " mm, " << diameter << " mm";
      }
    }
  }
}

TEST(HeightFieldExamples, SaddleHasASaddleBetweenItsPeaks) {
  const HeightField field = height_field_example("saddle", {160.0, 35.0, 2.0});
  const std::vector<int> top = peaks(field);
  ASSERT_EQ(top.size(), 2u);
  // The peaks mirror each other across x = 0 on the x axis, and the centre between them is lower
  // than both but the highest point of the y axis.
  EXPECT_NEAR(field.V(top[0], 0), -field.V(top[1], 0), 1e-9);
  EXPECT_NEAR(field.V(top[0], 1), 0.0, 1e-9);
  EXPECT_EQ(field.V(top[0], 2), field.V(top[1], 2));
  EXPECT_EQ(field.V(0, 0), 0.0);  // vertex 0 is the centre
  EXPECT_LT(field.V(0, 2), field.V(top[0], 2) - 5.0);
  for (int v = 1; v < field.V.rows(); ++v) {
    if (std::abs(field.V(v, 0)) < 1e-9) {
      EXPECT_LE(field.V(v, 2), field.V(0, 2)) << v;
    }
  }
}

TEST(HeightFieldExamples, RidgeIsLongerThanWide) {
  const HeightField field = height_field_example("ridge", {160.0, 35.0, 1.0});
  // Half-height extents along x and y: the crest runs along x, 2.55 times as long.
  double along_x = 0.0, along_y = 0.0;
  for (int v = 0; v < field.V.rows(); ++v) {
    if (field.V(v, 2) < 17.5) continue;
    along_x = std::max(along_x, std::abs(field.V(v, 0)));
    along_y = std::max(along_y, std::abs(field.V(v, 1)));
  }
  EXPECT_NEAR(along_x / along_y, 0.7071 / 0.2769, 0.1);
}

TEST(HeightFieldExamples, Deterministic) {
  const HeightField a = height_field_example("island"), b = height_field_example("island");
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
}

TEST(HeightFieldExamples, RefusesUnknownNamesAndBadSizes) {
  try {
    height_field_example("volcano");
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
    EXPECT_NE(std::string(e.what()).find("choose one of hill, saddle, island, ridge"),
              std::string::npos)
        << e.what();
  }
  for (const HeightFieldExampleOptions& bad :
       {HeightFieldExampleOptions{-160.0, 35.0, 2.0}, HeightFieldExampleOptions{160.0, 0.0, 2.0},
        HeightFieldExampleOptions{160.0, 35.0, 30.0},
        HeightFieldExampleOptions{160.0, 35.0, 0.01}}) {
    EXPECT_THROW(height_field_example("hill", bad), UserError)
        << bad.diameter_mm << " " << bad.height_mm << " " << bad.resolution_mm;
  }
}

}  // namespace
}  // namespace flatmorph::height_field_examples_test
