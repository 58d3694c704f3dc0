#include "toolpath/stripe_patterns.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "common/angles.h"
#include "mesh/operators.h"
#include "numerics/sparse_cholesky.h"
#include "toolpath/line_field.h"

namespace flatmorph {
namespace {

// Phases closer than this to an isoline level are moved off it (radians).
constexpr double kPhaseNudge = 1e-9;

// X_v, the unit vector at theta_v + pi/2: the square root of z_v = -e^{2 i theta_v} taken as
// e^{i arg(z_v) / 2}, arg in (-pi, pi] (the sign choice only decides which edges cross sheets).
Eigen::MatrixXd phase_directions(const Eigen::VectorXd& theta) {
  Eigen::MatrixXd X(theta.size(), 2);
  for (int v = 0; v < theta.size(); ++v) {
    const double half_arg = 0.5 * std::arg(-std::polar(1.0, 2 * theta(v)));
    X.row(v) << std::cos(half_arg), std::sin(half_arg);
  }
  return X;
}

// Half the cotangent of the angle opposite edge k of each face (edge k runs from corner k to k+1).
Eigen::MatrixXd half_cotangents(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd half_cot(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d o = V.row(F(f, (k + 2) % 3)).head<2>().transpose();
      const Eigen::Vector2d a = V.row(F(f, k)).head<2>().transpose() - o;
      const Eigen::Vector2d b = V.row(F(f, (k + 1) % 3)).head<2>().transpose() - o;
      const double cross = std::abs(a.x() * b.y() - a.y() * b.x());
      half_cot(f, k) = cross > 0 ? 0.5 * a.dot(b) / cross : 0;
    }
  }
  return half_cot;
}

// Everything about one field that the energy and the phases need.
struct FieldData {
  Eigen::MatrixXd X;       // #V x 2 phase directions
  Eigen::VectorXi sign;    // per edge
  Eigen::VectorXd omega;   // per edge: target phase increment i -> j in the sign of X_i (rad)
  Eigen::VectorXd weight;  // per edge: cotan weight over the non-singular faces, clamped to >= 0
  Eigen::VectorXi doubled_index;
};

FieldData field_data(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const EdgeTopology& topology, const Eigen::MatrixXd& half_cot,
                     const Eigen::VectorXd& theta, double nu) {
  FieldData d;
  d.X = phase_directions(theta);
  d.doubled_index = line_field_doubled_index(F, theta);
  const int ne = topology.num_edges();
  d.sign.resize(ne);
  d.omega.resize(ne);
  d.weight.setZero(ne);
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    const Eigen::Vector2d Xi = d.X.row(i), Xj = d.X.row(j);
    d.sign(e) = Xi.dot(Xj) >= 0 ? 1 : -1;
    const Eigen::Vector2d edge = (V.row(j) - V.row(i)).head<2>();
    // Knöppel et al. 2015 §5: the phase 1-form integrated along the edge, nu <X, e> with X the
    // mean of the two (sign-aligned) directions.
    d.omega(e) = 0.5 * nu * (Xi + d.sign(e) * Xj).dot(edge);
  }
  for (int f = 0; f < F.rows(); ++f) {
    if (d.doubled_index(f) != 0) continue;  // no alignment is asked where the field is singular
    for (int k = 0; k < 3; ++k) d.weight(topology.face_edges(f, k)) += half_cot(f, k);
  }
  d.weight = d.weight.cwiseMax(0.0);
  return d;
}

// The connection Laplacian E (Knöppel et al. 2015 Eq. 9 in real 2x2 blocks, vertex v at rows 2v,
// 2v+1): per edge w |psi_j - e^{i omega} psi_i|^2, with conj(psi_i) for edges that cross sheets.
// Every field has the same sparsity, so the matrix is built once and each field only rewrites its
// values through the positions kept per edge. Held with a diagonal shift added, the matrix the
// inverse power iteration factorizes.
struct ConnectionLaplacian {
  Eigen::SparseMatrix<double> A;  // E + diag(shift), 2 #V x 2 #V, both triangles stored
  Eigen::VectorXd shift;          // 2 #V
  std::vector<int> diagonal;      // per row, the position of its diagonal entry
  // Per edge, positions in A.valuePtr(): [0..3] the diagonal entries 2i, 2i+1, 2j, 2j+1; [4..11]
  // block (j, i) row-major (r, q) -> entry (2j + r, 2i + q), then its transpose's entries.
  std::vector<std::array<int, 12>> slots;
};

