// The paper's Table 1 on the printed laminate, as issue 21 asks the test suite to hold it: the
// design with the paper's settings (faces, width, w_D, the paper's PLA, side and stretch chosen
// automatically) ends within 1.5 times the paper's "Dist. to optim." (average and maximum, % of the
// bounding-box diagonal) and closer than theta2 = 0. Designed from every initial stretch
// (`--stretch all`), the beetle and the top meet the paper's own figures and the face 1.5 times
// them. The benchmark (BM_Table1) holds the real bar and the times. Slow: a whole design per model
// (2-12 s in Release, 20-30 s from every stretch).
//
// Not here because they do not meet it (issue 21, item 3, docs/design.md): the hat ends at
// 0.56 / 3.27 % (0.45 / 2.71 % from every stretch) against 1.5 x 0.30 / 1.18 %, the face's
// automatic stretch at 0.5398 % against 1.5 x 0.36 = 0.54 %, a margin no rounding difference
// between machines should have to respect.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "mesh/io.h"
#include "methods/shrink_morph/design.h"
#include "methods/shrink_morph/paper_table1.h"
#include "test_support.h"

namespace flatmorph::table1_test {
namespace {

struct Table1Case {
  const char* name;
  bool every_stretch;  // --stretch all
  double factor;       // of the paper's distances
};

void PrintTo(const Table1Case& c, std::ostream* os) {
  *os << c.name << (c.every_stretch ? ", every stretch, " : ", ") << c.factor << " x the paper";
}

class Table1 : public ::testing::TestWithParam<Table1Case> {};

TEST_P(Table1, EndsWithinTheBarOfThePaper) {
  const testing::PaperModel& model = testing::paper_model(GetParam().name);
  const std::filesystem::path path =
      testing::shared_dir() / "meshes" / (std::string(model.name) + ".obj");
  DesignOptions options = testing::paper_design_options(model);
  if (GetParam().every_stretch) options.stretch_candidate = kEveryStretch;
  const Design d = design_shrink_morph(read_mesh(path).mesh, path.string(), options);
  const DesignMetrics& m = d.metrics;
  EXPECT_LE(m.dist_to_optim_avg_pct, GetParam().factor * model.paper_optim_avg);
  EXPECT_LE(m.dist_to_optim_max_pct, GetParam().factor * model.paper_optim_max);
  EXPECT_LT(m.dist_to_optim_avg_pct, m.dist_to_sim_avg_pct);
  EXPECT_LT(m.dist_to_optim_max_pct, m.dist_to_sim_max_pct);
}

INSTANTIATE_TEST_SUITE_P(
    Paper, Table1,
    ::testing::Values(Table1Case{"hemisphere-big", false, 1.5}, Table1Case{"saddle", false, 1.5},
                      Table1Case{"beetle", false, 1.5}, Table1Case{"top", false, 1.5},
                      Table1Case{"beetle", true, 1.0}, Table1Case{"top", true, 1.0},
                      Table1Case{"face", true, 1.5}),
    [](const ::testing::TestParamInfo<Table1Case>& info) {
      std::string name = info.param.name;
      for (char& c : name) {
        if (c == '-') c = '_';
      }
      return name + (info.param.every_stretch ? "_every_stretch" : "");
    });

}  // namespace
}  // namespace flatmorph::table1_test
