#include "simulate/plate_energy.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/error.h"
#include "mesh/topology.h"
#include "numerics/autodiff.h"
#include "numerics/psd_projection.h"

namespace flatmorph {
namespace {

constexpr int kElementSize = 18;  // 6 vertices x 3 coordinates
constexpr int kElementEntries = kElementSize * kElementSize;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec18 = Eigen::Matrix<double, kElementSize, 1>;
using Mat18 = Eigen::Matrix<double, kElementSize, kElementSize>;

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return m;
}

// φ = θ 2A/ℓ as a function of the invariants of the hinge's edge e = x_j − x_i and the vectors
// a = x_k − x_i (to the face's third vertex) and b = x_l − x_i (to the vertex across e):
// ee = e·e, ea = e·a, eb = e·b, aa = a·a, ab = a·b, det = e·(a × b). With the face normal n_f = e ×
// a and the neighbour's n_g = b × e: n_f·n_g = eb·ea − ee·ab and n_f × n_g = −det e, so the
// dihedral angle is atan2(det |e|, n_f·n_g), positive when x_l lies on the +n_f side (the hinge
// bends toward n_f), and 2A/ℓ = |n_f|/|e| = sqrt((ee·aa − ea²)/ee).
template <typename T>
T hinge_measure_from_invariants(const T& ee, const T& ea, const T& eb, const T& aa, const T& ab,
                                const T& det) {
  using std::atan2;
  using std::sqrt;
  const T theta = atan2(det * sqrt(ee), eb * ea - ee * ab);
  return theta * sqrt((ee * aa - ea * ea) / ee);
}

struct HingeDerivatives {
  double phi;
  Vec12 gradient;  // over (x_i, x_j, x_k, x_l)
  Mat12 hessian;
};

// Chain rule through the six invariants: ∇φ = Jᵀ Φ', ∇²φ = Jᵀ Φ'' J + Σ_s Φ'_s ∇²s, where the
// invariants are quadratic (dot products) or trilinear (det) in (e, a, b), so their Hessians are
// constant or linear and written out below.
HingeDerivatives hinge_derivatives(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                   const Eigen::Vector3d& xk, const Eigen::Vector3d& xl) {
  const Eigen::Vector3d e = xj - xi, a = xk - xi, b = xl - xi;
  const Eigen::Vector3d axb = a.cross(b), bxe = b.cross(e), exa = e.cross(a);
  using D = Dual<6>;
  const D phi = hinge_measure_from_invariants(D::variable(e.dot(e), 0), D::variable(e.dot(a), 1),
                                              D::variable(e.dot(b), 2), D::variable(a.dot(a), 3),
                                              D::variable(a.dot(b), 4), D::variable(e.dot(axb), 5));
  Eigen::Matrix<double, 6, 9> jac = Eigen::Matrix<double, 6, 9>::Zero();
  jac.block<1, 3>(0, 0) = 2 * e.transpose();
  jac.block<1, 3>(1, 0) = a.transpose();
  jac.block<1, 3>(1, 3) = e.transpose();
  jac.block<1, 3>(2, 0) = b.transpose();
  jac.block<1, 3>(2, 6) = e.transpose();
  jac.block<1, 3>(3, 3) = 2 * a.transpose();
  jac.block<1, 3>(4, 3) = b.transpose();
  jac.block<1, 3>(4, 6) = a.transpose();
  jac.block<1, 3>(5, 0) = axb.transpose();
  jac.block<1, 3>(5, 3) = bxe.transpose();
  jac.block<1, 3>(5, 6) = exa.transpose();

  const Vec9 g9 = jac.transpose() * phi.gradient;
  const Eigen::Matrix<double, 6, 9> phi_jac = phi.hessian.lazyProduct(jac);
  Mat9 h9 = jac.transpose().lazyProduct(phi_jac);
  const Eigen::Matrix<double, 6, 1>& d = phi.gradient;
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  // Blocks (e, e), (e, a), (e, b), (a, a), (a, b) of Σ_s Φ'_s ∇²s; (b, b) is zero.
  const Eigen::Matrix3d ee = 2 * d(0) * id;
  const Eigen::Matrix3d ea = d(1) * id - d(5) * cross_matrix(b);
  const Eigen::Matrix3d eb = d(2) * id + d(5) * cross_matrix(a);
  const Eigen::Matrix3d aa = 2 * d(3) * id;
  const Eigen::Matrix3d ab = d(4) * id - d(5) * cross_matrix(e);
  h9.block<3, 3>(0, 0) += ee;
  h9.block<3, 3>(0, 3) += ea;
  h9.block<3, 3>(3, 0) += ea.transpose();
  h9.block<3, 3>(0, 6) += eb;
  h9.block<3, 3>(6, 0) += eb.transpose();
  h9.block<3, 3>(3, 3) += aa;
  h9.block<3, 3>(3, 6) += ab;
  h9.block<3, 3>(6, 3) += ab.transpose();

  // (e, a, b) = (x_j − x_i, x_k − x_i, x_l − x_i): x_j, x_k, x_l take the (e, a, b) blocks as they
  // are, x_i minus their sums.
  HingeDerivatives out;
  out.phi = phi.value;
  out.gradient.segment<9>(3) = g9;
  out.gradient.segment<3>(0) = -(g9.segment<3>(0) + g9.segment<3>(3) + g9.segment<3>(6));
  out.hessian.block<9, 9>(3, 3) = h9;
  Eigen::Matrix<double, 3, 9> row_sum =
      h9.block<3, 9>(0, 0) + h9.block<3, 9>(3, 0) + h9.block<3, 9>(6, 0);
  out.hessian.block<3, 9>(0, 3) = -row_sum;
  out.hessian.block<9, 3>(3, 0) = -row_sum.transpose();
  out.hessian.block<3, 3>(0, 0) =
      row_sum.block<3, 3>(0, 0) + row_sum.block<3, 3>(0, 3) + row_sum.block<3, 3>(0, 6);
  return out;
}

double hinge_measure(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                     const Eigen::Vector3d& xk, const Eigen::Vector3d& xl) {
  const Eigen::Vector3d e = xj - xi, a = xk - xi, b = xl - xi;
  return hinge_measure_from_invariants(e.dot(e), e.dot(a), e.dot(b), a.dot(a), a.dot(b),
                                       e.dot(a.cross(b)));
}

// Per-face results of one evaluation, written by the face's task into preallocated slots.
struct Workspace {
  std::vector<double> energy_membrane, energy_bending;
  std::vector<Vec18> gradient;
  std::vector<Mat18> hessian;
};

Eigen::Vector3d position(const Eigen::VectorXd& x, int v) { return x.segment<3>(3 * v); }

// The six scalars r = (|u|², |v|², u·v, φ_0, φ_1, φ_2) of face f, and with `hinge` their hinge
// derivatives (slot k for the hinge across edge k; left alone on the boundary, where φ_k = 0).
Vector6d face_scalars(const PlateEnergy& energy, int f, const Eigen::VectorXd& x,
                      HingeDerivatives* hinge) {
  const auto& ev = energy.element_vertices.row(f);
  const Eigen::Vector3d xs[3] = {position(x, ev(0)), position(x, ev(1)), position(x, ev(2))};
  const Eigen::Vector3d u = xs[1] - xs[0], v = xs[2] - xs[0];
  Vector6d r;
  r << u.dot(u), v.dot(v), u.dot(v), 0, 0, 0;
  for (int k = 0; k < 3; ++k) {
    const int l = ev(3 + k);
    if (l < 0) continue;
    const Eigen::Vector3d& xi = xs[k];
    const Eigen::Vector3d& xj = xs[(k + 1) % 3];
    const Eigen::Vector3d& xk = xs[(k + 2) % 3];
    if (hinge) {
      hinge[k] = hinge_derivatives(xi, xj, xk, position(x, l));
      r(3 + k) = hinge[k].phi;
    } else {
      r(3 + k) = hinge_measure(xi, xj, xk, position(x, l));
    }
  }
  return r;
}

// ∂r/∂x over the element's 18 coordinates (slots: face vertices 0-2, then the vertices across
// edges 0-2).
Eigen::Matrix<double, 6, kElementSize> scalar_jacobian(const PlateEnergy& energy, int f,
                                                       const Eigen::VectorXd& x,
                                                       const HingeDerivatives* hinge) {
  const auto& ev = energy.element_vertices.row(f);
  const Eigen::Vector3d x0 = position(x, ev(0));
  const Eigen::Vector3d u = position(x, ev(1)) - x0, v = position(x, ev(2)) - x0;
  Eigen::Matrix<double, 6, kElementSize> j = Eigen::Matrix<double, 6, kElementSize>::Zero();
  // (u, v) = (x1 − x0, x2 − x0).
  j.block<1, 3>(0, 3) = 2 * u.transpose();
  j.block<1, 3>(0, 0) = -2 * u.transpose();
  j.block<1, 3>(1, 6) = 2 * v.transpose();
  j.block<1, 3>(1, 0) = -2 * v.transpose();
  j.block<1, 3>(2, 3) = v.transpose();
  j.block<1, 3>(2, 6) = u.transpose();
  j.block<1, 3>(2, 0) = -(u + v).transpose();
  for (int k = 0; k < 3; ++k) {
    if (ev(3 + k) < 0) continue;
    const int slot[4] = {k, (k + 1) % 3, (k + 2) % 3, 3 + k};
    for (int p = 0; p < 4; ++p) {
      j.block<1, 3>(3 + k, 3 * slot[p]) = hinge[k].gradient.segment<3>(3 * p).transpose();
    }
  }
  return j;
}

// The energy of face f (its membrane and bending parts, the coupling split evenly); fills the
// element gradient/Hessian when asked.
void evaluate_face(const PlateEnergy& energy, int f, const Eigen::VectorXd& x, double& membrane,
                   double& bending, Vec18* gradient, Mat18* hessian, bool project) {
  const PlateEnergy::FaceConstants& c = energy.faces[f];
  const bool derivatives = gradient != nullptr;
  HingeDerivatives hinge[3];
  const Vector6d r = face_scalars(energy, f, x, derivatives ? hinge : nullptr);
  const Vector6d strain = c.strain_map * r - c.rest;
  const Vector6d stress = c.weighted_stiffness * strain;
  membrane = 0.5 * strain.head<3>().dot(stress.head<3>());
  bending = 0.5 * strain.tail<3>().dot(stress.tail<3>());
  if (!derivatives) return;

  // dW/dr = Tᵀ K' (T r − s̄); ∇²W = Jᵀ (Tᵀ K' T) J + Σ_i (dW/dr)_i ∇²r_i.
  const Vector6d rho = c.strain_map.transpose() * stress;
  const Eigen::Matrix<double, 6, kElementSize> j = scalar_jacobian(energy, f, x, hinge);
  Vec18& grad = *gradient;
  Mat18& hess = *hessian;
  grad = j.transpose() * rho;
  const Eigen::Matrix<double, 6, kElementSize> kj = c.stiffness_in_r * j;
  hess = j.transpose().lazyProduct(kj);
  // ∇²|u|² = 2 I on u, ∇²|v|² = 2 I on v, ∇²(u·v) = I across; (u, v) = (x1 − x0, x2 − x0).
  const double uu = 2 * rho(0), vv = 2 * rho(1), uv = rho(2);
  const double block[3][3] = {
      {uu + vv + 2 * uv, -(uu + uv), -(vv + uv)}, {-(uu + uv), uu, uv}, {-(vv + uv), uv, vv}};
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) hess.block<3, 3>(3 * p, 3 * q).diagonal().array() += block[p][q];
  }
  const auto& ev = energy.element_vertices.row(f);
  for (int k = 0; k < 3; ++k) {
    if (ev(3 + k) < 0) continue;
    const int slot[4] = {k, (k + 1) % 3, (k + 2) % 3, 3 + k};
    for (int p = 0; p < 4; ++p) {
      for (int q = 0; q < 4; ++q) {
        hess.block<3, 3>(3 * slot[p], 3 * slot[q]) +=
            rho(3 + k) * hinge[k].hessian.block<3, 3>(3 * p, 3 * q);
      }
    }
  }
  if (project) project_to_psd<kElementSize>(hess);
}

