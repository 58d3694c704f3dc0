#include "mesh/polygon.h"

namespace flatmorph {

double signed_area(const Eigen::MatrixX2d& polygon) {
  double twice = 0;
  for (Eigen::Index i = 0; i < polygon.rows(); ++i) {
    const Eigen::Index j = (i + 1) % polygon.rows();
    twice += polygon(i, 0) * polygon(j, 1) - polygon(j, 0) * polygon(i, 1);
  }
  return twice / 2;
}

}  // namespace flatmorph
