// Every method through the library's run pipeline alone (run/run.h), as a Python module or a web
// server calls it: no process, no command line. The results come back as data that agree with
// what the run folder holds, the print passes the safety check, progress names the stages, a bad
// option is refused before any work, and a cancel stops the run leaving nothing behind.
#include "run/run.h"

#include <gtest/gtest.h>

#include <limits>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "common/error.h"
#include "gcode/gcode_check.h"
#include "material/material.h"
#include "test_support.h"

namespace flatmorph::run_pipeline_test {
namespace {

namespace fs = std::filesystem;

struct MethodCase {
  std::string name;
  RunRequest request;
  std::string method;              // design.json's "method"
  std::vector<std::string> tools;  // the materials the G-code prints, tool by tool
  bool closes_loop = true;         // the pipeline simulates the first bed's G-code
};

RunRequest example_request(const std::string& example, MethodOptions options) {
  RunRequest request;
  request.input.example = example;
  request.options = std::move(options);
  return request;
}

// Small inputs, so that each method runs in a few seconds.
std::vector<MethodCase> method_cases() {
  std::vector<MethodCase> cases;
  {
    ShrinkMorphRunOptions o;
    o.faces = 1000;
    cases.push_back({"shrink_morph", example_request("dome", o), "shrink_morph", {"pla-paper"}});
  }
  {
    HeightFieldRunOptions o;
    o.diameter_mm = 90;
    o.height_mm = 15;
    o.upsample_length_mm = 4;
    cases.push_back({"heightfield", example_request("hill", o), "heightfield", {"pla-geodesy"}});
  }
  {
    TilesRunOptions o;
    o.mesh_edge_mm = 2;
    cases.push_back({"tiles", example_request("dome", o), "tiles", {"pla-geodesy"}});
  }
  {
    OrigamiRunOptions o;
    o.slicer = false;
    cases.push_back({"origami",
                     example_request("tetrahedron", o),
                     "origami",
                     {"pla-generic", "tpu-generic"},
                     false});
  }
  return cases;
}

class RunPipeline : public ::testing::TestWithParam<MethodCase> {};

TEST_P(RunPipeline, DesignsPrintsAndClosesTheLoopAsData) {
  const MethodCase& c = GetParam();
  std::vector<std::string> stages;
  RunControl control;
  control.progress = [&](const Progress& p) {
    if (stages.empty() || stages.back() != p.stage) stages.push_back(p.stage);
  };
  const RunResult result = run_design(c.request, control);
  const RunOutputs& run = result.outputs;

  EXPECT_EQ(method_name(c.request.options), c.method);
  EXPECT_EQ(result.record["method"], c.method);
  EXPECT_EQ(run.method, c.method);
  // design.json's metrics are the outputs' own, and every figure is in the generic list.
  EXPECT_EQ(result.record["metrics"].dump(), run.metrics.dump());
  EXPECT_EQ(run.metric_list.size(), result.record["metrics_list"].size());
  ASSERT_GT(run.plate.F.rows(), 0);
  EXPECT_GT(run.plate.stack.num_layers(), 0);

  // The print: checked safe for the printer and the materials it names, and its figures are the
  // ones the metrics report.
  ASSERT_TRUE(run.print.has_value());
  std::vector<Material> tools;
  for (const std::string& name : c.tools) tools.push_back(load_material(name));
  EXPECT_TRUE(check_gcode(run.print->gcode.text, result.printer, tools).empty());
  EXPECT_DOUBLE_EQ(run.metrics["print_time_s"].get<double>(), run.print->gcode.print_time);
  EXPECT_GT(run.print->gcode.print_time, 0);

  // The loop closed on the G-code: its predicted shape, on the vertices the G-code prints.
  EXPECT_EQ(run.gcode_predicted.has_value(), c.closes_loop);
  if (c.closes_loop) {
    EXPECT_EQ(run.gcode_predicted->V.rows(), run.gcode_predicted_deviation_mm.size());
    EXPECT_LE(run.gcode_predicted->V.rows(), run.plate.plate.rows());
    EXPECT_TRUE(run.metrics.contains("gcode_vs_fields_avg_pct"));
    EXPECT_NE(std::find(stages.begin(), stages.end(), "simulate"), stages.end());
  }
  // Every simulation says why it ended: "converged", or one sentence saying why not and what to
  // change (Shrink & Morph always simulates; the others say whether they did by sim_converged).
  if (c.method == "shrink_morph" || run.metrics.contains("sim_converged")) {
    ASSERT_TRUE(run.metrics.contains("sim_stop_reason"));
  }
  if (run.metrics.contains("sim_converged")) {
    EXPECT_EQ(run.metrics["sim_stop_reason"] == "converged",
              run.metrics["sim_converged"].get<bool>());
  }
  if (c.closes_loop) {
    EXPECT_EQ(run.metrics["gcode_sim_stop_reason"] == "converged",
              run.metrics["gcode_converged"].get<bool>());
  }
  EXPECT_FALSE(result.summary.empty());
  // Nothing was written: no "wrote" line.
  for (const std::string& line : result.summary) EXPECT_NE(line.rfind("wrote ", 0), 0u) << line;
}

INSTANTIATE_TEST_SUITE_P(Methods, RunPipeline, ::testing::ValuesIn(method_cases()),
                         [](const auto& info) { return info.param.name; });

// The folder holds what the run returns.
TEST(RunPipelineFolder, WritesTheRunItReturns) {
  MethodCase c = method_cases()[2];  // tiles: the quickest with a loop
  c.request.output = testing::scratch_dir() / "run";
  const RunResult result = run_design(c.request);
  EXPECT_EQ(testing::read_file(c.request.output / "design.json"), result.record.dump(2) + "\n");
  EXPECT_EQ(testing::read_file(c.request.output / "plate.gcode"), result.outputs.print->gcode.text);
  for (const RunFile& file : result.outputs.files) {
    EXPECT_EQ(testing::read_file(c.request.output / file.name), file.bytes) << file.name;
  }
  EXPECT_EQ(result.summary.back().rfind("wrote " + c.request.output.string() + ": ", 0), 0u);
}

// A bad option is refused before any stage starts, and nothing is written.
TEST(RunPipelineFolder, ABadOptionIsRefusedBeforeAnyWork) {
  ShrinkMorphRunOptions o;
  o.width_mm = -5;
  RunRequest request = example_request("dome", o);
  request.output = testing::scratch_dir() / "run";
  int reports = 0;
  RunControl control;
  control.progress = [&](const Progress&) { ++reports; };
  try {
    run_design(request, control);
    FAIL() << "a negative width was accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
    EXPECT_NE(std::string(e.what()).find("--width -5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(reports, 0);
  EXPECT_FALSE(fs::exists(request.output));
  for (double error : {-1.0, 90.0, std::numeric_limits<double>::quiet_NaN()}) {
    ShrinkMorphRunOptions bad;
    bad.path_error_deg = error;
    try {
      run_design(example_request("dome", bad), control);
      FAIL() << "--path-error " << error << " was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kOption);
      EXPECT_NE(std::string(e.what()).find("--path-error"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(reports, 0);
}

// A cancel from another thread (here: from the progress callback, after a few reports) stops the
// run at its next report; the folder it would have written is not there, and an earlier run's
// folder stays as it was.
TEST(RunPipelineFolder, ACancelStopsTheRunAndLeavesTheFolderAsItWas) {
  for (const MethodCase& base : method_cases()) {
    SCOPED_TRACE(base.name);
    MethodCase c = base;
    c.request.output = testing::scratch_dir() / ("run-" + c.name);
    fs::create_directories(c.request.output);
    {
      std::ofstream earlier(c.request.output / "design.json");
      earlier << "{\"earlier\": true}\n";
    }
    CancelToken token;
    int reports = 0;
    RunControl control;
    control.cancel = &token;
    control.progress = [&](const Progress&) {
      if (++reports == 3) token.cancel();
    };
    EXPECT_THROW(run_design(c.request, control), Cancelled);
    EXPECT_EQ(reports, 3);
    EXPECT_EQ(testing::read_file(c.request.output / "design.json"), "{\"earlier\": true}\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(c.request.output), fs::directory_iterator()), 1);
  }
}

}  // namespace
}  // namespace flatmorph::run_pipeline_test
