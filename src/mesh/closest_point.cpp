#include "mesh/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace flatmorph {
namespace {

constexpr int kLeafFaces = 8;

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (!(length2 > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) * ab;
}

// Squared distance from p to the box [lo, hi] (0 inside).
double box_distance2(const Eigen::Vector3d& p, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

}  // namespace

// Ericson, Real-Time Collision Detection §5.1.5: the Voronoi region of p among the triangle's
// vertices, edges and face, by barycentric tests.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = va + vb + vc;
  if (!(denominator > 0)) {
    // Collinear corners: the nearest of the three edges.
    Eigen::Vector3d best = closest_point_on_segment(p, a, b);
    for (const Eigen::Vector3d& q :
         {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)}) {
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  return a + vb / denominator * ab + vc / denominator * ac;
}

TriangleTree triangle_tree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  TriangleTree tree;
  tree.V = V;
  tree.F = F;
  const int num_faces = static_cast<int>(F.rows());
  if (num_faces == 0) return tree;
  std::vector<Eigen::Vector3d> lo(num_faces), hi(num_faces), centre(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    lo[f] = a.cwiseMin(b).cwiseMin(c);
    hi[f] = a.cwiseMax(b).cwiseMax(c);
    centre[f] = (lo[f] + hi[f]) / 2;
  }
  tree.order.resize(num_faces);
  std::iota(tree.order.begin(), tree.order.end(), 0);
  // Split each node at the median of its faces' centres along its longest side; ties by index,
  // so that the tree is the same on every run.
  std::vector<int> pending{0};
  tree.nodes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0, num_faces});
  while (!pending.empty()) {
    const int n = pending.back();
    pending.pop_back();
    TriangleTree::Node node = tree.nodes[n];
    node.lo = lo[tree.order[node.begin]];
    node.hi = hi[tree.order[node.begin]];
    for (int i = node.begin + 1; i < node.end; ++i) {
      node.lo = node.lo.cwiseMin(lo[tree.order[i]]);
      node.hi = node.hi.cwiseMax(hi[tree.order[i]]);
    }
    if (node.end - node.begin > kLeafFaces) {
      int axis = 0;
      (node.hi - node.lo).maxCoeff(&axis);
      const int middle = (node.begin + node.end) / 2;
      std::nth_element(tree.order.begin() + node.begin, tree.order.begin() + middle,
                       tree.order.begin() + node.end, [&](int f, int g) {
                         return centre[f](axis) < centre[g](axis) ||
                                (centre[f](axis) == centre[g](axis) && f < g);
                       });
      node.left = static_cast<int>(tree.nodes.size());
      node.right = node.left + 1;
      tree.nodes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), node.begin, middle});
      tree.nodes.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), middle, node.end});
      pending.push_back(node.right);
      pending.push_back(node.left);
    }
    tree.nodes[n] = node;
  }
  return tree;
}

SurfacePoint closest_surface_point(const TriangleTree& tree, const Eigen::Vector3d& p) {
  SurfacePoint best;
  double best2 = std::numeric_limits<double>::infinity();
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const TriangleTree::Node& node = tree.nodes[stack.back()];
    stack.pop_back();
    if (box_distance2(p, node.lo, node.hi) > best2) continue;
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const int f = tree.order[i];
        const Eigen::Vector3d q = closest_point_on_triangle(
            p, tree.V.row(tree.F(f, 0)), tree.V.row(tree.F(f, 1)), tree.V.row(tree.F(f, 2)));
        const double d2 = (q - p).squaredNorm();
        if (d2 < best2 || (d2 == best2 && f < best.face)) {
          best2 = d2;
          best.point = q;
          best.face = f;
        }
      }
      continue;
    }
    // The nearer child is searched first (pushed last), so the farther one is often pruned.
    const TriangleTree::Node& left = tree.nodes[node.left];
    const TriangleTree::Node& right = tree.nodes[node.right];
    const bool left_first =
        box_distance2(p, left.lo, left.hi) <= box_distance2(p, right.lo, right.hi);
    stack.push_back(left_first ? node.right : node.left);
    stack.push_back(left_first ? node.left : node.right);
  }
  best.distance = std::sqrt(best2);
  return best;
}

}  // namespace flatmorph
