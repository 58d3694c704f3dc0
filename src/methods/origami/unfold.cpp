#include "methods/origami/unfold.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <random>

#include "mesh/polygon.h"

namespace flatmorph {
namespace {

// Face f of the solid in its own plane (face_to_plane), as 2D corners.
Eigen::MatrixX2d face_in_plane(const Polyhedron& solid, int f) {
  const RigidMotion m = face_to_plane(solid, f);
  const std::vector<int>& face = solid.faces[f];
  Eigen::MatrixX2d out(static_cast<Eigen::Index>(face.size()), 2);
  for (size_t i = 0; i < face.size(); ++i) {
    out.row(static_cast<Eigen::Index>(i)) =
        (m.R * solid.V.row(face[i]).transpose() + m.t).head<2>().transpose();
  }
  return out;
}

int corner_of(const Polyhedron& solid, int f, int vertex) {
  const std::vector<int>& face = solid.faces[f];
  return static_cast<int>(std::find(face.begin(), face.end(), vertex) - face.begin());
}

// Face `child` moved rigidly in the plane so that its side of `edge` lies on the placed parent's.
Eigen::MatrixX2d placed_across(const Polyhedron& solid, const PolyhedronEdge& edge, int child,
                               const Eigen::MatrixX2d& child_local, int parent,
                               const Eigen::MatrixX2d& parent_placed) {
  const Eigen::Vector2d p0 = parent_placed.row(corner_of(solid, parent, edge.v0)).transpose();
  const Eigen::Vector2d p1 = parent_placed.row(corner_of(solid, parent, edge.v1)).transpose();
  const Eigen::Vector2d q0 = child_local.row(corner_of(solid, child, edge.v0)).transpose();
  const Eigen::Vector2d q1 = child_local.row(corner_of(solid, child, edge.v1)).transpose();
  const double angle =
      std::atan2((p1 - p0).y(), (p1 - p0).x()) - std::atan2((q1 - q0).y(), (q1 - q0).x());
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(angle).toRotationMatrix();
  Eigen::MatrixX2d out =
      (child_local * rotation.transpose()).rowwise() + (p0 - rotation * q0).transpose();
  return out;
}

// The indices of `values` from the largest down, values within a billionth of the largest counted
// equal and kept in index order: rounding must not reorder equal lengths or areas, or a turned
// solid would unfold into another net.
std::vector<int> largest_first(const std::vector<double>& values) {
  const double largest = *std::max_element(values.begin(), values.end());
  std::vector<long long> key(values.size());
  for (size_t i = 0; i < values.size(); ++i) key[i] = std::llround(values[i] / (1e-9 * largest));
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] > key[b]; });
  return order;
}

// Kruskal's maximum spanning forest of the dual graph under `weight`.
std::vector<int> spanning_hinges(const std::vector<PolyhedronEdge>& edges, int num_faces,
                                 const std::vector<double>& weight) {
  const std::vector<int> order = largest_first(weight);
  std::vector<int> root(num_faces);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int f) {
    while (root[f] != f) f = root[f] = root[root[f]];
    return f;
  };
  std::vector<int> hinges;
  for (int e : order) {
    if (edges[e].right < 0 || !(weight[e] > 0)) continue;  // a border, or an edge to cut
    const int a = find(edges[e].left), b = find(edges[e].right);
    if (a == b) continue;
    root[a] = b;
    hinges.push_back(e);
  }
  return hinges;
}

}  // namespace

bool Unfolding::is_hinge(int edge) const {
  const PolyhedronEdge& e = edges[edge];
  return (e.right >= 0 && parent_edge(e.right) == edge) || parent_edge(e.left) == edge;
}

RigidMotion face_to_plane(const Polyhedron& solid, int f) {
  const std::vector<int>& face = solid.faces[f];
  const Eigen::Vector3d n = face_normal(solid, f);
  const Eigen::Vector3d origin = solid.V.row(face[0]).transpose();
  const Eigen::Vector3d x = (solid.V.row(face[1]).transpose() - origin).normalized();
  RigidMotion m;
  m.R.row(0) = x.transpose();
  m.R.row(1) = n.cross(x).transpose();
  m.R.row(2) = n.transpose();
  m.t = -m.R * origin;
  return m;
}

std::vector<std::pair<int, int>> net_overlaps(const Unfolding& unfolding, int net) {
  std::vector<std::pair<int, int>> out;
  const std::vector<int>& faces = unfolding.nets[net].faces;
  for (size_t i = 0; i < faces.size(); ++i) {
    for (size_t j = i + 1; j < faces.size(); ++j) {
      if (polygons_overlap(unfolding.flat[faces[i]], unfolding.flat[faces[j]])) {
        out.push_back(std::minmax(faces[i], faces[j]));
      }
    }
  }
  return out;
}