ConnectionLaplacian connection_laplacian_pattern(const EdgeTopology& topology,
                                                 const Eigen::VectorXd& shift) {
  const int nv = static_cast<int>(shift.size() / 2);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(12 * topology.num_edges());
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    for (int r = 0; r < 2; ++r) {
      t.emplace_back(2 * i + r, 2 * i + r, 1.0);
      t.emplace_back(2 * j + r, 2 * j + r, 1.0);
      for (int q = 0; q < 2; ++q) {
        t.emplace_back(2 * j + r, 2 * i + q, 1.0);
        t.emplace_back(2 * i + q, 2 * j + r, 1.0);
      }
    }
  }
  for (int r = 0; r < 2 * nv; ++r) t.emplace_back(r, r, 1.0);
  ConnectionLaplacian L;
  L.shift = shift;
  L.A.resize(2 * nv, 2 * nv);
  L.A.setFromTriplets(t.begin(), t.end());
  L.A.makeCompressed();
  const auto position = [&](int row, int col) {
    const int* begin = L.A.innerIndexPtr() + L.A.outerIndexPtr()[col];
    const int* end = L.A.innerIndexPtr() + L.A.outerIndexPtr()[col + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - L.A.innerIndexPtr());
  };
  L.diagonal.resize(2 * nv);
  for (int r = 0; r < 2 * nv; ++r) L.diagonal[r] = position(r, r);
  L.slots.resize(topology.num_edges());
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    std::array<int, 12>& s = L.slots[e];
    s[0] = position(2 * i, 2 * i);
    s[1] = position(2 * i + 1, 2 * i + 1);
    s[2] = position(2 * j, 2 * j);
    s[3] = position(2 * j + 1, 2 * j + 1);
    for (int r = 0; r < 2; ++r) {
      for (int q = 0; q < 2; ++q) {
        s[4 + 2 * r + q] = position(2 * j + r, 2 * i + q);
        s[8 + 2 * r + q] = position(2 * i + q, 2 * j + r);
      }
    }
  }
  return L;
}

void set_connection_laplacian(const FieldData& d, ConnectionLaplacian& L) {
  double* value = L.A.valuePtr();
  std::fill(value, value + L.A.nonZeros(), 0.0);
  for (size_t r = 0; r < L.diagonal.size(); ++r) value[L.diagonal[r]] = L.shift(r);
  for (size_t e = 0; e < L.slots.size(); ++e) {
    const std::array<int, 12>& s = L.slots[e];
    const double w = d.weight(e), c = std::cos(d.omega(e)), sn = std::sin(d.omega(e));
    // Block (j, i) = -w R(omega): psi_j = e^{i omega} psi_i. Across sheets the phase read in X_j
    // is the negative of the one read in X_i, so conj(psi_j) = e^{i omega} psi_i and the block is
    // -w diag(1, -1) R(omega) (notes §5.3: R(-omega) diag(1, -1), the same matrix).
    const double block[4] = {-w * c, w * sn, d.sign(e) > 0 ? -w * sn : w * sn,
                             d.sign(e) > 0 ? -w * c : w * c};
    for (int k = 0; k < 4; ++k) value[s[k]] += w;
    for (int k = 0; k < 4; ++k) {
      value[s[4 + k]] += block[k];
      value[s[8 + k]] += block[k];
    }
  }
}

