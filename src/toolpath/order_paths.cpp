#include "toolpath/order_paths.h"

#include <algorithm>
#include <numeric>

namespace flatmorph {
namespace {

// Below this a move is not an improvement (mm), so rounding cannot make the search cycle.
constexpr double kMinGain = 1e-9;

// The tour as positions; endpoint id 2p is path p's first point, 2p + 1 its last, 2P the start.
class Tour {
 public:
  Tour(const Eigen::MatrixX2d& first, const Eigen::MatrixX2d& last, const Eigen::Vector2d& start)
      : n_(static_cast<int>(first.rows())), points_(2 * n_ + 1, 2) {
    for (int p = 0; p < n_; ++p) {
      points_.row(2 * p) = first.row(p);
      points_.row(2 * p + 1) = last.row(p);
    }
    points_.row(2 * n_) = start.transpose();
  }

  int size() const { return n_; }
  int depot() const { return 2 * n_; }
  double dist(int a, int b) const { return (points_.row(a) - points_.row(b)).norm(); }
  const Eigen::MatrixX2d& points() const { return points_; }

  int entry(int pos) const { return pos < 0 ? depot() : 2 * node_[pos] + (rev_[pos] ? 1 : 0); }
  int exit(int pos) const { return pos < 0 ? depot() : 2 * node_[pos] + (rev_[pos] ? 0 : 1); }
  int where(int endpoint) const { return where_[endpoint / 2]; }

  void set(std::vector<int> node, std::vector<bool> rev) {
    node_ = std::move(node);
    rev_ = std::move(rev);
    where_.assign(n_, 0);
    for (int pos = 0; pos < n_; ++pos) where_[node_[pos]] = pos;
  }

  // Reverses positions [i, j]: the order and the direction of each path.
  void reverse(int i, int j) {
    std::reverse(node_.begin() + i, node_.begin() + j + 1);
    std::reverse(rev_.begin() + i, rev_.begin() + j + 1);
    for (int pos = i; pos <= j; ++pos) {
      rev_[pos] = !rev_[pos];
      where_[node_[pos]] = pos;
    }
  }

  // Moves positions [i, i + len) to just after position p (outside the segment), flipped or not.
  void move(int i, int len, int p, bool flip) {
    std::vector<int> seg_node(node_.begin() + i, node_.begin() + i + len);
    std::vector<bool> seg_rev(rev_.begin() + i, rev_.begin() + i + len);
    if (flip) {
      std::reverse(seg_node.begin(), seg_node.end());
      std::reverse(seg_rev.begin(), seg_rev.end());
      for (size_t k = 0; k < seg_rev.size(); ++k) seg_rev[k] = !seg_rev[k];
    }
    node_.erase(node_.begin() + i, node_.begin() + i + len);
    rev_.erase(rev_.begin() + i, rev_.begin() + i + len);
    const int at = (p < i ? p : p - len) + 1;
    node_.insert(node_.begin() + at, seg_node.begin(), seg_node.end());
    rev_.insert(rev_.begin() + at, seg_rev.begin(), seg_rev.end());
    for (int pos = std::min(i, at); pos < n_; ++pos) where_[node_[pos]] = pos;
  }

  PathOrder result() const {
    PathOrder out;
    out.order = node_;
    out.reversed = rev_;
    if (n_ > 0) out.approach = dist(depot(), entry(0));
    for (int pos = 0; pos + 1 < n_; ++pos) out.travel += dist(exit(pos), entry(pos + 1));
    return out;
  }

