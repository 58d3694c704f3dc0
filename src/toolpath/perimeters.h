// Perimeter loops: closed paths parallel to the plate's outline. Off by default in Shrink & Morph
// (a loop along the boundary shrinks along the boundary and fights the designed directions); a
// user may want one for a cleaner edge.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "toolpath/isolines.h"

namespace flatmorph {

// Distance from each vertex of V (#V x 2, mm) to the outline of the plate (V_plate, F_plate: its
// boundary edges), in mm.
Eigen::VectorXd boundary_distance(const Eigen::MatrixXd& V, const Eigen::MatrixXd& V_plate,
                                  const Eigen::MatrixXi& F_plate);

// `count` loops at distances (m + 1/2) spacing from the outline, m = 0 (outermost) .. count - 1,
// traced as level sets of the boundary distance (linear in each face of the mesh V, F, which
// should be refined to about the spacing; `distance` per vertex of V). Loops shorter than
// min_length_mm are dropped. Returned outermost first.
std::vector<Polyline2> perimeter_loops(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const Eigen::VectorXd& distance, int count,
                                       double spacing_mm, double min_length_mm);

// Removes the parts of the polylines closer than min_distance_mm to the outline (cutting
// between points by bisection), so that paths stop short of the perimeter loops.
void clip_to_inner_region(std::vector<Polyline2>& polylines, const Eigen::MatrixXd& V_plate,
                          const Eigen::MatrixXi& F_plate, double min_distance_mm);

}  // namespace flatmorph
