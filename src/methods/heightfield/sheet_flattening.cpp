#include "methods/heightfield/sheet_flattening.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/error.h"
#include "mesh/plane_geometry.h"
#include "mesh/topology.h"
#include "numerics/sparse_cholesky.h"

namespace flatmorph {
namespace {

// Below this largest height (times the mean edge length) the sheet counts as flat: z is dropped,
// which changes an edge's length by less than 1e-6 of itself.
constexpr double kFlatHeight = 1e-3;
// Steps kept for the plane after the heights are dropped, whatever the budget.
constexpr int kPlaneSteps = 5;
// Fold guard: a face whose area seen from above (signed, counter-clockwise positive) falls below
// this fraction of its 3D area is pushed back to twice that (a valid sheet's faces are larger in
// the plate than on the target: printing edges lengthen, bridges keep their length), with this
// weight (dimensionless, like an edge's). Nothing else in the energy tells a face from its mirror
// image: a sliver between two long bridges turns over at no cost.
constexpr double kFoldArea = 0.2;
constexpr double kFoldWeight = 1.0;
// Anderson acceleration of the plane steps: how many past steps are mixed.
constexpr int kAndersonHistory = 5;

void require(bool condition, const char* what) {
  if (!condition) throw std::invalid_argument(std::string("flatten_sheet: ") + what);
}

void check_options(const SheetFlatteningOptions& o) {
  auto fail = [](const std::string& what) {
    throw UserError(ErrorCategory::kOption, "sheet flattening: " + what);
  };
  const std::pair<const char*, double> weights[] = {
      {"printing", o.printing},         {"bridge", o.bridge},         {"bending", o.bending},
      {"straightness", o.straightness}, {"shear", o.shear},           {"closeness", o.closeness},
      {"flattening", o.flattening},     {"stretching", o.stretching}, {"spreading", o.spreading},
      {"smoothness", o.smoothness}};
  for (const auto& [name, value] : weights) {
    if (!(value >= 0 && std::isfinite(value))) {
      fail(std::string("weight ") + name + " = " + std::to_string(value) +
           " is not a number >= 0; use a value >= 0 (0 turns the term off)");
    }
  }
  if (!(o.closeness > 0)) fail("closeness must be > 0 (it fixes the sheet's free translation)");
  if (!(o.flattening < 1))
    fail("flattening must be < 1 (the fraction of the heights removed per step)");
  if (!(o.printing > 0 && o.bridge > 0)) fail("the printing and bridge weights must be > 0");
  if (!(o.min_shrinkage >= 0 && o.min_shrinkage < o.max_shrinkage && o.max_shrinkage < 1)) {
    fail("the shrinkage range [" + std::to_string(o.min_shrinkage) + ", " +
         std::to_string(o.max_shrinkage) + "] must satisfy 0 <= min < max < 1");
  }
  if (!(o.bridge_growth > 0 && std::isfinite(o.bridge_growth))) {
    fail("bridge_growth = " + std::to_string(o.bridge_growth) + " must be a number > 0");
  }
  if (o.max_steps < 1) fail("max_steps must be at least 1");
  if (!(o.tolerance > 0)) fail("tolerance must be > 0");
}

// A symmetric sparse matrix (lower triangle) whose pattern is fixed after the first assembly: later
// assemblies add the same contributions in the same order into the stored values, so CHOLMOD's
// symbolic analysis is done once for the whole run.
class Assembler {
 public:
  explicit Assembler(int n) : n_(n) {}
  void begin() {
    next_ = 0;
    if (recorded_) std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
  }
  void add(int i, int j, double value) {
    if (i < j) std::swap(i, j);
    if (!recorded_) {
      triplets_.emplace_back(i, j, value);
    } else {
      matrix_.valuePtr()[slots_[next_++]] += value;
    }
  }
  const Eigen::SparseMatrix<double>& finish() {
    if (!recorded_) {
      matrix_.resize(n_, n_);
      matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
      matrix_.makeCompressed();
      slots_.reserve(triplets_.size());
      for (const auto& t : triplets_) {
        const int col = t.col();
        const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col];
        const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col + 1];
        slots_.push_back(
            static_cast<int>(std::lower_bound(begin, end, t.row()) - matrix_.innerIndexPtr()));
      }
      triplets_.clear();
      triplets_.shrink_to_fit();
      recorded_ = true;
    } else if (next_ != slots_.size()) {
      throw std::logic_error("flatten_sheet: the system's pattern changed between steps");
    }
    return matrix_;
  }

 private:
  int n_;
  bool recorded_ = false;
  size_t next_ = 0;
  std::vector<Eigen::Triplet<double>> triplets_;
  std::vector<int> slots_;
  Eigen::SparseMatrix<double> matrix_;
};

