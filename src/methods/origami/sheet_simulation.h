// The printed sheet folded by the shared simulator (src/simulate), the judge of every method: its
// faces and actuators meshed as one conforming plate, each triangle with the layers printed there
// (printed_sheet_stack), started from the designed fold (the curved model) and let settle. How far
// each hinge then folds, against its design, says whether the actuators bend as the hinge curve
// promises. Millimetres and radians.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "methods/origami/design_origami.h"
#include "plate/plate_design.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph {

struct SheetSimulation {
  PlateDesign plate;         // the conforming mesh of the sheet and its layers
  Eigen::VectorXi piece;     // per triangle: its face, then the actuators (from 0)
  Eigen::MatrixXd designed;  // #V x 3, mm: the curved model at the mesh's vertices (the start)
  SimulationResult result;
  ShapeDistance to_design;  // the simulated sheet against the curved model, rigidly aligned
  // Per actuator of the sheet: the angle its two faces make once simulated where they meet it (the
  // angle between their normals within 3 mm of its ends, signed as the design's), rad: the
  // actuator's own bend, apart from how the faces themselves warp.
  std::vector<double> fold_angle;
};

// Per actuator of `sheet`, the angle (rad, signed as the design's) its two faces make in the shape
// V (#V x 3 mm) of a mesh of the sheet (flat: #V x 2 or 3 plate coordinates; F; piece: per
// triangle its face, then the actuators, from 0): between the faces' mean normals within 3 mm of
// the actuator's ends. For a shape simulated from the design's layers or from its G-code alike.
std::vector<double> hinge_fold_angles(const ActuatedSheet& sheet, const Eigen::MatrixXd& flat,
                                      const Eigen::MatrixXi& F, const Eigen::VectorXi& piece,
                                      const Eigen::MatrixXd& V);

// Sheet `index` of `design` simulated, its mesh no coarser than `max_edge` mm (three or more
// triangles across the narrowest actuator). Throws the simulator's and the mesher's UserErrors.
SheetSimulation simulate_sheet(const OrigamiDesign& design, int index,
                               const OrigamiOptions& options, double max_edge);

// The largest |angle − designed angle| over every hinge of every sheet of `design`, rad:
// angles[i][a] is actuator a of sheet i (hinge_fold_angles' order), simulated from the layers or
// from the G-code.
double worst_hinge_error(const OrigamiDesign& design,
                         const std::vector<std::vector<double>>& angles);

// The design's actuators widened or narrowed until the shared simulator folds every printed sheet
// as designed (the hinge curve is a strip's alone: on a whole sheet the faces' own shrink holds
// some hinges back). Each round simulates every sheet (simulate_sheet at `max_edge`), scales each
// actuator's width by θ / θ_simulated (within [2/3, 3/2] per round; 3/2 when a hinge bends the
// wrong way) and rebuilds the sheets (with_hinges_widened). Stops when every hinge is within
// `tolerance` (rad) or after `max_rounds` simulations, or when the next widths would not print (a
// wider actuator that eats a face or overlaps another piece: `stopped` says why), and returns the
// design whose worst hinge came closest. Throws as simulate_sheet.
struct HingeFit {
  OrigamiDesign design;
  // Per round: the largest |θ_simulated − θ| over every hinge of every sheet, rad.
  std::vector<double> worst_error;
  int best_round = 0;   // the round whose design is returned
  std::string stopped;  // why the rounds ended early, when the next widths would not print
};
HingeFit fit_hinges_to_simulation(const OrigamiDesign& design, const OrigamiOptions& options,
                                  int max_rounds, double tolerance, double max_edge);

}  // namespace flatmorph