// The phase data of the converged psi (see StripePattern).
void stripe_phases(const Eigen::MatrixXi& F, const EdgeTopology& topology, const FieldData& d,
                   StripePattern& p) {
  const int nv = static_cast<int>(p.psi.size());
  p.vertex_phase.resize(nv);
  for (int v = 0; v < nv; ++v) {
    double phase = std::arg(p.psi(v));
    if (std::abs(phase) < kPhaseNudge) phase = phase < 0 ? -kPhaseNudge : kPhaseNudge;
    p.vertex_phase(v) = phase;
  }
  const int ne = topology.num_edges();
  p.edge_sign = d.sign;
  p.edge_phase.resize(ne);
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    // The phase jump that the integer part of the winding cannot see is taken from omega; the
    // rest from psi (geometry-central's texture-coordinate rule, notes §5.3).
    const double omega = d.omega(e);
    p.edge_phase(e) = omega + wrap_angle(d.sign(e) * p.vertex_phase(j) - p.vertex_phase(i) - omega);
  }
  const int nf = static_cast<int>(F.rows());
  p.doubled_index = d.doubled_index;
  p.stripe_index.setZero(nf);
  p.corner_phase.setZero(nf, 3);
  p.usable.assign(nf, false);
  for (int f = 0; f < nf; ++f) {
    // Signs of the three directions relative to the first corner's (identity transport).
    int c[3];
    const Eigen::Vector2d Xa = d.X.row(F(f, 0));
    for (int k = 0; k < 3; ++k) c[k] = Xa.dot(d.X.row(F(f, k)).transpose()) >= 0 ? 1 : -1;
    bool consistent = true;
    double increment[3];  // phase change along edge k of the face, in the face's sign
    for (int k = 0; k < 3; ++k) {
      const int e = topology.face_edges(f, k);
      const int u = F(f, k);
      const bool forward = topology.edges(e, 0) == u;
      const int c_first = forward ? c[k] : c[(k + 1) % 3];
      const int c_second = forward ? c[(k + 1) % 3] : c[k];
      if (c_second != c_first * d.sign(e)) consistent = false;
      increment[k] = c_first * (forward ? 1 : -1) * p.edge_phase(e);
    }
    double alpha[3];
    alpha[0] = c[0] * p.vertex_phase(F(f, 0));
    alpha[1] = alpha[0] + increment[0];
    alpha[2] = alpha[1] + increment[1];
    const double closing = alpha[2] + increment[2] - alpha[0];
    p.stripe_index(f) = static_cast<int>(std::lround(closing / kTwoPi));
    for (int k = 0; k < 3; ++k) p.corner_phase(f, k) = alpha[k];
    if (!consistent || p.doubled_index(f) != 0 || std::abs(p.stripe_index(f)) > 1) continue;
    // The face must see on each edge as many isoline crossings as the edge itself holds (the
    // boundary phase lifted: back at corner 0 it has wound 2 pi stripe_index).
    const double lifted_end = alpha[0] + kTwoPi * p.stripe_index(f);
    bool counts_agree = true;
    for (int k = 0; k < 3; ++k) {
      const int e = topology.face_edges(f, k);
      const int i = topology.edges(e, 0);
      const double a = p.vertex_phase(i), b = a + p.edge_phase(e);
      if (count_phase_levels(alpha[k], k < 2 ? alpha[k + 1] : lifted_end) !=
          count_phase_levels(a, b)) {
        counts_agree = false;
      }
    }
    p.usable[f] = counts_agree;
  }
}

// A breadth-first spanning tree of the vertex graph along which 1-forms are integrated into
// phases: vertices in visiting order, each with the edge it was reached by (-1 for the root). The
// root is the vertex nearest the centroid that touches no field-singular face, and the search
// first uses only edges that touch none: there X has no direction, and an edge at a singular
// vertex would give its whole subtree an arbitrary phase (around the centre of concentric circles
// that turns the circles into a spiral).
struct SpanningTree {
  std::vector<int> order;
  std::vector<int> parent_edge;
};

