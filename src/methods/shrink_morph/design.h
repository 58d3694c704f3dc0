// The Shrink & Morph design pipeline as one library call (paper §3.2): prepare the target (repair,
// disk check, Loop subdivision), flatten it (plate and theta1, §3.2.1), simulate the plate printed
// with theta2 = 0 from the target, optimize theta2 (§3.2.2), and measure each stage (Table 1's
// columns). The `design` command only parses options, calls this and writes the files.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "material/material.h"
#include "mesh/mesh.h"
#include "methods/shrink_morph/flatten.h"
#include "methods/shrink_morph/optimize_theta2.h"
#include "plate/plate_design.h"
#include "simulate/distance.h"

namespace flatmorph {

enum class PrintedSide {
  kAutomatic,   // the side whose natural bending agrees with the target (printed_side_agreement)
  kNormalUp,    // the side the target's normals point to on top
  kNormalDown,  // ... on the bed (flatten.h's `flip`)
};

inline constexpr int kAutomaticStretch = -1;
// The flattening has several local minima, and which one the theta2 design lands closest from is
// told by no cheap measure (docs/design.md): only the design's own E ranks them.
inline constexpr int kEveryStretch = -2;

struct DesignOptions {
  double width_mm = 100.0;  // the plate's largest extent, mm
  double w_D = 0.0;         // Eq. 12 smoothing weight (dimensionless)
  // Which side of the target is printed on top: chosen by printed_side_agreement when automatic.
  PrintedSide side = PrintedSide::kAutomatic;
  // The flattening's initial stretch (FlattenOptions::stretch_candidate, 0 to 3, 45° apart),
  // kAutomaticStretch to choose it by the target's curvature (choose_initial_stretch), or
  // kEveryStretch to design from each of them and keep the lowest final objective E.
  int stretch_candidate = kAutomaticStretch;
  int faces = 10000;  // Loop-subdivide the target until it has at least this many faces
  int layers = 10;    // printed layers of material.layer_height mm: h = layers * height
  Material material;
  OptimizeTheta2Options optimize;  // w_M, w_L, stopping
  // The first pass (both sides designed one Loop step coarser when the curvature does not tell
  // the printed side) runs `optimize` with these two changed. Its line-search trials may take
  // this many Newton iterations: a trial there costs a quarter and may snap to another branch,
  // which the design level's short trials reject (measured in docs/design.md).
  int first_pass_trial_forward_iterations = 30;
  // ... and it gives up on a side once its steps fall below this (max |Δθ2|, rad): it only has to
  // tell the sides apart, not finish either.
  double first_pass_min_step_rad = 0.03;
  // Stages "prepare", "flatten", "choose side", "simulate", "optimize theta2"; may be empty.
  ProgressCallback progress;
};

// Table 1's columns and the rest of what a run reports. Distances in % of the target's bounding-box
// diagonal, times in seconds of wall clock.
struct DesignMetrics {
  int faces = 0;
  int vertices = 0;
  double t_prepare_s = 0;
  double t_param_s = 0;  // flattening
  // The design level's theta2 = 0 simulation from the target ("Dist. to sim."). When the
  // optimization starts from zeros this is its first equilibrium, and is counted in t_optim_s too;
  // when it starts from the first pass's theta2, the simulation only serves the report.
  double t_sim_s = 0;
  double t_optim_s = 0;  // theta2 optimization, the first pass included
  double t_traj_s = 0;   // trajectories (not part of the pipeline yet)
  double dist_to_sim_avg_pct = 0, dist_to_sim_max_pct = 0;
  double dist_to_optim_avg_pct = 0, dist_to_optim_max_pct = 0;
  double theta2_max_abs_rad = 0;
  double theta2_dirichlet = 0;  // θ2ᵀ L θ2 on the target (dimensionless)
  int optim_iterations = 0;
  double optim_objective = 0;  // E (Eq. 13, normalized as in optimize_theta2.h) at the end
  // The first pass (both sides designed when the curvature does not tell the printed side): the
  // faces of its level one Loop step coarser (0 when there is none and it ran on the design
  // level) and the kept side's theta2 iterations there (0 when it did not run).
  int coarse_faces = 0;
  int first_pass_iterations = 0;
  bool optim_converged = false;
  // The design printed with the paths' errors (OptimizeTheta2Options::path_error_rad): the mean
  // over independent samples of the distances (avg, max, %) from the target, of the design kept.
  // When the nominal design's shapes under them lay more than 1 % from its prediction, theta2 was
  // optimized again for them: that design's figures, and whether it was kept (it lands closer).
  double path_error_dist_avg_pct = 0, path_error_dist_max_pct = 0;
  double path_error_redesign_avg_pct = 0, path_error_redesign_max_pct = 0;
  bool path_error_redesigned = false;
};

// One design of a kEveryStretch run (the kept one among them).
struct StretchOutcome {
  int stretch_candidate = 0;
  bool flipped = false;
  double objective = 0;  // the design level's final E
  double dist_to_optim_avg_pct = 0, dist_to_optim_max_pct = 0;
  int optim_iterations = 0;
  double seconds = 0;  // wall time of that whole design
};

struct Design {
  FlatPlate flat;             // target (scaled, maybe flipped), plate, theta1
  Eigen::VectorXd theta2;     // per vertex, rad
  Eigen::MatrixXd simulated;  // #V x 3 mm: equilibrium with theta2 = 0, started from the target
  std::string simulated_stop_reason;  // "converged", or why that simulation stopped (one sentence)
  Eigen::MatrixXd optimized;          // #V x 3 mm: equilibrium with the optimized theta2
  ShapeDistance dist_to_sim, dist_to_optim;
  Theta2Result optimization;
  bool flipped = false;       // the target's normal side is on the bed
  double side_agreement = 0;  // printed_side_agreement of the chosen side
  DesignMetrics metrics;
  std::vector<StretchOutcome> explored;  // kEveryStretch: every design, by stretch; else empty
};

// How well the bending a plate has with theta2 = 0 agrees with the target's curvature: the
// area-weighted cosine Σ A ⟨b, b̄⟩ / √(Σ A |b|² · Σ A |b̄|²) between the target's second fundamental
// form b pulled back to the plate and the rest one b̄ (Eq. 7: the top shrinks more, so the plate
// curls along its print direction toward its top). In [−1, 1]; negative means the other side
// should be on top (the plate would curl the wrong way, and theta2 alone cannot undo that).
double printed_side_agreement(const FlatPlate& flat, const Material& material, int num_layers);

// Which initial stretch the flattening starts from (FlattenOptions::stretch_candidate). The plate
// curls along its print direction with theta2 = 0, and theta2 only adds a twist: b̄ along theta1
// does not depend on it (Eq. 17). So the print directions should run where the target bends the
// way the plate does. The lowest-energy stretch is kept when its printed_side_agreement is clear
// for `side` (at least 0.2 in magnitude when automatic, with the side's sign when forced); else the
// lowest-energy stretch (Eq. 11 mean deviation, converged) among those whose agreement is clear;
// else the lowest-energy one. The paper's top (a shirt) shows why: the lowest-energy plate runs its
// paths along the two long flaps (agreement 0.02), which then curl whatever theta2 is (6.3 % /
// 30 % from the target, avg / max); the plate whose paths run across them (agreement 0.32,
// singular values 0.76 % off instead of 0.51 %) ends at 0.18 % / 2.84 %. A stretch named in
// options.stretch_candidate is taken as it is, clear or not, without a search.
struct StretchChoice {
  FlatPlate plate;       // normal side up (options.flip is ignored; flipping negates the agreement)
  double agreement = 0;  // printed_side_agreement of `plate`
  double lowest_energy_agreement = 0;  // ... of the lowest-energy stretch
  bool clear = false;                  // `agreement` is clear for the side
  bool searched = false;               // the other stretches were tried
};
StretchChoice choose_initial_stretch(const Mesh& target, const FlattenOptions& options,
                                     const Material& material, int num_layers, PrintedSide side);

// The plate to print: the flattened plate, its layer stack (shrink_morph_layer_stack of theta1
// and theta2 averaged to faces, num_layers layers of material.layer_height mm of `material`) and
// the design fields theta1 (per face), theta2 (per vertex; empty: zeros) and sv_deviation.
PlateDesign shrink_morph_plate_design(const FlatPlate& flat, const Eigen::VectorXd& theta2,
                                      const Material& material, int num_layers);

// Runs the pipeline on a target surface (any units; the plate is options.width_mm wide). `source`
// names the input in error messages. Throws UserError for bad options or a target that is not a
// disk. With kEveryStretch the designs from the four stretches run side by side on the cores
// there are (each gives the same bits as alone) and the one with the lowest final E is returned,
// its times those of the whole exploration (t_optim_s: the wall time less the kept flattening's).
Design design_shrink_morph(Mesh target, const std::string& source, const DesignOptions& options);

}  // namespace flatmorph