void run_faces(const PlateEnergy& energy, const Eigen::VectorXd& x, Workspace& w, bool derivatives,
               bool project) {
  const int num_faces = static_cast<int>(energy.F.rows());
  w.energy_membrane.resize(num_faces);
  w.energy_bending.resize(num_faces);
  if (derivatives) {
    w.gradient.resize(num_faces);
    w.hessian.resize(num_faces);
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, num_faces, 64),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int f = range.begin(); f != range.end(); ++f) {
                        evaluate_face(energy, f, x, w.energy_membrane[f], w.energy_bending[f],
                                      derivatives ? &w.gradient[f] : nullptr,
                                      derivatives ? &w.hessian[f] : nullptr, project);
                      }
                    });
}

void set_face_rest_forms(PlateEnergy::FaceConstants& c, const Eigen::Matrix2d& a_bar,
                         const Eigen::Matrix2d& b_bar, const Matrix6d& stiffness, int f) {
  if (!stiffness.allFinite() || stiffness.llt().info() != Eigen::Success ||
      !(a_bar.determinant() > 0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("face {}: the laminate's stiffness or rest metric is not positive "
                                "definite: check the rest forms given for this face",
                                f));
  }
  c.rest = rest_vector(a_bar, b_bar);
  c.weighted_stiffness = 0.5 * c.rest_area * stiffness;
  c.stiffness_in_r = c.strain_map.transpose() * c.weighted_stiffness * c.strain_map;
}

}  // namespace