SpanningTree spanning_tree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                           const EdgeTopology& topology, const Eigen::VectorXi& doubled_index) {
  const int nv = static_cast<int>(V.rows());
  std::vector<bool> near_singular(nv, false);
  for (int f = 0; f < F.rows(); ++f) {
    if (doubled_index(f) == 0) continue;
    for (int k = 0; k < 3; ++k) near_singular[F(f, k)] = true;
  }
  std::vector<std::vector<int>> incident(nv);
  for (int e = 0; e < topology.num_edges(); ++e) {
    incident[topology.edges(e, 0)].push_back(e);
    incident[topology.edges(e, 1)].push_back(e);
  }
  const Eigen::RowVector2d centroid = V.leftCols<2>().colwise().mean();
  int root = -1;
  double best = 0;
  for (int v = 0; v < nv; ++v) {
    const double d = (V.row(v).head<2>() - centroid).squaredNorm();
    if (!near_singular[v] && (root < 0 || d < best)) {
      root = v;
      best = d;
    }
  }
  if (root < 0) root = 0;
  SpanningTree tree;
  tree.parent_edge.assign(nv, -1);
  std::vector<bool> seen(nv, false);
  seen[root] = true;
  tree.order.push_back(root);
  for (const bool any_edge : {false, true}) {
    for (size_t head = 0; head < tree.order.size(); ++head) {
      const int v = tree.order[head];
      for (int e : incident[v]) {
        const int w = topology.edges(e, 0) == v ? topology.edges(e, 1) : topology.edges(e, 0);
        if (seen[w] || (!any_edge && (near_singular[v] || near_singular[w]))) continue;
        seen[w] = true;
        tree.parent_edge[w] = e;
        tree.order.push_back(w);
      }
    }
  }
  return tree;
}

// Phases Phi with Phi_j = s_e (form_e + Phi_i) along every tree edge e = (i, j) (psi_j =
// e^{i omega} psi_i, or conj(psi_j) = e^{i omega} psi_i across sheets), Phi = 0 at the root.
Eigen::VectorXd integrate_one_form(const SpanningTree& tree, const EdgeTopology& topology,
                                   const Eigen::VectorXi& sign, const Eigen::VectorXd& form) {
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(static_cast<int>(tree.parent_edge.size()));
  for (int v : tree.order) {
    const int e = tree.parent_edge[v];
    if (e < 0) continue;
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    phi(v) = v == j ? sign(e) * (form(e) + phi(i)) : sign(e) * phi(j) - form(e);
  }
  return phi;
}

}  // namespace

int count_phase_levels(double a, double b) {
  const double lo = std::min(a, b), hi = std::max(a, b);
  const double n = std::floor(hi / kTwoPi) - std::ceil(lo / kTwoPi) + 1;
  return n > 0 ? static_cast<int>(n) : 0;
}

Eigen::VectorXd stripe_direction(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const StripePattern& pattern) {
  Eigen::VectorXd direction = Eigen::VectorXd::Constant(F.rows(), NAN);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!pattern.usable[f] || pattern.stripe_index(f) != 0) continue;
    const Eigen::Vector2d e1 = (V.row(F(f, 1)) - V.row(F(f, 0))).head<2>().transpose();
    const Eigen::Vector2d e2 = (V.row(F(f, 2)) - V.row(F(f, 0))).head<2>().transpose();
    const double d1 = pattern.corner_phase(f, 1) - pattern.corner_phase(f, 0);
    const double d2 = pattern.corner_phase(f, 2) - pattern.corner_phase(f, 0);
    // The phase gradient g solves e1.g = d1, e2.g = d2; the isolines run along its normal
    // (-g_y, g_x), which by Cramer's rule is (d1 e2 - d2 e1) / det(e1, e2).
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    const Eigen::Vector2d along = (d1 * e2 - d2 * e1) / det;
    direction(f) = std::remainder(std::atan2(along.y(), along.x()), std::numbers::pi);
  }
  return direction;
}

