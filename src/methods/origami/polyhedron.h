// The solid a Thermorph origami folds into (CHI 2018, Step 2; notes §3, §6): planar polygon faces,
// counter-clockwise seen from outside, joined edge to edge, and each edge's fold angle. Millimetres
// and radians.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace flatmorph {

struct Polyhedron {
  Eigen::MatrixX3d V;                   // mm
  std::vector<std::vector<int>> faces;  // vertex indices, counter-clockwise seen from outside
  std::string source;                   // names it in errors
};

// An edge between two faces: v0 → v1 is its direction in face `left`'s counter-clockwise order
// (and v1 → v0 in face `right`'s); right = −1 on the border of an open solid.
struct PolyhedronEdge {
  int v0 = 0, v1 = 0;
  int left = 0, right = -1;
};

// Every edge once. Throws UserError (kTopology) naming the faces when an edge has three or more
// faces or two faces run it the same way (the faces are not consistently oriented), and (kGeometry)
// for a face of fewer than three vertices or a vertex index out of range.
std::vector<PolyhedronEdge> polyhedron_edges(const Polyhedron& solid);

// The unit normal of face f, outward (Newell's method: exact for planar polygons).
Eigen::Vector3d face_normal(const Polyhedron& solid, int f);

// The fold angle of an edge between two faces (notes §3): π − the dihedral angle, signed as FOLD's
// edges_foldAngle for a net laid outward side up: negative (a mountain) where the solid is convex,
// positive (a valley) where it is concave; 0 on the border. rad, in [−π, π].
double fold_angle(const Polyhedron& solid, const PolyhedronEdge& edge);

// The solid as a Wavefront OBJ of its polygon faces (MeshLab and Blender keep the polygons), mm.
std::string polyhedron_obj(const Polyhedron& solid);

}  // namespace flatmorph
