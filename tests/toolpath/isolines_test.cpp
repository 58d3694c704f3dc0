// Isolines of stripe patterns where the stripes fork: radial print directions on a disk spread
// apart with the radius, so equally spaced paths must fork again and again. Every fork adds one
// path that begins there; the paths passing the fork go on through it.
#include "toolpath/isolines.h"

#include <gtest/gtest.h>

#include <cmath>

#include "toolpath/refine_plate.h"
#include "toolpath/stripe_patterns.h"
#include "toolpath/test_plates.h"

namespace flatmorph::isolines_test {
namespace {

TEST(StripeIsolines, PathsPassForksAndOnlyTheNewBranchEnds) {
  const double spacing = 0.4, radius = 15;
  const toolpath_testing::TestPlate coarse = toolpath_testing::disk_plate(2 * radius, 1.2);
  // Edges about twice the spacing: the phase winds about twice along each edge.
  const RefinedPlate plate = refine_plate(coarse.V, coarse.F, 2 * spacing);
  const EdgeTopology topology = edge_topology(plate.F);
  Eigen::VectorXd theta(plate.V.rows());
  for (int v = 0; v < theta.size(); ++v) theta(v) = std::atan2(plate.V(v, 1), plate.V(v, 0));
  StripeOptions options;
  options.spacing = spacing;
  const StripePattern pattern = stripe_patterns(plate.V, plate.F, topology, {theta}, options)[0];
  int forks = 0;
  for (int f = 0; f < plate.F.rows(); ++f) {
    if (pattern.doubled_index(f) == 0 && pattern.stripe_index(f) != 0) ++forks;
  }
  // Half a circumference of 2 pi r / spacing paths more at the rim than near the centre.
  ASSERT_GT(forks, 20);
  const std::vector<Polyline2> paths = stripe_isolines(plate.V, plate.F, topology, pattern, 0.0);
  // Path ends away from the rim and from the field's singularity at the centre.
  int interior_ends = 0;
  for (const Polyline2& path : paths) {
    if (path.closed) continue;
    for (const Eigen::Index i : {Eigen::Index{0}, path.points.rows() - 1}) {
      const double r = path.points.row(i).norm();
      if (r > 2.0 && r < radius - 0.5) ++interior_ends;
    }
  }
  // A fork where every passing path broke would leave two ends per path through the face.
  EXPECT_LE(interior_ends, forks + 4) << forks << " forks";
  EXPECT_GE(interior_ends, forks / 2) << forks << " forks";
}

}  // namespace
}  // namespace flatmorph::isolines_test