namespace {

// What the solves of every field on one plate share.
struct StripeSetup {
  double nu = 0;                  // 2 pi / spacing, 1/mm
  Eigen::MatrixXd half_cot;       // per face corner
  Eigen::VectorXd mass;           // 2 #V: the lumped mass, twice per vertex
  ConnectionLaplacian laplacian;  // the sparsity pattern, values of the last field set
};

StripeSetup stripe_setup(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                         const EdgeTopology& topology, const StripeOptions& options) {
  StripeSetup out;
  const int nv = static_cast<int>(V.rows());
  out.nu = kTwoPi / options.spacing;
  out.half_cot = half_cotangents(V, F);
  const Eigen::VectorXd vertex_mass = lumped_mass(V.leftCols<2>(), F);
  out.mass.resize(2 * nv);
  for (int v = 0; v < nv; ++v) out.mass.segment<2>(2 * v).setConstant(vertex_mass(v));
  out.laplacian = connection_laplacian_pattern(topology, 1e-6 * out.nu * out.nu * out.mass);
  return out;
}

// Warm start: x, a pattern of the field whose phase directions are previous_X, carried to the
// field d: each value in d's sign of X (a vertex whose direction changed sign carries the
// conjugate), advanced by the change of the 1-form integrated along d's spanning tree, so that its
// stripes turn with the field while keeping their offsets and forks.
void advance_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const EdgeTopology& topology, const FieldData& d,
                     const Eigen::MatrixXd& previous_X, double nu, Eigen::VectorXd& x) {
  const int nv = static_cast<int>(V.rows());
  const SpanningTree tree = spanning_tree(V, F, topology, d.doubled_index);
  Eigen::MatrixXd previous_aligned = previous_X;
  for (int v = 0; v < nv; ++v) {
    if (d.X.row(v).dot(previous_X.row(v)) < 0) {
      x(2 * v + 1) = -x(2 * v + 1);
      previous_aligned.row(v) *= -1;
    }
  }
  Eigen::VectorXd change(topology.num_edges());
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    const Eigen::Vector2d edge = (V.row(j) - V.row(i)).head<2>();
    const Eigen::Vector2d turn =
        (d.X.row(i) - previous_aligned.row(i)) + d.sign(e) * (d.X.row(j) - previous_aligned.row(j));
    change(e) = 0.5 * nu * turn.dot(edge);
  }
  const Eigen::VectorXd phi = integrate_one_form(tree, topology, d.sign, change);
  for (int v = 0; v < nv; ++v) {
    const std::complex<double> value =
        std::complex<double>(x(2 * v), x(2 * v + 1)) * std::polar(1.0, phi(v));
    x.segment<2>(2 * v) << value.real(), value.imag();
  }
}

// The pattern of field d by inverse power iteration from x (which it leaves at the result), with
// `laplacian` set to d's values and `solver` factorizing it (analysed first when `analysed` is
// false: minimum degree alone, which on these planar meshes orders several times faster than
// trying nested dissection as well, for a similar fill).
StripePattern solve_pattern(const Eigen::MatrixXi& F, const EdgeTopology& topology,
                            const FieldData& d, const StripeOptions& options, double nu,
                            const Eigen::VectorXd& mass, ConnectionLaplacian& laplacian,
                            SparseCholesky& solver, bool& analysed, Eigen::VectorXd& x) {
  set_connection_laplacian(d, laplacian);
  const Eigen::SparseMatrix<double>& A = laplacian.A;
  if (!analysed) {
    solver.cholmod().nmethods = 1;
    solver.cholmod().method[0].ordering = CHOLMOD_AMD;
    analyze_pattern(solver, A);
    analysed = true;
  }
  factorize(solver, A);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("stripe_patterns: factorization of the connection Laplacian failed");
  }
  StripePattern p;
  x /= std::sqrt(x.dot(mass.cwiseProduct(x)));
  for (p.iterations = 1; p.iterations <= options.max_iterations; ++p.iterations) {
    const Eigen::VectorXd y = solver.solve(mass.cwiseProduct(x));
    x = y / std::sqrt(y.dot(mass.cwiseProduct(y)));
    const Eigen::VectorXd Ex = A * x - laplacian.shift.cwiseProduct(x);
    p.eigenvalue = x.dot(Ex);
    const Eigen::VectorXd r = Ex - p.eigenvalue * mass.cwiseProduct(x);
    p.residual = std::sqrt(r.dot(r.cwiseQuotient(mass))) / (nu * nu);
    if (p.residual < options.tolerance) break;
  }
  p.iterations = std::min(p.iterations, options.max_iterations);
  const int nv = static_cast<int>(x.size() / 2);
  p.psi.resize(nv);
  for (int v = 0; v < nv; ++v) p.psi(v) = {x(2 * v), x(2 * v + 1)};
  stripe_phases(F, topology, d, p);
  return p;
}

}  // namespace

