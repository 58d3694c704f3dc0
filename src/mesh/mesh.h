// The triangle mesh every stage passes around, and the named scalar fields stored with it.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace flatmorph {

// A triangle mesh over Eigen matrices (libigl's V, F convention).
// Units: millimetres once a mesh has been through `prepare`; raw files keep their own units.
struct Mesh {
  Eigen::MatrixXd V;  // #V x 3 vertex positions
  Eigen::MatrixXi F;  // #F x 3 vertex indices; the normal follows the right-hand rule on this order

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(F.rows()); }
};

// A named scalar per vertex or per face (e.g. theta1 in radians, deviation_mm).
struct ScalarProperty {
  std::string name;
  Eigen::VectorXd values;
};

// Named per-vertex and per-face scalars, kept in the order they were added (files list them so).
struct MeshProperties {
  std::vector<ScalarProperty> vertex;
  std::vector<ScalarProperty> face;

  // nullptr when there is no property of that name.
  const Eigen::VectorXd* find_vertex(const std::string& name) const;
  const Eigen::VectorXd* find_face(const std::string& name) const;
  // Adds the property, or replaces the one with the same name.
  void set_vertex(const std::string& name, Eigen::VectorXd values);
  void set_face(const std::string& name, Eigen::VectorXd values);
};

}  // namespace flatmorph