// cot of the angle between u and w.
double cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
  const double sine = u.cross(w).norm();
  return sine > 0 ? u.dot(w) / sine : 0.0;
}

struct Hinge {
  int v[4];             // the edge's ends v0, v1; v2 opposite in one face, v3 in the other
  double rest_area[2];  // the two faces' areas on the target, mm²
};

struct PathTriple {
  int v[3];  // a path vertex's two path neighbours and itself: a, v, b
  double weight;
};

struct Corner {
  int v[3];  // the corner p0 and the ends of its two edges p1, p2
  double rest_angle;
  double weight;
};

struct PathPair {
  int v[3];        // a, v, b: the path edges a–v and v–b
  double rest[2];  // their 3D lengths
  double weight;
};

struct FaceGuard {
  double least_area;  // mm²: below it the guard holds the face
  double weight;
};

// The fixed data of one run: the constraints (§6.2.1) and what the relocations (§6.2.2) walk over.
struct Sheet {
  int nv = 0;
  Eigen::MatrixXi E, F;
  Eigen::VectorXd rest;          // l_3D per edge
  Eigen::VectorXd lower, upper;  // the admissible flat length of each edge, mm
  Eigen::VectorXd edge_weight;   // w / (l_3D l̄)
  double mean_length = 0;        // l̄
  std::vector<Hinge> hinges;
  std::vector<PathTriple> triples;
  std::vector<Corner> corners;
  std::vector<PathPair> pairs;
  std::vector<FaceGuard> guards;  // per face
  std::vector<int> boundary_vertices;
  std::vector<std::pair<int, int>> boundary_neighbours;  // per boundary vertex
  std::vector<char> interior_edge_of_corner;  // per face corner: the edge opposite it is interior
};

