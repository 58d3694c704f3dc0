// Checks shared by the DXF and SVG tile-outline reader tests: areas, boxes, distances, and the
// UserError a read throws.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "common/angles.h"
#include "common/error.h"

namespace flatmorph::testing {

// Signed area (mm^2), positive counter-clockwise.
inline double signed_area(const Eigen::MatrixX2d& p) {
  double twice = 0;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const Eigen::Index j = (i + 1) % p.rows();
    twice += p(i, 0) * p(j, 1) - p(j, 0) * p(i, 1);
  }
  return twice / 2;
}

// Largest and smallest distance of the polygon's vertices and chord midpoints from `centre`.
inline std::pair<double, double> radius_range(const Eigen::MatrixX2d& p,
                                              const Eigen::RowVector2d& centre) {
  double lo = INFINITY, hi = 0;
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    const Eigen::RowVector2d a = p.row(i), b = p.row((i + 1) % p.rows());
    for (const Eigen::RowVector2d& q : {a, Eigen::RowVector2d((a + b) / 2)}) {
      lo = std::min(lo, (q - centre).norm());
      hi = std::max(hi, (q - centre).norm());
    }
  }
  return {lo, hi};
}

// Whether the polygon has a vertex within `tolerance` of (x, y).
inline bool has_vertex(const Eigen::MatrixX2d& p, double x, double y, double tolerance = 1e-9) {
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    if ((p.row(i) - Eigen::RowVector2d(x, y)).norm() <= tolerance) return true;
  }
  return false;
}

// The UserError `read` throws (a failed expectation when it throws none).
template <typename Read>
UserError error_of(Read read) {
  try {
    read();
  } catch (const UserError& e) {
    return e;
  }
  ADD_FAILURE() << "no UserError";
  return UserError(ErrorCategory::kFile, "");
}

}  // namespace flatmorph::testing
