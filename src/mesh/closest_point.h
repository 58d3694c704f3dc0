// The nearest point of a triangle mesh's surface to a point in space, for comparing two shapes
// that share no vertices (simulate/surface_fit.h). Coordinates in mm.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace flatmorph {

// The point of the triangle (a, b, c) nearest p; a degenerate triangle (a segment or a point)
// gives the nearest point of what it is.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// A bounding-box hierarchy over a mesh's faces, built once and queried for many points.
struct TriangleTree {
  Eigen::MatrixXd V;  // #V x 3
  Eigen::MatrixXi F;  // #F x 3
  struct Node {
    Eigen::Vector3d lo, hi;     // the box of its faces
    int begin = 0, end = 0;     // its faces: order[begin .. end)
    int left = -1, right = -1;  // children (nodes), -1 for a leaf
  };
  std::vector<Node> nodes;  // nodes[0] is the root
  std::vector<int> order;   // face indices, each node's a contiguous range
};

// The tree over the faces F (#F x 3) of V (#V x 3). Empty when F is.
TriangleTree triangle_tree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

struct SurfacePoint {
  Eigen::Vector3d point{0, 0, 0};
  int face = -1;  // the face it lies on (the lowest index among equally near faces)
  double distance = 0;
};

// The nearest point of the tree's surface to p. Requires a tree with at least one face.
SurfacePoint closest_surface_point(const TriangleTree& tree, const Eigen::Vector3d& p);

}  // namespace flatmorph
