// Path ordering: a permutation with directions, never worse than greedy nearest neighbour, much
// better where greedy strands paths, deterministic.
#include "toolpath/order_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

namespace flatmorph::order_paths_test {
namespace {

// Deterministic pseudo-random numbers in [0, 1) (a fixed linear congruential generator).
class Lcg {
 public:
  explicit Lcg(uint64_t seed) : state_(seed) {}
  double next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) / 9007199254740992.0;
  }

 private:
  uint64_t state_;
};

// The travel of an order, recomputed from scratch.
double travel_of(const PathOrder& order, const Eigen::MatrixX2d& first,
                 const Eigen::MatrixX2d& last) {
  double travel = 0;
  for (size_t pos = 0; pos + 1 < order.order.size(); ++pos) {
    const int a = order.order[pos], b = order.order[pos + 1];
    const Eigen::RowVector2d exit = order.reversed[pos] ? first.row(a) : last.row(a);
    const Eigen::RowVector2d entry = order.reversed[pos + 1] ? last.row(b) : first.row(b);
    travel += (entry - exit).norm();
  }
  return travel;
}

void expect_permutation(const PathOrder& order, int n) {
  ASSERT_EQ(static_cast<int>(order.order.size()), n);
  ASSERT_EQ(static_cast<int>(order.reversed.size()), n);
  std::vector<int> sorted = order.order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < n; ++i) EXPECT_EQ(sorted[i], i);
}

TEST(OrderPaths, RandomSegmentsBeatGreedy) {
  Lcg random(7);
  const int n = 400;
  Eigen::MatrixX2d first(n, 2), last(n, 2);
  for (int p = 0; p < n; ++p) {
    first.row(p) << 100 * random.next(), 100 * random.next();
    last.row(p) = first.row(p) + Eigen::RowVector2d(4 * random.next() - 2, 4 * random.next() - 2);
  }
  const Eigen::Vector2d start(0, 0);
  const PathOrder greedy = greedy_order(first, last, start);
  const PathOrder best = order_paths(first, last, start);
  expect_permutation(greedy, n);
  expect_permutation(best, n);
  EXPECT_NEAR(greedy.travel, travel_of(greedy, first, last), 1e-9);
  EXPECT_NEAR(best.travel, travel_of(best, first, last), 1e-9);
  EXPECT_LT(best.travel + best.approach, 0.9 * (greedy.travel + greedy.approach));
  EXPECT_GT(best.evaluations, 0);
  // Same input, same answer.
  const PathOrder again = order_paths(first, last, start);
  EXPECT_EQ(again.order, best.order);
  EXPECT_EQ(again.reversed, best.reversed);
}

TEST(OrderPaths, ParallelLinesZigZag) {
  // 50 parallel lines given all left-to-right: the best order prints every other one reversed,
  // with a jump of one spacing between neighbours.
  const int n = 50;
  Eigen::MatrixX2d first(n, 2), last(n, 2);
  for (int p = 0; p < n; ++p) {
    const int row = (p * 17) % n;  // shuffled
    first.row(p) << 0, 0.4 * row;
    last.row(p) << 30, 0.4 * row;
  }
  const PathOrder best = order_paths(first, last, Eigen::Vector2d(0, 0));
  expect_permutation(best, n);
  EXPECT_NEAR(best.travel, 0.4 * (n - 1), 1e-9);
  EXPECT_NEAR(best.approach, 0, 1e-12);
}

TEST(OrderPaths, RespectsTheEvaluationBudget) {
  Lcg random(3);
  const int n = 200;
  Eigen::MatrixX2d first(n, 2), last(n, 2);
  for (int p = 0; p < n; ++p) {
    first.row(p) << 50 * random.next(), 50 * random.next();
    last.row(p) = first.row(p) + Eigen::RowVector2d(1, 0);
  }
  OrderOptions options;
  options.max_evaluations = 100;
  const PathOrder limited = order_paths(first, last, Eigen::Vector2d(0, 0), options);
  expect_permutation(limited, n);
  // A move found at the last evaluation may finish its loop, so allow a few more.
  EXPECT_LE(limited.evaluations, options.max_evaluations + 3 * options.neighbours);
  const PathOrder greedy = greedy_order(first, last, Eigen::Vector2d(0, 0));
  EXPECT_LE(limited.travel + limited.approach, greedy.travel + greedy.approach + 1e-9);
}

TEST(OrderPaths, EmptyAndSingle) {
  const PathOrder none =
      order_paths(Eigen::MatrixX2d(0, 2), Eigen::MatrixX2d(0, 2), Eigen::Vector2d(0, 0));
  EXPECT_TRUE(none.order.empty());
  EXPECT_EQ(none.travel, 0);
  Eigen::MatrixX2d first(1, 2), last(1, 2);
  first << 5, 0;
  last << 1, 0;
  const PathOrder one = order_paths(first, last, Eigen::Vector2d(0, 0));
  ASSERT_EQ(one.order.size(), 1u);
  EXPECT_TRUE(one.reversed[0]);  // enter at the end nearer the start
  EXPECT_NEAR(one.approach, 1, 1e-12);
}

}  // namespace
}  // namespace flatmorph::order_paths_test
