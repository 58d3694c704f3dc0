// Connectivity of a triangle mesh: edges, face adjacency, boundary loops, components.
// Edge k of face f runs from F(f,k) to F(f,(k+1)%3); corner k is opposite edge (k+1)%3.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/mesh.h"

namespace flatmorph {

// Undirected edges and how faces use them. Requires an edge-manifold mesh (at most two faces per
// edge); diagnose_mesh reports meshes that are not.
struct EdgeTopology {
  Eigen::MatrixXi edges;        // #E x 2, vertex indices with edges(e,0) < edges(e,1), sorted
  Eigen::MatrixXi face_edges;   // #F x 3, face_edges(f,k) = edge index of edge k of face f
  Eigen::MatrixXi edge_faces;   // #E x 2, the faces on each side; -1 where there is none
  Eigen::MatrixXi face_faces;   // #F x 3, face_faces(f,k) = face across edge k of f, or -1
  Eigen::MatrixXi face_faces_edge;  // #F x 3, the k' of edge k of f inside face_faces(f,k), or -1

  int num_edges() const { return static_cast<int>(edges.rows()); }
  bool is_boundary_edge(int e) const { return edge_faces(e, 1) < 0; }
};

EdgeTopology edge_topology(const Eigen::MatrixXi& F);

// Boundary loops as vertex sequences, each walked in the direction its edges have in their faces
// (so the surface lies on the left when seen from the normal side). Sorted longest first (by
// vertex count, ties by smallest first vertex) so the result is deterministic.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F);

// Component id per face (faces sharing an edge are connected), numbered from 0 in order of the
// first face of each component. Returns the number of components.
int face_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component);

// V - E + F over the vertices referenced by F.
int euler_characteristic(const Eigen::MatrixXi& F);

// For each vertex, the faces around it (unordered, increasing face index).
std::vector<std::vector<int>> vertex_faces(const Eigen::MatrixXi& F, int num_vertices);

}  // namespace flatmorph