PlateEnergy make_plate_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const RestForms& rest_forms) {
  if (plate.cols() != 2) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the plate has {} coordinates per vertex: give the flat plate as "
                                "2D (x, y) positions in mm",
                                plate.cols()));
  }
  const int num_faces = static_cast<int>(F.rows());
  if (rest_forms.num_faces() != num_faces ||
      static_cast<int>(rest_forms.rest_first_fundamental_form.size()) != num_faces ||
      static_cast<int>(rest_forms.rest_second_fundamental_form.size()) != num_faces ||
      static_cast<int>(rest_forms.stiffness.size()) != num_faces) {
    throw std::invalid_argument(
        fmt::format("the rest forms have {} faces but the plate has {}: compute them "
                    "for this plate",
                    rest_forms.num_faces(), num_faces));
  }
  PlateEnergy out;
  out.num_vertices = static_cast<int>(plate.rows());
  out.F = F;

  const EdgeTopology topology = edge_topology(F);
  out.element_vertices.resize(num_faces, 6);
  for (int f = 0; f < num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      out.element_vertices(f, k) = F(f, k);
      const int g = topology.face_faces(f, k);
      out.element_vertices(f, 3 + k) = g < 0 ? -1 : F(g, (topology.face_faces_edge(f, k) + 2) % 3);
    }
  }

  out.faces.resize(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::Vector2d p[3] = {plate.row(F(f, 0)).transpose(), plate.row(F(f, 1)).transpose(),
                                  plate.row(F(f, 2)).transpose()};
    Eigen::Matrix2d rest_edges;
    rest_edges << p[1] - p[0], p[2] - p[0];
    const double double_area = rest_edges.determinant();
    if (!(double_area > 0)) {
      throw UserError(
          ErrorCategory::kGeometry,
          fmt::format("plate face {} is {} (signed area {} mm²): the flat plate must "
                      "have counter-clockwise, non-degenerate triangles",
                      f, double_area < 0 ? "clockwise" : "degenerate", 0.5 * double_area));
    }
    const double t = rest_forms.thickness(f);
    if (!(t > 0)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("face {} has thickness {} mm: thicknesses must be positive", f, t));
    }
    PlateEnergy::FaceConstants& c = out.faces[f];
    c.inverse_rest_edges = rest_edges.inverse();
    c.rest_area = 0.5 * double_area;
    const Eigen::Matrix2d& d = c.inverse_rest_edges;
    // a = Dᵀ G D with G = [[u·u, u·v], [u·v, v·v]] and D the inverse rest edges.
    const Eigen::Matrix2d unit[3] = {(Eigen::Matrix2d() << 1, 0, 0, 0).finished(),
                                     (Eigen::Matrix2d() << 0, 0, 0, 1).finished(),
                                     (Eigen::Matrix2d() << 0, 1, 1, 0).finished()};
    c.strain_map.setZero();
    for (int j = 0; j < 3; ++j) {
      const Eigen::Matrix2d a = d.transpose() * unit[j] * d;
      c.strain_map.block<3, 1>(0, j) = Eigen::Vector3d(a(0, 0), a(1, 1), a(0, 1));
    }
    // b = Σ_k φ_k K_k, K_k = m̂ m̂ᵀ ℓ̂²/(2Â)² for the rest edge k (corner k to k+1).
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d edge = p[(k + 1) % 3] - p[k];
      const Eigen::Vector2d normal(edge.y(), -edge.x());  // length ℓ̂: m̂ ℓ̂
      const Eigen::Matrix2d kk = normal * normal.transpose() / (double_area * double_area);
      c.strain_map.block<3, 1>(3, 3 + k) = Eigen::Vector3d(kk(0, 0), kk(1, 1), kk(0, 1));
    }
    set_face_rest_forms(c, rest_forms.rest_first_fundamental_form[f],
                        rest_forms.rest_second_fundamental_form[f], rest_forms.stiffness[f], f);
  }

  // Hessian pattern: the lower triangle of every element's 18 x 18 block.
  const int n = 3 * out.num_vertices;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(num_faces) * 171);
  auto global = [&](int f, int local) {
    const int v = out.element_vertices(f, local / 3);
    return v < 0 ? -1 : 3 * v + local % 3;
  };
  for (int f = 0; f < num_faces; ++f) {
    for (int p = 0; p < kElementSize; ++p) {
      const int row = global(f, p);
      if (row < 0) continue;
      for (int q = 0; q < kElementSize; ++q) {
        const int col = global(f, q);
        if (col >= 0 && row >= col) triplets.emplace_back(row, col, 0.0);
      }
    }
  }
  out.hessian_pattern.resize(n, n);
  out.hessian_pattern.setFromTriplets(triplets.begin(), triplets.end());
  out.hessian_pattern.makeCompressed();
  triplets.clear();
  triplets.shrink_to_fit();

  // Gather lists, by counting sort on the nonzero index so that each list is in face order.
  const Eigen::SparseMatrix<double>& pat = out.hessian_pattern;
  auto nonzero_index = [&](int row, int col) {
    const int* begin = pat.innerIndexPtr() + pat.outerIndexPtr()[col];
    const int* end = pat.innerIndexPtr() + pat.outerIndexPtr()[col + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - pat.innerIndexPtr());
  };
  std::vector<std::pair<int, int>> contributions;  // (nonzero, source)
  contributions.reserve(static_cast<size_t>(num_faces) * 171);
  for (int f = 0; f < num_faces; ++f) {
    for (int p = 0; p < kElementSize; ++p) {
      const int row = global(f, p);
      if (row < 0) continue;
      for (int q = 0; q < kElementSize; ++q) {
        const int col = global(f, q);
        if (col >= 0 && row >= col) {
          contributions.emplace_back(nonzero_index(row, col),
                                     f * kElementEntries + q * kElementSize + p);
        }
      }
    }
  }
  out.gather_offsets.assign(pat.nonZeros() + 1, 0);
  for (const auto& [nz, src] : contributions) ++out.gather_offsets[nz + 1];
  for (size_t i = 1; i < out.gather_offsets.size(); ++i) {
    out.gather_offsets[i] += out.gather_offsets[i - 1];
  }
  out.gather_sources.resize(contributions.size());
  std::vector<int> fill(out.gather_offsets.begin(), out.gather_offsets.end() - 1);
  for (const auto& [nz, src] : contributions) out.gather_sources[fill[nz]++] = src;
  return out;
}

