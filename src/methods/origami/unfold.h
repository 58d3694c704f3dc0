// A solid's faces laid flat as nets (Thermorph Step 2; notes §6-7): a spanning tree of the faces'
// dual graph whose arcs are the hinges (every other edge is cut), each face placed by unfolding it
// about its hinge to its parent, outward side up (+z), without two faces of a net overlapping; and
// the sharp fold back, each face turned about its hinge by the edge's fold angle. Millimetres and
// radians.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "methods/origami/polyhedron.h"

namespace flatmorph {

struct UnfoldOptions {
  // Spanning trees tried before a solid is split into several nets: the first takes the longest
  // hinges (strong, and the faces stay compact); the others perturb those weights (a fixed seed:
  // the same solid gives the same nets).
  int tries = 200;
  // The weight of a hinge whose fold runs against most of the solid's folding (a valley of a mostly
  // convex solid), as a share of its length: such hinges print the weaker case B actuator, which
  // is wider, so a tree that cuts them instead folds on narrower actuators. 1: length alone; 0:
  // every such hinge is cut (the solid may then unfold into several nets).
  double minority_weight = 1;
  // Per edge of polyhedron_edges, a factor on its weight (empty: 1 for all): a design that finds a
  // hinge it cannot print (its trims eat a face) turns it down so that the next tree cuts it; an
  // edge of factor 0 is always cut, even if the solid then unfolds into several nets.
  std::vector<double> edge_weight;
};

struct Net {
  int root = 0;            // the face that stays put
  std::vector<int> faces;  // in the order they were laid: every parent before its child
};

struct Unfolding {
  std::vector<std::vector<int>> faces;  // the solid's, counter-clockwise seen from outside
  std::vector<PolyhedronEdge> edges;    // polyhedron_edges
  Eigen::VectorXd fold_angle;           // per edge (fold_angle), rad
  // Per face: the edge to its parent in its net (a hinge), or −1 for a net's root.
  Eigen::VectorXi parent_edge;
  Eigen::VectorXi parent_face;  // −1 for a root
  Eigen::VectorXi net_of_face;
  // Per face: its corners in the plane of its net, in face order (counter-clockwise), mm.
  std::vector<Eigen::MatrixX2d> flat;
  std::vector<Net> nets;  // one unless no tree of `tries` laid the solid flat
  bool is_hinge(int edge) const;
};

// Throws polyhedron_edges' UserErrors.
Unfolding unfold(const Polyhedron& solid, const UnfoldOptions& options = {});

// The pairs of faces of one net whose flat polygons overlap by more than a sliver (an area over
// 1e-4 of the smaller face's); empty for a valid net.
std::vector<std::pair<int, int>> net_overlaps(const Unfolding& unfolding, int net);

// The net folded sharply, every hinge by `progress` (0 flat, 1 folded) times its fold angle, in the
// net's frame (its root fixed in the plane z = 0): per face its corners in 3D, mm.
std::vector<Eigen::MatrixX3d> fold_net(const Unfolding& unfolding, int net, double progress);

// The rigid motion that lays face f of `solid` in the plane outward side up with its first edge
// along +x from the origin, as unfold lays a net's root: x ↦ R x + t.
struct RigidMotion {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};
RigidMotion face_to_plane(const Polyhedron& solid, int f);

}  // namespace flatmorph