Sheet make_sheet(const IsolineMesh& mesh, const SheetFlatteningOptions& options) {
  const int nv = static_cast<int>(mesh.V.rows());
  require(mesh.V.cols() == 3, "V must be #V x 3");
  require(nv >= 3 && mesh.F.rows() >= 1 && mesh.F.cols() == 3, "the mesh has no face");
  require(mesh.V.allFinite(), "V has non-finite coordinates");
  require(mesh.F.minCoeff() >= 0 && mesh.F.maxCoeff() < nv, "a face index is out of range");
  require(mesh.E.cols() == 2 && static_cast<size_t>(mesh.E.rows()) == mesh.edge_kind.size(),
          "E and edge_kind differ in size");
  const EdgeTopology topology = edge_topology(mesh.F);
  const int ne = static_cast<int>(mesh.E.rows());
  require(topology.num_edges() == ne, "E is not the set of edges of F");
  std::map<std::pair<int, int>, int> index;
  for (int e = 0; e < ne; ++e) index.emplace(std::minmax(mesh.E(e, 0), mesh.E(e, 1)), e);
  require(static_cast<int>(index.size()) == ne, "E has a repeated edge");
  for (int t = 0; t < ne; ++t) {
    require(index.count(std::minmax(topology.edges(t, 0), topology.edges(t, 1))) == 1,
            "E is not the set of edges of F");
  }

  Sheet s;
  s.nv = nv;
  s.E = mesh.E;
  s.F = mesh.F;
  s.rest.resize(ne);
  for (int e = 0; e < ne; ++e) {
    s.rest(e) = (mesh.V.row(mesh.E(e, 1)) - mesh.V.row(mesh.E(e, 0))).norm();
    require(s.rest(e) > 0, "an edge has zero length");
  }
  s.mean_length = s.rest.mean();

  // Printing strain (§6.2.1 with the bounds the right way round, notes §3.2): the stretch
  // l / l_3D within [1/(1 − σ_min), 1/(1 − σ_max)]. Bridge strain: l = l_3D / λ2.
  s.lower.resize(ne);
  s.upper.resize(ne);
  s.edge_weight.resize(ne);
  std::vector<std::vector<int>> path_neighbours(nv);
  for (int e = 0; e < ne; ++e) {
    if (mesh.edge_kind[e] == EdgeKind::kBridge) {
      s.lower(e) = s.upper(e) = s.rest(e) / options.bridge_growth;
      s.edge_weight(e) = options.bridge / (s.rest(e) * s.mean_length);
    } else {
      s.lower(e) = s.rest(e) / (1 - options.min_shrinkage);
      s.upper(e) = s.rest(e) / (1 - options.max_shrinkage);
      s.edge_weight(e) = options.printing / (s.rest(e) * s.mean_length);
      path_neighbours[mesh.E(e, 0)].push_back(mesh.E(e, 1));
      path_neighbours[mesh.E(e, 1)].push_back(mesh.E(e, 0));
    }
  }

  // Bending (§6.2.1) on every interior edge.
  for (int t = 0; t < ne; ++t) {
    if (topology.is_boundary_edge(t)) continue;
    const int f0 = topology.edge_faces(t, 0), f1 = topology.edge_faces(t, 1);
    int k0 = 0, k1 = 0;
    while (topology.face_edges(f0, k0) != t) ++k0;
    while (topology.face_edges(f1, k1) != t) ++k1;
    // Edge k of face f runs from F(f, k) to F(f, k + 1); corner k + 2 is opposite it.
    require(
        mesh.F(f0, k0) == mesh.F(f1, (k1 + 1) % 3),
        "the faces are not consistently oriented (an edge runs the same way in both of its faces)");
    Hinge h{{mesh.F(f0, k0), mesh.F(f0, (k0 + 1) % 3), mesh.F(f0, (k0 + 2) % 3),
             mesh.F(f1, (k1 + 2) % 3)},
            {0, 0}};
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3d a = mesh.V.row(h.v[0]), b = mesh.V.row(h.v[1]),
                            c = mesh.V.row(h.v[2 + side]);
      h.rest_area[side] = 0.5 * (b - a).cross(c - a).norm();
    }
    s.hinges.push_back(h);
  }

  // Straightness (the code's reading of w_shear, notes §3.2): every vertex with exactly two path
  // edges (printing or boundary) and its two path neighbours.
  for (std::vector<int>& n : path_neighbours) std::sort(n.begin(), n.end());
  if (options.straightness > 0) {
    for (int v = 0; v < nv; ++v) {
      const std::vector<int>& n = path_neighbours[v];
      if (n.size() != 2) continue;
      const double length = 0.5 * ((mesh.V.row(n[0]) - mesh.V.row(v)).norm() +
                                   (mesh.V.row(n[1]) - mesh.V.row(v)).norm());
      s.triples.push_back({{n[0], v, n[1]}, options.straightness / (length * s.mean_length)});
    }
  }

  // Even shrinkage: the same path vertices, their two edges at one stretch.
  if (options.smoothness > 0) {
    for (int v = 0; v < nv; ++v) {
      const std::vector<int>& n = path_neighbours[v];
      if (n.size() != 2) continue;
      const double r0 = (mesh.V.row(n[0]) - mesh.V.row(v)).norm();
      const double r1 = (mesh.V.row(n[1]) - mesh.V.row(v)).norm();
      s.pairs.push_back(
          {{n[0], v, n[1]}, {r0, r1}, options.smoothness / (0.5 * (r0 + r1) * s.mean_length)});
    }
  }

  // Shear (the paper's text, §6.2.1): every face corner keeps its target angle.
  if (options.shear > 0) {
    for (int f = 0; f < mesh.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int p0 = mesh.F(f, k), p1 = mesh.F(f, (k + 1) % 3), p2 = mesh.F(f, (k + 2) % 3);
        const Eigen::Vector3d x0 = mesh.V.row(p1) - mesh.V.row(p0);
        const Eigen::Vector3d x1 = mesh.V.row(p2) - mesh.V.row(p0);
        const double angle = std::atan2(x0.cross(x1).norm(), x0.dot(x1));
        const double length = 0.5 * (x0.norm() + x1.norm());
        s.corners.push_back({{p0, p1, p2}, angle, options.shear / (length * s.mean_length)});
      }
    }
  }

  for (int f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const double shortest = std::min({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    s.guards.push_back(
        {kFoldArea * 0.5 * (b - a).cross(c - a).norm(), kFoldWeight / (shortest * s.mean_length)});
  }

  // Stretching walks the rim; spreading the face corners opposite interior edges.
  std::vector<std::vector<int>> rim(nv);
  for (int t = 0; t < ne; ++t) {
    if (!topology.is_boundary_edge(t)) continue;
    rim[topology.edges(t, 0)].push_back(topology.edges(t, 1));
    rim[topology.edges(t, 1)].push_back(topology.edges(t, 0));
  }
  for (int v = 0; v < nv; ++v) {
    if (rim[v].size() != 2) continue;  // a non-manifold rim vertex is left alone
    s.boundary_vertices.push_back(v);
    s.boundary_neighbours.emplace_back(rim[v][0], rim[v][1]);
  }
  s.interior_edge_of_corner.resize(3 * mesh.F.rows());
  for (int f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      s.interior_edge_of_corner[3 * f + k] =
          !topology.is_boundary_edge(topology.face_edges(f, (k + 1) % 3));
    }
  }
  return s;
}