double evaluate_plate_energy(const PlateEnergy& energy, const Eigen::VectorXd& x,
                             Eigen::VectorXd* gradient, Eigen::SparseMatrix<double>* hessian,
                             bool project) {
  const bool derivatives = gradient != nullptr || hessian != nullptr;
  Workspace w;
  run_faces(energy, x, w, derivatives, project);
  const int num_faces = static_cast<int>(energy.F.rows());
  double total = 0;
  for (int f = 0; f < num_faces; ++f) total += w.energy_membrane[f] + w.energy_bending[f];
  if (!std::isfinite(total)) return std::numeric_limits<double>::infinity();

  if (gradient) {
    gradient->setZero(3 * energy.num_vertices);
    for (int f = 0; f < num_faces; ++f) {
      for (int s = 0; s < 6; ++s) {
        const int v = energy.element_vertices(f, s);
        if (v >= 0) gradient->segment<3>(3 * v) += w.gradient[f].segment<3>(3 * s);
      }
    }
  }
  if (hessian) {
    if (hessian->rows() != energy.hessian_pattern.rows() ||
        hessian->nonZeros() != energy.hessian_pattern.nonZeros() || !hessian->isCompressed()) {
      *hessian = energy.hessian_pattern;
    }
    double* values = hessian->valuePtr();
    const int nnz = static_cast<int>(energy.hessian_pattern.nonZeros());
    const double* local = w.hessian.empty() ? nullptr : w.hessian[0].data();
    tbb::parallel_for(
        tbb::blocked_range<int>(0, nnz, 4096), [&](const tbb::blocked_range<int>& range) {
          for (int i = range.begin(); i != range.end(); ++i) {
            double sum = 0;
            for (int k = energy.gather_offsets[i]; k < energy.gather_offsets[i + 1]; ++k) {
              sum += local[energy.gather_sources[k]];
            }
            values[i] = sum;
          }
        });
  }
  return total;
}