std::vector<StripePattern> stripe_patterns(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                           const EdgeTopology& topology,
                                           const std::vector<Eigen::VectorXd>& theta_vertex,
                                           const StripeOptions& options) {
  const int nv = static_cast<int>(V.rows());
  StripeSetup setup = stripe_setup(V, F, topology, options);
  std::vector<StripePattern> patterns;
  SparseCholesky solver;
  bool analysed = false;
  Eigen::VectorXd x;
  Eigen::MatrixXd previous_X;
  for (size_t layer = 0; layer < theta_vertex.size(); ++layer) {
    if (layer > 0 && theta_vertex[layer] == theta_vertex[layer - 1]) {
      // The same field (theta2 = 0) has the same stripes: printed lines stack exactly.
      patterns.push_back(patterns.back());
      continue;
    }
    const FieldData d = field_data(V, F, topology, setup.half_cot, theta_vertex[layer], setup.nu);
    if (layer == 0) {
      // Start from the target 1-form integrated along the tree: stripes already aligned with the
      // field everywhere, mismatched only across the tree's cuts, which the iteration heals.
      const SpanningTree tree = spanning_tree(V, F, topology, d.doubled_index);
      const Eigen::VectorXd phi = integrate_one_form(tree, topology, d.sign, d.omega);
      x.resize(2 * nv);
      for (int v = 0; v < nv; ++v) x.segment<2>(2 * v) << std::cos(phi(v)), std::sin(phi(v));
    } else {
      advance_pattern(V, F, topology, d, previous_X, setup.nu, x);
    }
    patterns.push_back(solve_pattern(F, topology, d, options, setup.nu, setup.mass, setup.laplacian,
                                     solver, analysed, x));
    previous_X = d.X;
  }
  return patterns;
}

std::vector<StripePattern> restripe_patterns(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             const EdgeTopology& topology,
                                             const std::vector<Eigen::VectorXd>& theta_vertex,
                                             const std::vector<Eigen::VectorXd>& previous_theta,
                                             const std::vector<StripePattern>& previous,
                                             const StripeOptions& options) {
  const size_t n = theta_vertex.size();
  if (previous_theta.size() != n || previous.size() != n) {
    throw std::invalid_argument("restripe_patterns: one previous field and pattern per field");
  }
  const int nv = static_cast<int>(V.rows());
  const StripeSetup setup = stripe_setup(V, F, topology, options);
  // A layer whose field and previous field equal the layer below's has its pattern.
  std::vector<size_t> solved;
  for (size_t layer = 0; layer < n; ++layer) {
    if (layer == 0 || theta_vertex[layer] != theta_vertex[layer - 1] ||
        previous_theta[layer] != previous_theta[layer - 1]) {
      solved.push_back(layer);
    }
  }
  struct Worker {
    ConnectionLaplacian laplacian;
    SparseCholesky solver;
    bool analysed = false;
  };
  tbb::enumerable_thread_specific<std::unique_ptr<Worker>> workers;
  std::vector<StripePattern> patterns(n);
  tbb::parallel_for(size_t{0}, solved.size(), [&](size_t i) {
    std::unique_ptr<Worker>& worker = workers.local();
    if (!worker) {
      worker = std::make_unique<Worker>();
      worker->laplacian = setup.laplacian;
    }
    const size_t layer = solved[i];
    const FieldData d = field_data(V, F, topology, setup.half_cot, theta_vertex[layer], setup.nu);
    Eigen::VectorXd x(2 * nv);
    for (int v = 0; v < nv; ++v) {
      x.segment<2>(2 * v) << previous[layer].psi(v).real(), previous[layer].psi(v).imag();
    }
    advance_pattern(V, F, topology, d, phase_directions(previous_theta[layer]), setup.nu, x);
    patterns[layer] = solve_pattern(F, topology, d, options, setup.nu, setup.mass,
                                    worker->laplacian, worker->solver, worker->analysed, x);
  });
  for (size_t layer = 1; layer < n; ++layer) {
    if (!std::binary_search(solved.begin(), solved.end(), layer)) {
      patterns[layer] = patterns[layer - 1];
    }
  }
  return patterns;
}

}  // namespace flatmorph
