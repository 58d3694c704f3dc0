// The paper's six models with Shrink & Morph Table 1's settings and figures, for the tests and the
// benchmarks that measure against them.
#pragma once

#include <stdexcept>
#include <string>

#include "material/material.h"
#include "methods/shrink_morph/design.h"

namespace flatmorph::testing {

struct PaperModel {
  const char* name;  // ../shared/meshes/NAME.obj
  int faces;
  double width_mm;
  double w_D;
  // Which side is printed on top: the one design_shrink_morph chooses (docs/design.md, Table 1).
  bool flip;
  double paper_sim_avg, paper_sim_max;      // Table 1, "Dist. to sim."
  double paper_optim_avg, paper_optim_max;  // Table 1, "Dist. to optim."
  double paper_total_s;                     // Table 1, t_param + t_optim (6-core Xeon)
};

inline constexpr PaperModel kPaperModels[] = {
    {"hemisphere-big", 17152, 150, 0.1, false, 3.36, 10.28, 0.25, 3.02, 147},
    {"saddle", 2048, 100, 0.0, true, 2.20, 6.05, 0.47, 2.15, 4},
    {"beetle", 8448, 200, 0.0, true, 5.41, 16.23, 0.34, 1.41, 123},
    {"face", 3996, 200, 0.1, false, 2.81, 12.56, 0.36, 2.04, 50},
    {"top", 3584, 250, 0.0, true, 5.85, 45.62, 0.24, 2.95, 62},
    {"hat", 11008, 100, 0.1, false, 1.34, 9.31, 0.30, 1.18, 73},
};

// The model of that name; std::invalid_argument for any other name.
inline const PaperModel& paper_model(const std::string& name) {
  for (const PaperModel& model : kPaperModels) {
    if (name == model.name) return model;
  }
  throw std::invalid_argument("no paper model named " + name);
}

// The design options of Table 1 for `model`: the paper's PLA, width, w_D and face count; the
// printed side and the initial stretch chosen automatically, as `design` does.
inline DesignOptions paper_design_options(const PaperModel& model) {
  DesignOptions options;
  options.material = load_material("pla-paper");
  options.width_mm = model.width_mm;
  options.w_D = model.w_D;
  options.faces = model.faces;
  return options;
}

}  // namespace flatmorph::testing
