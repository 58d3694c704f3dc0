#include "mesh/mesh.h"

#include <algorithm>

namespace flatmorph {
namespace {

const Eigen::VectorXd* find(const std::vector<ScalarProperty>& list, const std::string& name) {
  auto it = std::find_if(list.begin(), list.end(), [&](const auto& p) { return p.name == name; });
  return it == list.end() ? nullptr : &it->values;
}

void set(std::vector<ScalarProperty>& list, const std::string& name, Eigen::VectorXd values) {
  auto it = std::find_if(list.begin(), list.end(), [&](const auto& p) { return p.name == name; });
  if (it == list.end()) {
    list.push_back({name, std::move(values)});
  } else {
    it->values = std::move(values);
  }
}

}  // namespace

const Eigen::VectorXd* MeshProperties::find_vertex(const std::string& name) const {
  return find(vertex, name);
}
const Eigen::VectorXd* MeshProperties::find_face(const std::string& name) const {
  return find(face, name);
}
void MeshProperties::set_vertex(const std::string& name, Eigen::VectorXd values) {
  set(vertex, name, std::move(values));
}
void MeshProperties::set_face(const std::string& name, Eigen::VectorXd values) {
  set(face, name, std::move(values));
}

}  // namespace flatmorph
