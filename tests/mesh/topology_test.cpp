#include "mesh/topology.h"

#include <gtest/gtest.h>

namespace flatmorph::topology_test {
namespace {

// Two triangles sharing edge (1,2): a square split along its diagonal.
Eigen::MatrixXi square_faces() {
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 2, 1, 3;
  return F;
}

TEST(Topology, EdgesAndAdjacencyOfTwoTriangles) {
  const EdgeTopology t = edge_topology(square_faces());
  ASSERT_EQ(t.num_edges(), 5);
  // Edge 1 of face 0 is (1,2); it is edge 0 of face 1 in reverse.
  EXPECT_EQ(t.face_faces(0, 1), 1);
  EXPECT_EQ(t.face_faces_edge(0, 1), 0);
  EXPECT_EQ(t.face_faces(1, 0), 0);
  EXPECT_EQ(t.face_edges(0, 1), t.face_edges(1, 0));
  int boundary = 0;
  for (int e = 0; e < t.num_edges(); ++e) boundary += t.is_boundary_edge(e);
  EXPECT_EQ(boundary, 4);
}

TEST(Topology, NonManifoldEdgeThrows) {
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_THROW(edge_topology(F), std::invalid_argument);
}

TEST(Topology, BoundaryLoopFollowsFaceOrientation) {
  const auto loops = boundary_loops(square_faces());
  ASSERT_EQ(loops.size(), 1u);
  ASSERT_EQ(loops[0].size(), 4u);
  // Counter-clockwise square 0-1-3-2: walking edges as faces use them gives 0->1->3->2.
  std::vector<int> expected{0, 1, 3, 2};
  EXPECT_EQ(loops[0], expected);
}

TEST(Topology, ComponentsAndEuler) {
  Eigen::MatrixXi F(3, 3);
  F << 0, 1, 2, 2, 1, 3, 4, 5, 6;
  Eigen::VectorXi component;
  EXPECT_EQ(face_components(F, component), 2);
  EXPECT_EQ(component(0), component(1));
  EXPECT_NE(component(0), component(2));
  EXPECT_EQ(euler_characteristic(square_faces()), 1);
  // Closed tetrahedron: chi = 2.
  Eigen::MatrixXi T(4, 3);
  T << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  EXPECT_EQ(euler_characteristic(T), 2);
  EXPECT_TRUE(boundary_loops(T).empty());
}

}  // namespace
}  // namespace flatmorph::topology_test
