// Thermorph's self-folding origami end to end (CHI 2018, Steps 1-4; notes §6-8): a solid of planar
// faces unfolded into nets, or a drawn crease pattern, each fold given a curved PLA/TPU actuator
// whose width and print speed bend it by the fold's angle (the hinge curve), the sheets laid on the
// bed, folded back to check them, and printed in two materials. Millimetres, radians, mm/s.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "material/hinge_curve.h"
#include "material/material.h"
#include "mesh/mesh.h"
#include "methods/origami/actuators.h"
#include "methods/origami/crease_pattern.h"
#include "methods/origami/fold_simulation.h"
#include "methods/origami/origami_toolpath.h"
#include "methods/origami/polyhedron.h"
#include "methods/origami/unfold.h"
#include "plate/plate_design.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct OrigamiOptions {
  Material pla;  // the faces and the actuators' active layers (tool 0)
  Material tpu;  // the actuators' constraint layer (tool 1)
  // The hinge curve: pla.hinge_curve when calibrated, else the default from the laminate
  // (plate/actuator_stack.h).
  // Every actuator's active PLA is printed at this speed, and its width follows from the angle
  // (W = |θ| / κ(v)); with actuator_width > 0, every actuator is that wide and its speed follows
  // (κ(v) = |θ| / W, Fig. 11c).
  double actuator_speed = 150;  // mm/s: 9000 mm/min, the paper's for polyhedra (Table 1 e, f)
  double actuator_width = 0;    // mm; 0: from the speed
  // Folds of less than this print no actuator (the faces stay joined flat), rad.
  double flat_angle = 1.0 * 3.14159265358979323846 / 180;
  UnfoldOptions unfold;
  // With the uncalibrated hinge curve the tree cuts every hinge that would print case B (its
  // actuator folds less than the curve promises on a hinge longer than it is wide): true lets it
  // keep them, only preferring to cut them as a calibrated curve does (fewer nets; each sheet
  // with case B hinges names them in a warning).
  bool case_b_hinges = false;
  // How many times a solid is unfolded again when its net cannot print (a face its trims eat,
  // pieces that overlap once shifted), each time cutting the hinges at fault.
  int retrees = 40;
  // ... as long as the nets keep this share of the first tree's hinges (F − 1 for a single net
  // that cuts no valley); else the first tree's problem is refused.
  double min_hinge_share = 0.75;
  ActuateOptions actuate;
  OrigamiPrintSettings print;
  // Where the sheets may go (x, y: the printer's bed less a margin), mm, and their gap.
  Eigen::Vector2d room{200, 200};
  double sheet_gap = 5;
  int fold_steps = 50;  // collision checks from flat to folded
  ProgressCallback progress;
};

// One printed sheet: a net of the solid, or the drawn pattern.
struct OrigamiSheet {
  CreasePattern pattern;            // placed on the bed (plate coordinates), the side printed up
  bool turned_over = false;         // printed with the solid's inward side up (mostly valleys)
  int bed = 0;                      // the print job it goes on, from 0
  std::vector<HingeDesign> hinges;  // one per hinge of the pattern
  ActuatedSheet sheet;
  FoldedSheet folded;                            // the curved model at full fold
  std::optional<FoldCollision> collision;        // every hinge folding together
  std::optional<FoldCollision> order_collision;  // hinge after hinge in the fold order
  double corner_gap = 0;                         // mm, largest_corner_gap
  double loop_closure = 0;                       // mm, loop_closure_error (0 for a net)
};

struct OrigamiDesign {
  std::optional<Polyhedron> solid;  // the inverse flow's (none for a drawn pattern)
  std::optional<Unfolding> unfolding;
  HingeCurve curve;
  std::vector<OrigamiSheet> sheets;
  // The sheets go on num_beds beds (print jobs, when they do not fit one), laid side by side in
  // plate coordinates; per bed, its sheets' toolpath.
  int num_beds = 1;
  std::vector<Toolpath> bed_toolpaths;
  // The inverse flow's checks (notes §11), in % of the solid's diagonal: the nets folded sharply
  // against the solid's corners after the best rigid motion, and the curved model's face corners
  // off their faces' planes in that same frame.
  double sharp_error_pct = 0;
  double curved_plane_error_pct = 0;
  double fold_angle_error = 0;  // rad: the largest |θ − (π − dihedral)| over the hinges
  std::vector<std::string> warnings;
  struct Times {
    double unfold = 0, actuate = 0, fold = 0, toolpath = 0, total = 0;  // s
  } times;
};

// The solid folded from nets (Steps 2-4). Throws unfold's, actuate's and the hinge curve's
// UserErrors (a fold no speed in the curve's range reaches, a face too narrow for its trims) and
// pack_on_beds' (a sheet larger than options.room).
OrigamiDesign design_origami(const Polyhedron& solid, const OrigamiOptions& options);

// A drawn crease pattern (the forward flow, Fig. 12 "2D pattern"): the same actuators, layout,
// folding and print. Throws as design_origami.
OrigamiDesign design_origami_pattern(const CreasePattern& pattern, const OrigamiOptions& options);

// The design again with actuator a of sheet s printed width_scale[s][a] times as wide (actuators
// in each sheet's order; the same speed, the arc's radius growing with the width): every sheet
// actuated, laid out, folded, checked and printed anew. For widths corrected against the shared
// simulator (sheet_simulation.h). Throws as design_origami (a wider actuator may eat a face or
// overlap another piece); std::invalid_argument for scales that do not match the sheets or are
// not positive.
OrigamiDesign with_hinges_widened(const OrigamiDesign& design,
                                  const std::vector<std::vector<double>>& width_scale,
                                  const OrigamiOptions& options);

// The layers of a plate whose triangle t lies in piece piece(t) (a face, then the actuators, from
// 0) of sheet sheet_of(t): faces PLA in every layer, their lines crossed as face_lines_along_y
// says, shrinking as active_lambda1 says at the face speed (λ2 = λ3 = 1, the bed side more, as the
// actuators' PLA); actuators as actuator_layer_stack prints them (the active PLA's λ1 from its
// speed, the TPU along the hinge). Materials {pla, tpu}.
LayerStack printed_sheet_stack(const std::vector<OrigamiSheet>& sheets,
                               const Eigen::VectorXi& sheet_of, const Eigen::VectorXi& piece,
                               const OrigamiOptions& options);

// The printed sheets as one plate (flat.ply and its stack), and the same triangles folded (the
// curved model, folded.ply: vertex for vertex the plate's): each face and each actuator strip
// (`arc_steps` strips across) triangulated apart, with printed_sheet_stack's layers. A per-face
// property "piece" numbers the face (0 ...) or actuator (faces + a) of each sheet a triangle
// belongs to, "sheet" the sheet.
struct OrigamiPlate {
  PlateDesign plate;
  Mesh folded;
};
OrigamiPlate origami_plate(const OrigamiDesign& design, const OrigamiOptions& options,
                           int arc_steps = 8);

// The rows of plate.plate.F (origami_plate's) whose sheet goes on `bed` (from 0): the faces one
// print job prints.
Eigen::MatrixXi bed_faces(const OrigamiPlate& plate, const OrigamiDesign& design, int bed);

// The solid scaled about its centre so that its bounding box's longest side is `size` mm.
Polyhedron scaled_to_size(const Polyhedron& solid, double size);

}  // namespace flatmorph
