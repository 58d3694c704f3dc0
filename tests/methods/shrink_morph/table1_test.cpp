// The paper's Table 1 on the printed laminate, as issue 21 asks the test suite to hold it: the
// design with the paper's settings (faces, width, w_D, the paper's PLA, side and stretch chosen
// automatically) ends within 1.5 times the paper's "Dist. to optim." (average and maximum, % of the
// bounding-box diagonal) and closer than theta2 = 0. The benchmark (BM_Table1) holds the real bar,
// the paper's own figures, and the times. Slow: a whole design per model (2-12 s in Release).
//
// Not here because they do not meet it yet (issue 21, item 3, open): the hat ends at
// 0.56 / 3.27 % against 1.5 x 0.30 / 1.18 %, and the face at 0.5398 % against 1.5 x 0.36 = 0.54 %,
// a margin no rounding difference between machines should have to respect.
#include <gtest/gtest.h>

#include <string>

#include "mesh/io.h"
#include "methods/shrink_morph/design.h"
#include "methods/shrink_morph/paper_table1.h"
#include "test_support.h"

namespace flatmorph {
namespace {

class Table1 : public ::testing::TestWithParam<const char*> {};

TEST_P(Table1, EndsWithinOneAndAHalfTimesThePaper) {
  const testing::PaperModel& model = testing::paper_model(GetParam());
  const std::filesystem::path path =
      testing::shared_dir() / "meshes" / (std::string(model.name) + ".obj");
  const Design d = design_shrink_morph(read_mesh(path).mesh, path.string(),
                                       testing::paper_design_options(model));
  const DesignMetrics& m = d.metrics;
  EXPECT_LE(m.dist_to_optim_avg_pct, 1.5 * model.paper_optim_avg);
  EXPECT_LE(m.dist_to_optim_max_pct, 1.5 * model.paper_optim_max);
  EXPECT_LT(m.dist_to_optim_avg_pct, m.dist_to_sim_avg_pct);
  EXPECT_LT(m.dist_to_optim_max_pct, m.dist_to_sim_max_pct);
}

INSTANTIATE_TEST_SUITE_P(Paper, Table1,
                         ::testing::Values("hemisphere-big", "saddle", "beetle", "top"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace flatmorph
