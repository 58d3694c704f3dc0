// The paper's six models (tests/methods/shrink_morph/paper_table1.h) for the benchmarks.
#pragma once

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "../tests/methods/shrink_morph/paper_table1.h"

namespace flatmorph {

using testing::kPaperModels;
using testing::paper_design_options;
using testing::PaperModel;

// The model's file in ../shared/meshes; empty (and the benchmark skipped) when it is missing.
inline std::filesystem::path paper_model_path(const PaperModel& model, benchmark::State& state) {
  state.SetLabel(model.name);
  const std::filesystem::path path =
      std::filesystem::path(FLATMORPH_SHARED_DIR) / "meshes" / (std::string(model.name) + ".obj");
  if (std::filesystem::exists(path)) return path;
  state.SkipWithError("../shared/meshes is not beside the project");
  return {};
}

}  // namespace flatmorph