// The vertex relocations of §6.2.2 applied to x (#V x 3).
void relocate(const Sheet& s, const SheetFlatteningOptions& o, Eigen::MatrixXd& x) {
  const int nf = static_cast<int>(s.F.rows());
  Eigen::MatrixXd shift = Eigen::MatrixXd::Zero(s.nv, 3);
  if (o.stretching > 0 || o.spreading > 0) {
    Eigen::MatrixXd area_normal(nf, 3);  // twice the area times the unit normal
    for (int f = 0; f < nf; ++f) {
      const Eigen::Vector3d a = x.row(s.F(f, 0)), b = x.row(s.F(f, 1)), c = x.row(s.F(f, 2));
      area_normal.row(f) = (b - a).cross(c - a).transpose();
    }
    if (o.stretching > 0) {
      // The area-weighted mean normal of a boundary vertex's faces, projected on the plane.
      Eigen::MatrixXd vertex_normal = Eigen::MatrixXd::Zero(s.nv, 3);
      Eigen::VectorXd vertex_area = Eigen::VectorXd::Zero(s.nv);
      for (int f = 0; f < nf; ++f) {
        const double area = area_normal.row(f).norm();
        for (int k = 0; k < 3; ++k) {
          vertex_normal.row(s.F(f, k)) += area_normal.row(f);
          vertex_area(s.F(f, k)) += area;
        }
      }
      for (size_t i = 0; i < s.boundary_vertices.size(); ++i) {
        const int v = s.boundary_vertices[i];
        if (!(vertex_area(v) > 0)) continue;
        const auto [a, b] = s.boundary_neighbours[i];
        const double length = 0.5 * ((x.row(a) - x.row(v)).norm() + (x.row(b) - x.row(v)).norm());
        shift.block<1, 2>(v, 0) +=
            o.stretching * length * vertex_normal.block<1, 2>(v, 0) / vertex_area(v);
      }
    }
    if (o.spreading > 0) {
      for (int f = 0; f < nf; ++f) {
        const double area = area_normal.row(f).norm();
        if (!(area > 0)) continue;
        const Eigen::RowVector2d normal_xy = area_normal.block<1, 2>(f, 0) / area;
        for (int k = 0; k < 3; ++k) {
          if (!s.interior_edge_of_corner[3 * f + k]) continue;
          const int v = s.F(f, k), a = s.F(f, (k + 1) % 3), b = s.F(f, (k + 2) % 3);
          const double length = 0.5 * ((x.row(a) - x.row(v)).norm() + (x.row(b) - x.row(v)).norm());
          shift.block<1, 2>(v, 0) += o.spreading * length * normal_xy;
        }
      }
    }
  }
  // Flattening: the heights above the mean decay geometrically (a flat sheet is left as it is).
  if (o.flattening > 0) {
    const double mean_z = x.col(2).mean();
    x.col(2) = (x.col(2).array() - mean_z) * (1 - o.flattening) + mean_z;
  }
  x += shift;
}

// The signed area of face f seen from above at x, mm²: negative when turned over.
double sheet_face_area(const Sheet& s, const Eigen::MatrixXd& x, int f) {
  const auto corner = [&](int k) -> Eigen::Vector2d {
    return x.row(s.F(f, k)).head<2>().transpose();
  };
  return triangle_signed_area(corner(0), corner(1), corner(2));
}

// Per face: whether its area seen from above is below its guard's least area at x.
std::vector<char> held_faces(const Sheet& s, const Eigen::MatrixXd& x) {
  std::vector<char> held(s.F.rows());
  for (int f = 0; f < s.F.rows(); ++f) {
    held[f] = !(sheet_face_area(s, x, f) >= s.guards[f].least_area);
  }
  return held;
}

// Faces turned over or collapsed (area seen from above below 1e-9 l̄², far below any real face).
int folded_faces(const Sheet& s, const Eigen::MatrixXd& x) {
  const double least = 1e-9 * s.mean_length * s.mean_length;
  int count = 0;
  for (int f = 0; f < s.F.rows(); ++f) {
    count += !(sheet_face_area(s, x, f) > least);
  }
  return count;
}