 private:
  int n_;
  Eigen::MatrixX2d points_;
  std::vector<int> node_;
  std::vector<bool> rev_;
  std::vector<int> where_;
};

void greedy(Tour& tour) {
  const int n = tour.size();
  std::vector<int> node;
  std::vector<bool> rev;
  std::vector<bool> used(n, false);
  int current = tour.depot();
  for (int step = 0; step < n; ++step) {
    int best = -1;
    double best_d = 0;
    for (int e = 0; e < 2 * n; ++e) {
      if (used[e / 2]) continue;
      const double d = tour.dist(current, e);
      if (best < 0 || d < best_d) {
        best = e;
        best_d = d;
      }
    }
    used[best / 2] = true;
    node.push_back(best / 2);
    rev.push_back(best % 2 == 1);
    current = best ^ 1;  // leave from the other end
  }
  tour.set(std::move(node), std::move(rev));
}

// The k nearest path endpoints of every endpoint and of the start, nearest first.
std::vector<std::vector<int>> neighbour_lists(const Tour& tour, int k) {
  const int m = 2 * tour.size();
  std::vector<std::vector<int>> lists(m + 1);
  std::vector<std::pair<double, int>> candidates;
  for (int a = 0; a <= m; ++a) {
    candidates.clear();
    for (int b = 0; b < m; ++b) {
      if (b != a) candidates.emplace_back(tour.dist(a, b), b);
    }
    const int keep = std::min<int>(k, static_cast<int>(candidates.size()));
    std::partial_sort(candidates.begin(), candidates.begin() + keep, candidates.end());
    for (int c = 0; c < keep; ++c) lists[a].push_back(candidates[c].second);
  }
  return lists;
}

}  // namespace

PathOrder greedy_order(const Eigen::MatrixX2d& first_points, const Eigen::MatrixX2d& last_points,
                       const Eigen::Vector2d& start) {
  Tour tour(first_points, last_points, start);
  greedy(tour);
  return tour.result();
}

PathOrder order_paths(const Eigen::MatrixX2d& first_points, const Eigen::MatrixX2d& last_points,
                      const Eigen::Vector2d& start, const OrderOptions& options) {
  Tour tour(first_points, last_points, start);
  greedy(tour);
  const int n = tour.size();
  if (n < 2) return tour.result();
  const std::vector<std::vector<int>> near = neighbour_lists(tour, options.neighbours);
  long long evaluations = 0;
  const auto budget_left = [&] { return evaluations < options.max_evaluations; };
  const auto d = [&](int a, int b) { return tour.dist(a, b); };

  bool improved = true;
  while (improved && budget_left()) {
    improved = false;
    // 2-opt: for the jump into position i (a -> b), try a new jump a -> c with c near a or b.
    for (int i = 0; i < n && budget_left(); ++i) {
      const int a = tour.exit(i - 1), b = tour.entry(i);
      const double removed = d(a, b);
      bool moved = false;
      for (int c : near[a]) {
        if (d(a, c) >= removed || moved) break;
        const int j = tour.where(c);
        if (tour.exit(j) != c || j < i) continue;  // reversing [i, j] makes a -> c
        ++evaluations;
        double delta = d(a, c) - removed;
        if (j + 1 < n) delta += d(b, tour.entry(j + 1)) - d(c, tour.entry(j + 1));
        if (delta < -kMinGain) {
          tour.reverse(i, j);
          moved = improved = true;
        }
      }
      if (moved) continue;
      for (int c : near[b]) {
        if (d(b, c) >= removed || moved) break;
        const int j = tour.where(c);
        if (tour.entry(j) != c || j > i - 1) continue;  // reversing [j, i-1] makes c -> b
        ++evaluations;
        const double delta = d(c, b) - removed + d(tour.exit(j - 1), a) - d(tour.exit(j - 1), c);
        if (delta < -kMinGain) {
          tour.reverse(j, i - 1);
          moved = improved = true;
        }
      }
    }
    // Or-opt: move positions [i, i + len) between p and its successor, either way round.
    for (int len = 1; len <= 3; ++len) {
      for (int i = 0; i + len <= n && budget_left(); ++i) {
        const int in = tour.entry(i), out = tour.exit(i + len - 1);
        const int prev = tour.exit(i - 1);
        const bool has_next = i + len < n;
        const int next = has_next ? tour.entry(i + len) : -1;
        const double removal_gain = d(prev, in) + (has_next ? d(out, next) - d(prev, next) : 0.0);
        if (removal_gain <= kMinGain) continue;
        bool moved = false;
        for (int side = 0; side < 2 && !moved; ++side) {
          const int end = side == 0 ? in : out;
          for (int c : near[end]) {
            if (d(end, c) >= removal_gain || moved) break;
            const int q = tour.where(c);
            if (q >= i && q < i + len) continue;
            // c = exit(q): insert after q with `end` next to c; c = entry(q): insert before q.
            const bool c_is_exit = tour.exit(q) == c;
            const int p = c_is_exit ? q : q - 1;
            if (p >= i - 1 && p < i + len) continue;  // the segment's own place
            const bool flip = (end == in) != c_is_exit;
            const int succ = p + 1 < n ? p + 1 : -1;
            const int head = flip ? out : in, tail = flip ? in : out;
            ++evaluations;
            double added = d(tour.exit(p), head);
            if (succ >= 0) added += d(tail, tour.entry(succ)) - d(tour.exit(p), tour.entry(succ));
            if (added - removal_gain < -kMinGain) {
              tour.move(i, len, p, flip);
              moved = improved = true;
            }
          }
        }
      }
    }
  }
  PathOrder result = tour.result();
  result.evaluations = evaluations;
  return result;
}

}  // namespace flatmorph
