// Pictures of a design for people in a terminal or a paper, rendered headless (src/raster/): the
// flat plate coloured by its print direction, and the predicted shape coloured by its distance to
// the target. Each carries a colour bar with its range (degrees or mm). Deterministic bytes.
#pragma once

#include <Eigen/Core>

#include "raster/raster.h"

namespace flatmorph {

enum class PlateField {
  kTheta1,  // per face, cyclic colour map over 0..180 degrees (a line direction)
  kTheta2,  // per vertex, diverging map over -max|theta2|..+max|theta2|
  // per face, sequential map from 0 to the largest value: the shrink σ along the path of the
  // thickness-controlled methods (a fraction, labelled in %)
  kShrinkage,
};

// The plate (#V x 2, mm) seen from above (+z, x right, y up), `pixels` wide, with a colour bar
// below: coloured by `values`, per face for kTheta1 (rad) and kShrinkage, per vertex for kTheta2
// (rad).
Canvas plate_picture(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                     const Eigen::VectorXd& values, PlateField field, int pixels = 800);

// The shape V, F seen obliquely from above (orthographic, shaded), vertices coloured by
// `deviation_mm` from 0 (dark blue) to its maximum (yellow), with a colour bar below; grey when
// `deviation_mm` is empty.
Canvas shape_picture(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const Eigen::VectorXd& deviation_mm, int pixels = 800);

}  // namespace flatmorph