// The global step's matrix Σ w AᵀA + closeness I / l̄² at x̂: its values change with the bending
// weights and the held faces, its pattern never (every contribution is added, zero or not). Bending
// is left out once the sheet is planar: a plane sheet has no bending, and without it the matrix
// stays the same from one plane step to the next.
void assemble(const Sheet& s, const SheetFlatteningOptions& o, const Eigen::MatrixXd& xhat,
              bool bending, const std::vector<char>& held, Assembler& assembler) {
  assembler.begin();
  const double closeness = o.closeness / (s.mean_length * s.mean_length);
  for (int v = 0; v < s.nv; ++v) assembler.add(v, v, closeness);
  auto add_difference = [&](int a, int b, double w) {
    assembler.add(a, a, w);
    assembler.add(b, b, w);
    assembler.add(a, b, -w);
  };
  // The centred points of a triple or a face: w (I − 11ᵀ/3).
  auto add_centred = [&](const int* v, double w) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j <= i; ++j) assembler.add(v[i], v[j], w * ((i == j) - 1.0 / 3));
    }
  };
  for (int e = 0; e < s.E.rows(); ++e) add_difference(s.E(e, 0), s.E(e, 1), s.edge_weight(e));
  // Bending toward flat: w 3/(A0 + A1) |K x|², K from the cotangents of the current hinge (its
  // isometric unfolding, so the target mean-curvature vector is 0: notes §3.2).
  for (const Hinge& h : s.hinges) {
    double k[4] = {0, 0, 0, 0};
    double w = 0;
    if (bending && o.bending > 0) {
      Eigen::Vector3d p[4];
      for (int i = 0; i < 4; ++i) p[i] = xhat.row(h.v[i]).transpose();
      const Eigen::Vector3d e0 = p[1] - p[0], e1 = p[2] - p[0], e2 = p[3] - p[0], e3 = p[2] - p[1],
                            e4 = p[3] - p[1];
      const double area0 = 0.5 * e0.cross(e1).norm(), area1 = 0.5 * e0.cross(e2).norm();
      // A hinge whose faces have nearly collapsed has no meaningful cotangents (and they would
      // swamp the matrix): it is left to the other terms for this step.
      if (area0 > 1e-2 * h.rest_area[0] && area1 > 1e-2 * h.rest_area[1]) {
        const double c01 = cotangent(e0, e1), c02 = cotangent(e0, e2), c03 = cotangent(-e0, e3),
                     c04 = cotangent(-e0, e4);
        k[0] = c03 + c04, k[1] = c01 + c02, k[2] = -c01 - c03, k[3] = -c02 - c04;
        w = o.bending * 3 / (area0 + area1);
      }
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j <= i; ++j) assembler.add(h.v[i], h.v[j], w * k[i] * k[j]);
    }
  }
  for (const PathTriple& t : s.triples) add_centred(t.v, t.weight);
  for (const PathPair& p : s.pairs) {
    add_difference(p.v[0], p.v[1], p.weight);
    add_difference(p.v[1], p.v[2], p.weight);
  }
  for (const Corner& c : s.corners) {
    add_difference(c.v[0], c.v[1], c.weight);
    add_difference(c.v[0], c.v[2], c.weight);
  }
  for (int f = 0; f < s.F.rows(); ++f) {
    const int v[3] = {s.F(f, 0), s.F(f, 1), s.F(f, 2)};
    add_centred(v, held[f] ? s.guards[f].weight : 0.0);
  }
}

