// The printed sheet folded by the shared simulator (src/simulate), the judge of every method: its
// faces and actuators meshed as one conforming plate, each triangle with the layers printed there
// (printed_sheet_stack), started from the designed fold (the curved model) and let settle. How far
// each hinge then folds, against its design, says whether the actuators bend as the hinge curve
// promises. Millimetres and radians.
#pragma once

#include <Eigen/Core>
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

}  // namespace flatmorph
