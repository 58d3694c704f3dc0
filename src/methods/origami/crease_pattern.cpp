#include "methods/origami/crease_pattern.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

namespace flatmorph {
namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

int CreasePattern::other_face(int c, int f) const {
  const Crease& crease = creases[c];
  return crease.left == f ? crease.right : crease.left;
}

bool CreasePattern::is_hinge(int c) const {
  const Crease& crease = creases[c];
  if (crease.kind != CreaseKind::kMountain && crease.kind != CreaseKind::kValley) return false;
  return parent_crease[crease.left] == c || (crease.right >= 0 && parent_crease[crease.right] == c);
}

CreasePattern crease_pattern_of_net(const Unfolding& unfolding, int net, const std::string& name,
                                    double flat_angle) {
  if (net < 0 || net >= static_cast<int>(unfolding.nets.size())) {
    throw std::invalid_argument("crease_pattern_of_net: no such net");
  }
  // The sheet's faces in the solid's order, so that face numbers read the same in every file.
  std::vector<int> solid_faces = unfolding.nets[net].faces;
  std::sort(solid_faces.begin(), solid_faces.end());
  std::vector<int> local(unfolding.faces.size(), -1);
  for (size_t i = 0; i < solid_faces.size(); ++i) local[solid_faces[i]] = static_cast<int>(i);

  // A corner of the sheet per (face, corner); a hinge welds the corners its two faces share.
  std::vector<int> first_corner(solid_faces.size() + 1, 0);
  for (size_t i = 0; i < solid_faces.size(); ++i) {
    first_corner[i + 1] =
        first_corner[i] + static_cast<int>(unfolding.faces[solid_faces[i]].size());
  }
  std::vector<int> weld(first_corner.back());
  std::iota(weld.begin(), weld.end(), 0);
  auto corner_id = [&](int f, int vertex) {
    const std::vector<int>& face = unfolding.faces[f];
    return first_corner[local[f]] +
           static_cast<int>(std::find(face.begin(), face.end(), vertex) - face.begin());
  };
  for (int f : solid_faces) {
    const int e = unfolding.parent_edge(f);
    if (e < 0) continue;
    const PolyhedronEdge& edge = unfolding.edges[e];
    const int parent = unfolding.parent_face(f);
    for (int vertex : {edge.v0, edge.v1}) {
      weld[find_root(weld, corner_id(f, vertex))] = find_root(weld, corner_id(parent, vertex));
    }
  }

  CreasePattern out;
  out.name = name;
  std::vector<int> sheet_vertex(weld.size(), -1);
  std::vector<int> members;
  int num_vertices = 0;
  for (size_t c = 0; c < weld.size(); ++c) {
    const int r = find_root(weld, static_cast<int>(c));
    if (sheet_vertex[r] < 0) sheet_vertex[r] = num_vertices++;
    sheet_vertex[c] = sheet_vertex[r];
  }
  out.V = Eigen::MatrixX2d::Zero(num_vertices, 2);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(num_vertices);
  out.faces.resize(solid_faces.size());
  for (size_t i = 0; i < solid_faces.size(); ++i) {
    const Eigen::MatrixX2d& flat = unfolding.flat[solid_faces[i]];
    for (Eigen::Index k = 0; k < flat.rows(); ++k) {
      const int v = sheet_vertex[first_corner[i] + k];
      out.V.row(v) += flat.row(k);
      count(v) += 1;
      out.faces[i].push_back(v);
    }
  }
  out.V.array().colwise() /= count.array();

  // Creases: a welded side is one crease between its two faces, every other side a border.
  const int num_faces = static_cast<int>(solid_faces.size());
  out.parent_crease.assign(num_faces, -1);
  std::map<std::pair<int, int>, int> crease_of_side;  // (v0, v1) as the left face runs it
  for (int i = 0; i < num_faces; ++i) {
    const std::vector<int>& face = out.faces[i];
    for (size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      const auto twin = crease_of_side.find({b, a});
      if (twin != crease_of_side.end()) {
        out.creases[twin->second].right = i;
        continue;
      }
      crease_of_side[{a, b}] = static_cast<int>(out.creases.size());
      Crease crease;
      crease.v0 = a;
      crease.v1 = b;
      crease.left = i;
      out.creases.push_back(crease);
    }
  }
  for (int f : solid_faces) {
    const int e = unfolding.parent_edge(f);
    if (e < 0) {
      out.root = local[f];
      continue;
    }
    // The crease between f and its parent: the side of f whose ends are the hinge's corners.
    const int a = sheet_vertex[corner_id(f, unfolding.edges[e].v0)];
    const int b = sheet_vertex[corner_id(f, unfolding.edges[e].v1)];
    auto it = crease_of_side.find({a, b});
    if (it == crease_of_side.end()) it = crease_of_side.find({b, a});
    Crease& crease = out.creases[it->second];
    const double angle = unfolding.fold_angle(e);
    crease.fold_angle = std::abs(angle) < flat_angle ? 0.0 : angle;
    crease.kind = std::abs(angle) < flat_angle ? CreaseKind::kFlat
                  : angle > 0                  ? CreaseKind::kValley
                                               : CreaseKind::kMountain;
    out.parent_crease[local[f]] = it->second;
  }
  for (int f : unfolding.nets[net].faces) out.fold_order.push_back(local[f]);
  out.solid_face = solid_faces;
  return out;
}

CreasePattern turned_over(const CreasePattern& pattern) {
  CreasePattern out = pattern;
  out.V.col(1) *= -1;
  for (std::vector<int>& face : out.faces) std::reverse(face.begin(), face.end());
  for (Crease& crease : out.creases) {
    std::swap(crease.v0, crease.v1);  // still counter-clockwise around its left face
    crease.fold_angle = -crease.fold_angle;
    if (crease.kind == CreaseKind::kMountain) {
      crease.kind = CreaseKind::kValley;
    } else if (crease.kind == CreaseKind::kValley) {
      crease.kind = CreaseKind::kMountain;
    }
  }
  return out;
}

}  // namespace flatmorph