// The local step at x (its first D columns): Σ w Aᵀ P(x), P the projection of every constraint,
// and the energy Σ w |A x − P(x)|² (bending, a quadratic toward 0, is not in it).
template <int D>
Eigen::MatrixXd project(const Sheet& s, const Eigen::MatrixXd& x, const std::vector<char>& held,
                        double& energy) {
  using Vec = Eigen::Matrix<double, 1, D>;
  using Points = Eigen::Matrix<double, 3, D>;
  Eigen::Matrix<double, Eigen::Dynamic, D> rhs =
      Eigen::Matrix<double, Eigen::Dynamic, D>::Zero(s.nv, D);
  energy = 0;
  auto at = [&](int v) { return Vec(x.row(v).template head<D>()); };
  // A term w |x_b − x_a − p|².
  auto add_difference = [&](int a, int b, double w, const Vec& p) {
    energy += w * (at(b) - at(a) - p).squaredNorm();
    rhs.row(a) -= w * p;
    rhs.row(b) += w * p;
  };
  // Centred points q of a triple or a face and their projection.
  auto add_centred = [&](const int* v, double w, const Points& q, const Points& projected) {
    energy += w * (q - projected).squaredNorm();
    for (int i = 0; i < 3; ++i) rhs.row(v[i]) += w * projected.row(i);
  };
  auto centred = [&](const int* v) {
    Points q;
    for (int i = 0; i < 3; ++i) q.row(i) = at(v[i]);
    const Vec centre = q.colwise().mean();
    q.rowwise() -= centre;
    return q;
  };
  // Printing and bridge strain: the edge vector rescaled into its admissible lengths.
  for (int e = 0; e < s.E.rows(); ++e) {
    const int a = s.E(e, 0), b = s.E(e, 1);
    Vec d = at(b) - at(a);
    const double length = d.norm();
    if (length > 0) d *= std::clamp(length, s.lower(e), s.upper(e)) / length;
    add_difference(a, b, s.edge_weight(e), d);
  }
  // Straightness: the three points, centred, projected on their best-fitting line.
  for (const PathTriple& t : s.triples) {
    const Points q = centred(t.v);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eig;
    eig.computeDirect(Eigen::Matrix<double, D, D>(q.transpose() * q));
    const Eigen::Matrix<double, D, 1> u = eig.eigenvectors().col(D - 1);
    add_centred(t.v, t.weight, q, (q * u) * u.transpose());
  }
  // Even shrinkage: both edges rescaled, directions kept, to the common stretch nearest theirs.
  for (const PathPair& p : s.pairs) {
    const Vec d0 = at(p.v[1]) - at(p.v[0]), d1 = at(p.v[2]) - at(p.v[1]);
    const double l0 = d0.norm(), l1 = d1.norm();
    const double stretch =
        (l0 * p.rest[0] + l1 * p.rest[1]) / (p.rest[0] * p.rest[0] + p.rest[1] * p.rest[1]);
    add_difference(p.v[0], p.v[1], p.weight, l0 > 0 ? Vec(d0 * (stretch * p.rest[0] / l0)) : d0);
    add_difference(p.v[1], p.v[2], p.weight, l1 > 0 ? Vec(d1 * (stretch * p.rest[1] / l1)) : d1);
  }
  // Shear: both edges of a corner turned in their plane by equal and opposite angles, keeping
  // their lengths, until the corner has its target angle.
  for (const Corner& c : s.corners) {
    const Eigen::Vector3d x0 = x.row(c.v[1]) - x.row(c.v[0]);
    const Eigen::Vector3d x1 = x.row(c.v[2]) - x.row(c.v[0]);
    const Eigen::Vector3d normal = x0.cross(x1);
    Eigen::Vector3d y0 = x0, y1 = x1;
    if (normal.norm() > 0) {
      const double turn = 0.5 * (c.rest_angle - std::atan2(normal.norm(), x0.dot(x1)));
      const Eigen::Vector3d axis = normal.normalized();
      y0 = Eigen::AngleAxisd(-turn, axis) * x0;
      y1 = Eigen::AngleAxisd(turn, axis) * x1;
    }
    add_difference(c.v[0], c.v[1], c.weight, y0.head<D>().transpose());
    add_difference(c.v[0], c.v[2], c.weight, y1.head<D>().transpose());
  }
  // Fold guard: a held face's corners, centred, moved along the gradient of its area seen from
  // above until that area is twice the least one (heights untouched); left where they are when
  // the area is already that large.
  for (int f = 0; f < s.F.rows(); ++f) {
    if (!held[f]) continue;
    const int v[3] = {s.F(f, 0), s.F(f, 1), s.F(f, 2)};
    const Points q = centred(v);
    Points projected = q;
    Eigen::Matrix<double, 3, 2> g;  // ∂ area / ∂ corner
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      g.row(i) << 0.5 * (q(j, 1) - q(k, 1)), 0.5 * (q(k, 0) - q(j, 0));
    }
    auto area_of = [](const auto& p) {
      return 0.5 * ((p(1, 0) - p(0, 0)) * (p(2, 1) - p(0, 1)) -
                    (p(1, 1) - p(0, 1)) * (p(2, 0) - p(0, 0)));
    };
    const double gg = g.squaredNorm(), missing = 2 * s.guards[f].least_area - area_of(q);
    if (gg > 0 && missing > 0) {
      // area(q + t g) = area(q) + t |g|² + t² area(g): the least t > 0 that restores it.
      const double g_area = area_of(g);
      double t = missing / gg;
      const double disc = gg * gg + 4 * g_area * missing;
      if (g_area != 0 && disc >= 0) {
        const double root = (-gg + std::sqrt(disc)) / (2 * g_area);
        if (root > 0) t = root;
      }
      projected.template leftCols<2>() += t * g;
    }
    add_centred(v, s.guards[f].weight, q, projected);
  }
  return rhs;
}

// Numeric factorization of the assembled matrix (symbolic analysis on the first call only); the
// caller checks solver.info().
void factorize_system(const Eigen::SparseMatrix<double>& matrix, SparseCholesky& solver,
                      bool& analyzed) {
  if (!analyzed) {
    configure_sparse_cholesky(solver);
    analyze_pattern(solver, matrix);
    analyzed = true;
  }
  factorize(solver, matrix);
}

// Σ w AᵀA + closeness I without bending is positive definite for any positions: a failure is a bug.
void require_factorized(const SparseCholesky& solver) {
  if (solver.info() != Eigen::Success) {
    throw std::logic_error("flatten_sheet: the global step's matrix is not positive definite");
  }
}

