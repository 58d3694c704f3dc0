// The order in which one layer's paths are printed, and the direction of each: the travel between
// paths is a Travelling Salesperson Problem over path endpoints (Shrink & Morph §3.2.3 used
// OR-Tools; the reference implementation fell back to greedy nearest neighbour, notes §5.5).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace flatmorph {

struct OrderOptions {
  // The local search stops after this many move evaluations (a count, not a time, so the result
  // is the same on every machine) or at a local optimum, whichever comes first.
  long long max_evaluations = 4'000'000;
  int neighbours = 10;  // candidate endpoints per endpoint
};

// Paths given by their two ends (#P x 2 each, mm; equal for a closed loop).
struct PathOrder {
  std::vector<int> order;      // path indices in print order
  std::vector<bool> reversed;  // per position: print path order[i] from its last point to its first
  double travel = 0;           // mm: sum of the jumps between consecutive paths (as travel_length)
  double approach = 0;         // mm: from the start point to the first path
  long long evaluations = 0;   // move evaluations used by the local search
};

// Greedy nearest neighbour from `start` (mm): always jump to the nearest free path end.
PathOrder greedy_order(const Eigen::MatrixX2d& first_points, const Eigen::MatrixX2d& last_points,
                       const Eigen::Vector2d& start);

// Greedy nearest neighbour improved by 2-opt (segment reversals, which flip the direction of every
// path in the segment) and Or-opt (moving one to three consecutive paths elsewhere, either way
// round), over neighbour lists, first improvement, until a local optimum or the evaluation
// budget. Minimizes approach + travel; never worse than greedy_order. Deterministic.
PathOrder order_paths(const Eigen::MatrixX2d& first_points, const Eigen::MatrixX2d& last_points,
                      const Eigen::Vector2d& start, const OrderOptions& options = {});

}  // namespace flatmorph