Eigen::Vector2d plate_energy_terms(const PlateEnergy& energy, const Eigen::VectorXd& x) {
  Workspace w;
  run_faces(energy, x, w, false, false);
  Eigen::Vector2d terms = Eigen::Vector2d::Zero();
  for (size_t f = 0; f < w.energy_membrane.size(); ++f) {
    terms(0) += w.energy_membrane[f];
    terms(1) += w.energy_bending[f];
  }
  return terms;
}

std::vector<Vector6d> plate_forms(const PlateEnergy& energy, const Eigen::VectorXd& x) {
  std::vector<Vector6d> forms(energy.faces.size());
  for (size_t f = 0; f < forms.size(); ++f) {
    forms[f] = energy.faces[f].strain_map * face_scalars(energy, static_cast<int>(f), x, nullptr);
  }
  return forms;
}

double smallest_metric_ratio(const PlateEnergy& energy, const Eigen::VectorXd& x) {
  double smallest = std::numeric_limits<double>::infinity();
  for (int f = 0; f < static_cast<int>(energy.faces.size()); ++f) {
    const PlateEnergy::FaceConstants& c = energy.faces[f];
    const auto& ev = energy.element_vertices.row(f);
    const Eigen::Vector3d u = position(x, ev(1)) - position(x, ev(0));
    const Eigen::Vector3d v = position(x, ev(2)) - position(x, ev(0));
    // The membrane block of T maps the current edges' Gram entries to a, stored (a00, a11, a01).
    const Eigen::Vector3d a =
        c.strain_map.topLeftCorner<3, 3>() * Eigen::Vector3d(u.dot(u), v.dot(v), u.dot(v));
    Eigen::Matrix2d metric, rest;
    metric << a(0), a(2), a(2), a(1);
    rest << c.rest(0), c.rest(2), c.rest(2), c.rest(1);
    // μ are the eigenvalues of L⁻¹ a L⁻ᵀ, ā = L Lᵀ; the smaller one of a symmetric 2 x 2 matrix in
    // the form that does not cancel when the two are equal.
    const Eigen::Matrix2d inverse = rest.llt().matrixL().solve(Eigen::Matrix2d::Identity());
    const Eigen::Matrix2d m = inverse * metric * inverse.transpose();
    smallest = std::min(smallest,
                        0.5 * (m(0, 0) + m(1, 1)) - std::hypot(0.5 * (m(0, 0) - m(1, 1)), m(0, 1)));
  }
  return smallest;
}