Eigen::VectorXd edge_lengths(const Eigen::MatrixXi& E, const Eigen::MatrixXd& x) {
  Eigen::VectorXd l(E.rows());
  for (int e = 0; e < E.rows(); ++e) l(e) = (x.row(E(e, 1)) - x.row(E(e, 0))).norm();
  return l;
}

// The mean relative change of the edge lengths from x to y.
double relative_change(const Eigen::MatrixXi& E, const Eigen::MatrixXd& x,
                       const Eigen::MatrixXd& y) {
  const Eigen::VectorXd before = edge_lengths(E, x), after = edge_lengths(E, y);
  return ((after - before).array().abs() / before.array()).mean();
}

double max_height(const Eigen::MatrixXd& x) {
  return (x.col(2).array() - x.col(2).mean()).abs().maxCoeff();
}

}  // namespace

Eigen::VectorXd sheet_edge_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate) {
  if (plate.rows() != mesh.V.rows() || plate.cols() < 2 ||
      static_cast<size_t>(mesh.E.rows()) != mesh.edge_kind.size()) {
    throw std::invalid_argument("sheet_edge_shrinkage: plate, V, E and edge_kind differ in size");
  }
  Eigen::VectorXd sigma(mesh.E.rows());
  for (int e = 0; e < mesh.E.rows(); ++e) {
    const int a = mesh.E(e, 0), b = mesh.E(e, 1);
    if (mesh.edge_kind[e] == EdgeKind::kBridge) {
      sigma(e) = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const double target = (mesh.V.row(b) - mesh.V.row(a)).norm();
    const double flat = (plate.block<1, 2>(b, 0) - plate.block<1, 2>(a, 0)).norm();
    sigma(e) = 1 - target / flat;
  }
  return sigma;
}

FlatSheet flatten_sheet(const IsolineMesh& mesh, const SheetFlatteningOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  const Sheet s = make_sheet(mesh, options);

  Assembler assembler(s.nv);
  SparseCholesky solver;
  bool analyzed = false;
  const double closeness = options.closeness / (s.mean_length * s.mean_length);
  FlatSheet result;
  double change = std::numeric_limits<double>::infinity();
  auto report = [&](int step, double height) {
    result.steps = step;
    if (options.progress) options.progress(step, change, height);
  };

  // Pressed into the plane (§6.2): the relocations, then one local/global step with the bending
  // weights of the relocated sheet, until its heights are negligible (or only the plane steps are
  // left in the budget).
  Eigen::MatrixXd x = mesh.V;
  int step = 0;
  while (step < options.max_steps - kPlaneSteps) {
    ++step;
    Eigen::MatrixXd xhat = x;
    relocate(s, options, xhat);
    const std::vector<char> held = held_faces(s, xhat);
    assemble(s, options, xhat, true, held, assembler);
    factorize_system(assembler.finish(), solver, analyzed);
    if (solver.info() != Eigen::Success) {
      // The bending weights of a badly shaped sheet can make the matrix numerically indefinite;
      // the step is then taken without them (the matrix is then positive definite by construction).
      assemble(s, options, xhat, false, held, assembler);
      factorize_system(assembler.finish(), solver, analyzed);
      require_factorized(solver);
    }
    double energy = 0;
    const Eigen::MatrixXd next = solver.solve(project<3>(s, xhat, held, energy) + closeness * xhat);
    change = relative_change(s.E, x, next);
    x = next;
    const double height = max_height(x);
    report(step, height);
    if (height <= kFlatHeight * s.mean_length) break;
  }
  const double dropped_height = max_height(x);

  // The plane sheet: z dropped, then local/global steps on a matrix that changes only when a face
  // starts or stops being held, accelerated by Anderson mixing of the last few steps (Peng et al.
  // 2018: a mixed point is kept only if its energy is below the last one and it folds no more faces
  // than the plain step, else the plain step is taken), until a plain step changes the edge lengths
  // by less than the tolerance on average.
  x.col(2).setZero();
  Eigen::MatrixXd point = x;  // the current iterate, #V x 3 with z = 0
  Eigen::MatrixXd plain;      // the plain local/global step from the last one kept
  double kept_energy = std::numeric_limits<double>::infinity();
  std::vector<char> factorized_held;
  std::vector<Eigen::VectorXd> dg, df;  // differences of the last steps' outputs, residuals
  Eigen::VectorXd last_g, last_f;
  // A face once held stays held (its guard is idle while the face is large enough): guards
  // switching on and off would refactor the matrix at every other step.
  auto hold = [&](const Eigen::MatrixXd& p) {
    std::vector<char> h = held_faces(s, p);
    for (size_t f = 0; f < h.size() && f < factorized_held.size(); ++f) h[f] |= factorized_held[f];
    return h;
  };
  while (step < options.max_steps) {
    ++step;
    std::vector<char> held = hold(point);
    double energy = 0;
    Eigen::MatrixXd rhs = project<2>(s, point, held, energy);
    if (plain.size() > 0 &&
        (!(energy < kept_energy) || folded_faces(s, point) > folded_faces(s, plain))) {
      point = plain;
      held = hold(point);
      rhs = project<2>(s, point, held, energy);
      dg.clear();
      df.clear();
    }
    kept_energy = energy;
    if (held != factorized_held) {
      assemble(s, options, point, false, held, assembler);
      factorize_system(assembler.finish(), solver, analyzed);
      require_factorized(solver);
      factorized_held = held;
      dg.clear();
      df.clear();
      last_g.resize(0);
    }
    plain = point;
    plain.leftCols(2) = solver.solve(rhs + closeness * point.leftCols(2));
    change = relative_change(s.E, point, plain);
    report(step, 0.0);
    if (change < options.tolerance) {
      point = plain;
      result.converged = true;
      break;
    }
    const Eigen::VectorXd g = plain.leftCols(2).reshaped();
    const Eigen::VectorXd f = g - point.leftCols(2).reshaped();
    if (last_g.size() > 0) {
      dg.push_back(g - last_g);
      df.push_back(f - last_f);
      if (static_cast<int>(dg.size()) > kAndersonHistory) {
        dg.erase(dg.begin());
        df.erase(df.begin());
      }
    }
    last_g = g;
    last_f = f;
    Eigen::VectorXd mixed = g;
    if (!df.empty()) {
      Eigen::MatrixXd DF(f.size(), df.size()), DG(g.size(), dg.size());
      for (size_t k = 0; k < df.size(); ++k) DF.col(k) = df[k], DG.col(k) = dg[k];
      const Eigen::VectorXd theta = DF.colPivHouseholderQr().solve(f);
      if (theta.allFinite()) mixed = g - DG * theta;
    }
    point.leftCols(2) = mixed.reshaped(s.nv, 2);
  }
  if (!result.converged) point = plain;

  // Rigid placement: centroid at the origin; a mirror image (the whole sheet turned over) put
  // back; then the rotation that best matches the target's footprint (2D Procrustes), so that
  // turning the target about z turns the plate alike.
  Eigen::MatrixXd plate = point.leftCols(2);
  plate.rowwise() -= plate.colwise().mean().eval();
  double total_area = 0;
  for (int f = 0; f < s.F.rows(); ++f) {
    total_area += sheet_face_area(s, plate, f);
  }
  if (total_area < 0) plate.col(0) *= -1;
  Eigen::MatrixXd footprint = mesh.V.leftCols(2);
  footprint.rowwise() -= footprint.colwise().mean().eval();
  const double cross = (plate.col(0).array() * footprint.col(1).array() -
                        plate.col(1).array() * footprint.col(0).array())
                           .sum();
  const double dot = (plate.array() * footprint.array()).sum();
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(std::atan2(cross, dot)).toRotationMatrix();
  result.plate = plate * rotation.transpose();

  result.edge_shrinkage = sheet_edge_shrinkage(mesh, result.plate);
  int paths = 0, invalid = 0;
  for (int e = 0; e < s.E.rows(); ++e) {
    if (mesh.edge_kind[e] == EdgeKind::kBridge) continue;
    ++paths;
    const double sigma = result.edge_shrinkage(e);
    if (!(sigma >= options.min_shrinkage - kShrinkageRangeTolerance &&
          sigma <= options.max_shrinkage + kShrinkageRangeTolerance)) {
      ++invalid;
    }
  }
  result.invalid_edge_percent = paths > 0 ? 100.0 * invalid / paths : 0.0;
  result.flipped_faces = folded_faces(s, result.plate);

  std::ostringstream reason;
  reason.precision(3);
  if (result.converged) {
    reason << "converged after " << result.steps << " steps (mean relative edge change " << change
           << " < " << options.tolerance << ")";
  } else {
    reason << "step limit reached (" << options.max_steps << " steps; mean relative edge change "
           << change << ", tolerance " << options.tolerance << ")";
  }
  if (dropped_height > kFlatHeight * s.mean_length) {
    reason << "; the step budget ran out before the sheet was flat: heights up to "
           << dropped_height << " mm were dropped";
    result.converged = false;
  }
  if (result.flipped_faces > 0) {
    reason << "; " << result.flipped_faces << " of " << s.F.rows()
           << " faces are folded over or collapsed in the plate";
    result.converged = false;
  }
  result.stop_reason = reason.str();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace flatmorph
