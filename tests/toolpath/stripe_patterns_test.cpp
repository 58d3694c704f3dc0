// Stripe patterns on fields whose exact stripes are known: a constant direction has the stripes
// e^{i nu <X, x>}, of zero energy, whatever the sign of X chosen at each vertex.
#include "toolpath/stripe_patterns.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "toolpath/refine_plate.h"
#include "toolpath/test_plates.h"

namespace flatmorph::stripe_patterns_test {
namespace {

struct Refined {
  RefinedPlate plate;
  EdgeTopology topology;
};

Refined refined_rectangle() {
  const toolpath_testing::TestPlate coarse = toolpath_testing::rectangle_plate(12, 8, 1.0);
  Refined r;
  r.plate = refine_plate(coarse.V, coarse.F, 0.4);
  r.topology = edge_topology(r.plate.F);
  return r;
}

// Checks that `pattern` is the exact stripe pattern of the constant direction theta: zero energy,
// no fork, every face usable, and the phase increment along every edge nu <X, e> up to the sign
// of X.
void expect_exact_stripes(const Refined& r, const StripePattern& pattern, double theta, double nu) {
  EXPECT_LT(pattern.eigenvalue, 1e-8 * nu * nu);
  EXPECT_EQ(pattern.stripe_index.cwiseAbs().sum(), 0);
  EXPECT_EQ(pattern.doubled_index.cwiseAbs().sum(), 0);
  for (bool usable : pattern.usable) EXPECT_TRUE(usable);
  const Eigen::Vector2d X(-std::sin(theta), std::cos(theta));
  double worst = 0;
  for (int e = 0; e < r.topology.num_edges(); ++e) {
    const Eigen::Vector2d edge =
        (r.plate.V.row(r.topology.edges(e, 1)) - r.plate.V.row(r.topology.edges(e, 0))).transpose();
    const double expected = nu * X.dot(edge);
    worst = std::max(worst, std::min(std::abs(pattern.edge_phase(e) - expected),
                                     std::abs(pattern.edge_phase(e) + expected)));
  }
  EXPECT_LT(worst, 1e-4);  // rad; the +-1e-6 rad directions below shift it by ~1e-5
}

TEST(StripePatterns, ConstantFieldIsExact) {
  const Refined r = refined_rectangle();
  StripeOptions options;
  const double nu = kTwoPi / options.spacing;
  const std::vector<StripePattern> patterns =
      stripe_patterns(r.plate.V, r.plate.F, r.topology,
                      {Eigen::VectorXd::Constant(r.plate.V.rows(), 0.3)}, options);
  ASSERT_EQ(patterns.size(), 1u);
  expect_exact_stripes(r, patterns[0], 0.3, nu);
}

TEST(StripePatterns, SignOfXDoesNotMatter) {
  // Directions +-1e-6 rad around 0 in patches: -e^{2 i theta} sits on the branch cut of the
  // square root, so X flips sign from patch to patch and many edges cross sheets. The stripes
  // must still be the straight ones (a wrong conjugation rule on those edges gives forks and a
  // large energy).
  const Refined r = refined_rectangle();
  Eigen::VectorXd theta(r.plate.V.rows());
  for (int v = 0; v < theta.size(); ++v) {
    const double x = r.plate.V(v, 0), y = r.plate.V(v, 1);
    theta(v) = std::sin(x / 1.3) * std::cos(y / 1.7) > 0 ? 1e-6 : -1e-6;
  }
  StripeOptions options;
  options.tolerance = 1e-10;
  options.max_iterations = 30;
  const std::vector<StripePattern> patterns =
      stripe_patterns(r.plate.V, r.plate.F, r.topology, {theta}, options);
  int crossing = 0;
  for (int e = 0; e < r.topology.num_edges(); ++e) crossing += patterns[0].edge_sign(e) < 0;
  EXPECT_GT(crossing, 100);
  expect_exact_stripes(r, patterns[0], 0.0, kTwoPi / options.spacing);
}

TEST(StripePatterns, WarmStartFollowsTheNextField) {
  // Three layers turning by 0.2 rad each: every pattern is the exact one of its own direction.
  const Refined r = refined_rectangle();
  StripeOptions options;
  std::vector<Eigen::VectorXd> thetas;
  for (double t : {-0.2, 0.0, 0.2})
    thetas.push_back(Eigen::VectorXd::Constant(r.plate.V.rows(), t));
  thetas.push_back(thetas.back());  // the same field again reuses the pattern
  const std::vector<StripePattern> patterns =
      stripe_patterns(r.plate.V, r.plate.F, r.topology, thetas, options);
  ASSERT_EQ(patterns.size(), 4u);
  const double nu = kTwoPi / options.spacing;
  expect_exact_stripes(r, patterns[0], -0.2, nu);
  expect_exact_stripes(r, patterns[1], 0.0, nu);
  expect_exact_stripes(r, patterns[2], 0.2, nu);
  EXPECT_EQ(patterns[3].psi, patterns[2].psi);
}

}  // namespace
}  // namespace flatmorph::stripe_patterns_test