Unfolding unfold(const Polyhedron& solid, const UnfoldOptions& options) {
  Unfolding out;
  out.edges = polyhedron_edges(solid);
  out.faces = solid.faces;
  const int num_faces = static_cast<int>(solid.faces.size());
  const int num_edges = static_cast<int>(out.edges.size());
  out.fold_angle.resize(num_edges);
  for (int e = 0; e < num_edges; ++e) out.fold_angle(e) = fold_angle(solid, out.edges[e]);
  std::vector<Eigen::MatrixX2d> local(num_faces);
  std::vector<double> area(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    local[f] = face_in_plane(solid, f);
    area[f] = signed_area(local[f]);
  }
  double mountains = 0, valleys = 0;
  for (int e = 0; e < num_edges; ++e) {
    (out.fold_angle(e) < 0 ? mountains : valleys) += std::abs(out.fold_angle(e));
  }
  std::vector<double> hinge_weight(num_edges);  // the spanning tree keeps the heaviest
  for (int e = 0; e < num_edges; ++e) {
    hinge_weight[e] = (solid.V.row(out.edges[e].v0) - solid.V.row(out.edges[e].v1)).norm();
    const bool minority = valleys > mountains ? out.fold_angle(e) < 0 : out.fold_angle(e) > 0;
    if (minority) hinge_weight[e] *= options.minority_weight;
    if (!options.edge_weight.empty()) hinge_weight[e] *= options.edge_weight.at(e);
  }
  std::vector<std::vector<int>> face_edges(num_faces);
  for (int e = 0; e < num_edges; ++e) {
    face_edges[out.edges[e].left].push_back(e);
    if (out.edges[e].right >= 0) face_edges[out.edges[e].right].push_back(e);
  }

  // Lays the forest of `hinges` from the largest face of each tree, breadth first; with `split`,
  // a face that would overlap its net starts a net of its own instead.
  const auto lay = [&](const std::vector<int>& hinges, bool split) {
    std::vector<char> is_hinge(num_edges, 0);
    for (int e : hinges) is_hinge[e] = 1;
    out.parent_edge = Eigen::VectorXi::Constant(num_faces, -1);
    out.parent_face = Eigen::VectorXi::Constant(num_faces, -1);
    out.net_of_face = Eigen::VectorXi::Constant(num_faces, -1);
    out.flat.assign(num_faces, Eigen::MatrixX2d());
    out.nets.clear();
    const std::vector<int> by_area = largest_first(area);
    std::deque<int> roots(by_area.begin(), by_area.end());
    while (!roots.empty()) {
      const int root = roots.front();
      roots.pop_front();
      if (out.net_of_face(root) >= 0) continue;
      const int net = static_cast<int>(out.nets.size());
      out.nets.push_back({root, {root}});
      out.net_of_face(root) = net;
      out.flat[root] = local[root];
      std::deque<int> queue{root};
      while (!queue.empty()) {
        const int a = queue.front();
        queue.pop_front();
        for (int e : face_edges[a]) {
          if (!is_hinge[e]) continue;
          const PolyhedronEdge& edge = out.edges[e];
          const int b = edge.left == a ? edge.right : edge.left;
          if (out.net_of_face(b) >= 0) continue;
          const Eigen::MatrixX2d placed = placed_across(solid, edge, b, local[b], a, out.flat[a]);
          bool overlaps = false;
          for (size_t i = 0; split && !overlaps && i < out.nets[net].faces.size(); ++i) {
            overlaps = polygons_overlap(placed, out.flat[out.nets[net].faces[i]]);
          }
          if (overlaps) {
            roots.push_front(b);  // its own net, next
            continue;
          }
          out.flat[b] = placed;
          out.parent_edge(b) = e;
          out.parent_face(b) = a;
          out.net_of_face(b) = net;
          out.nets[net].faces.push_back(b);
          queue.push_back(b);
        }
      }
    }
  };

  std::mt19937 random(20181021);  // fixed: the same solid gives the same nets
  std::uniform_real_distribution<double> jitter(0.0, 1.0);
  std::vector<int> first_hinges;
  for (int attempt = 0; attempt < std::max(1, options.tries); ++attempt) {
    std::vector<double> weight = hinge_weight;
    if (attempt > 0) {
      for (double& w : weight) w *= 1 + jitter(random);
    }
    const std::vector<int> hinges = spanning_hinges(out.edges, num_faces, weight);
    if (attempt == 0) first_hinges = hinges;
    lay(hinges, false);
    bool clean = true;
    for (int net = 0; net < static_cast<int>(out.nets.size()) && clean; ++net) {
      clean = net_overlaps(out, net).empty();
    }
    if (clean) return out;
  }
  lay(first_hinges, true);
  return out;
}

std::vector<Eigen::MatrixX3d> fold_net(const Unfolding& unfolding, int net, double progress) {
  const size_t num_faces = unfolding.flat.size();
  std::vector<Eigen::Matrix3d> rotation(num_faces, Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> shift(num_faces, Eigen::Vector3d::Zero());
  std::vector<Eigen::MatrixX3d> out(num_faces);
  for (int b : unfolding.nets[net].faces) {  // every parent before its child
    const int e = unfolding.parent_edge(b);
    if (e >= 0) {
      const int a = unfolding.parent_face(b);
      const PolyhedronEdge& edge = unfolding.edges[e];
      // The hinge as face b runs it (counter-clockwise seen from +z): b lies to its left, and a
      // turn by +α about it lifts b toward +z, a valley (notes §3).
      const std::vector<int>& face = unfolding.faces[b];
      const int from = edge.left == b ? edge.v0 : edge.v1;
      const auto corner = std::find(face.begin(), face.end(), from) - face.begin();
      Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero();
      start.head<2>() = unfolding.flat[b].row(corner).transpose();
      end.head<2>() = unfolding.flat[b].row((corner + 1) % face.size()).transpose();
      const Eigen::Matrix3d turn =
          Eigen::AngleAxisd(progress * unfolding.fold_angle(e), (end - start).normalized())
              .toRotationMatrix();
      rotation[b] = rotation[a] * turn;
      shift[b] = rotation[a] * (start - turn * start) + shift[a];
    }
    const Eigen::MatrixX2d& flat = unfolding.flat[b];
    out[b].resize(flat.rows(), 3);
    for (Eigen::Index i = 0; i < flat.rows(); ++i) {
      out[b].row(i) =
          (rotation[b] * Eigen::Vector3d(flat(i, 0), flat(i, 1), 0) + shift[b]).transpose();
    }
  }
  return out;
}

}  // namespace flatmorph