void set_rest_forms(PlateEnergy& energy, const RestForms& rest_forms) {
  if (rest_forms.num_faces() != static_cast<int>(energy.faces.size()) ||
      rest_forms.stiffness.size() != energy.faces.size() ||
      rest_forms.rest_first_fundamental_form.size() != energy.faces.size() ||
      rest_forms.rest_second_fundamental_form.size() != energy.faces.size()) {
    throw std::invalid_argument(
        fmt::format("rest forms of {} faces for a plate of {}: give one per face",
                    rest_forms.num_faces(), energy.faces.size()));
  }
  for (size_t f = 0; f < energy.faces.size(); ++f) {
    set_face_rest_forms(energy.faces[f], rest_forms.rest_first_fundamental_form[f],
                        rest_forms.rest_second_fundamental_form[f], rest_forms.stiffness[f],
                        static_cast<int>(f));
  }
}

Eigen::SparseMatrix<double> rest_forms_mixed_derivative(const PlateEnergy& energy,
                                                        const Eigen::VectorXd& x,
                                                        const LaminateDerivative& derivative) {
  const int num_faces = static_cast<int>(energy.F.rows());
  if (static_cast<int>(derivative.stiffness.size()) != num_faces ||
      static_cast<int>(derivative.rest.size()) != num_faces) {
    throw std::invalid_argument(
        fmt::format("rest form derivatives of {} faces for a plate of {}: give one "
                    "per face",
                    derivative.rest.size(), num_faces));
  }
  std::vector<Vec18> columns(num_faces);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, num_faces, 64), [&](const tbb::blocked_range<int>& range) {
        for (int f = range.begin(); f != range.end(); ++f) {
          const PlateEnergy::FaceConstants& c = energy.faces[f];
          HingeDerivatives hinge[3];
          const Vector6d r = face_scalars(energy, f, x, hinge);
          const Vector6d strain = c.strain_map * r - c.rest;
          const Vector6d d_stress = 0.5 * c.rest_area * (derivative.stiffness[f] * strain) -
                                    c.weighted_stiffness * derivative.rest[f];
          columns[f] = scalar_jacobian(energy, f, x, hinge).transpose() *
                       (c.strain_map.transpose() * d_stress);
        }
      });
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(num_faces) * kElementSize);
  for (int f = 0; f < num_faces; ++f) {
    for (int s = 0; s < 6; ++s) {
      const int v = energy.element_vertices(f, s);
      if (v < 0) continue;
      for (int d = 0; d < 3; ++d) triplets.emplace_back(3 * v + d, f, columns[f](3 * s + d));
    }
  }
  Eigen::SparseMatrix<double> out(3 * energy.num_vertices, num_faces);
  out.setFromTriplets(triplets.begin(), triplets.end());
  return out;
}

double hinge_bending_measure(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                             const Eigen::Vector3d& xk, const Eigen::Vector3d& xl) {
  return hinge_measure(xi, xj, xk, xl);
}

double unit_strain_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                          const RestForms& rest_forms) {
  double sum = 0;
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix2d edges;
    edges << (plate.row(F(f, 1)) - plate.row(F(f, 0))).transpose(),
        (plate.row(F(f, 2)) - plate.row(F(f, 0))).transpose();
    sum += 0.5 * std::abs(edges.determinant()) * rest_forms.energy_scale(f);
  }
  return sum;
}

}  // namespace flatmorph
