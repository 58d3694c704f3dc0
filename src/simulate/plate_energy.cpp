#include "simulate/plate_energy.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

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

Eigen::Vector3d voigt(const Eigen::Matrix2d& e) { return {e(0, 0), e(1, 1), e(0, 1) + e(1, 0)}; }

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

// The energy of face f; fills the element gradient/Hessian (slots: face vertices 0-2, then the
// vertices across edges 0-2) when asked.
void evaluate_face(const PlateEnergy& energy, int f, const Eigen::VectorXd& x, double& membrane,
                   double& bending, Vec18* gradient, Mat18* hessian, bool project) {
  const PlateEnergy::FaceConstants& c = energy.faces[f];
  const auto& ev = energy.element_vertices.row(f);
  const Eigen::Vector3d x0 = position(x, ev(0)), x1 = position(x, ev(1)), x2 = position(x, ev(2));
  const Eigen::Vector3d u = x1 - x0, v = x2 - x0;
  const Eigen::Matrix3d& elasticity = energy.elasticity;

  // Membrane: ε_M = P g − c, g = (u·u, v·v, u·v).
  const Eigen::Vector3d g(u.dot(u), v.dot(v), u.dot(v));
  const Eigen::Vector3d strain_m = c.membrane_map * g - c.membrane_offset;
  const Eigen::Vector3d stress_m = elasticity * strain_m;
  membrane = c.membrane_weight * strain_m.dot(stress_m);

  // Bending: ε_M = P φ − c, φ_k for the hinge across edge k (0 on the boundary).
  const Eigen::Vector3d xs[3] = {x0, x1, x2};
  Eigen::Vector3d phi = Eigen::Vector3d::Zero();
  HingeDerivatives hinge[3];
  const bool derivatives = gradient != nullptr;
  for (int k = 0; k < 3; ++k) {
    const int l = ev(3 + k);
    if (l < 0) continue;
    const Eigen::Vector3d& xi = xs[k];
    const Eigen::Vector3d& xj = xs[(k + 1) % 3];
    const Eigen::Vector3d& xk = xs[(k + 2) % 3];
    if (derivatives) {
      hinge[k] = hinge_derivatives(xi, xj, xk, position(x, l));
      phi(k) = hinge[k].phi;
    } else {
      phi(k) = hinge_measure(xi, xj, xk, position(x, l));
    }
  }
  const Eigen::Vector3d strain_b = c.bending_map * phi - c.bending_offset;
  const Eigen::Vector3d stress_b = elasticity * strain_b;
  bending = c.bending_weight * strain_b.dot(stress_b);
  if (!derivatives) return;

  // Membrane derivatives through g: dW/dg = s, ∇²W = Jᵀ Q J + Σ s_i ∇²g_i.
  const Eigen::Vector3d s = 2 * c.membrane_weight * c.membrane_map.transpose() * stress_m;
  const Eigen::Matrix3d q_m =
      2 * c.membrane_weight * c.membrane_map.transpose() * elasticity * c.membrane_map;
  Eigen::Matrix<double, 3, 6> jg;
  jg << 2 * u.transpose(), Eigen::RowVector3d::Zero(), Eigen::RowVector3d::Zero(),
      2 * v.transpose(), v.transpose(), u.transpose();
  const Eigen::Matrix<double, 3, 6> q_jg = q_m * jg;
  Eigen::Matrix<double, 6, 6> huv = jg.transpose().lazyProduct(q_jg);
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  huv.block<3, 3>(0, 0) += 2 * s(0) * id;
  huv.block<3, 3>(3, 3) += 2 * s(1) * id;
  huv.block<3, 3>(0, 3) += s(2) * id;
  huv.block<3, 3>(3, 0) += s(2) * id;
  const Eigen::Matrix<double, 6, 1> guv = jg.transpose() * s;

  Vec18& grad = *gradient;
  Mat18& hess = *hessian;
  grad.setZero();
  hess.setZero();
  // (u, v) = (x1 − x0, x2 − x0).
  grad.segment<3>(3) = guv.head<3>();
  grad.segment<3>(6) = guv.tail<3>();
  grad.segment<3>(0) = -guv.head<3>() - guv.tail<3>();
  const Eigen::Matrix3d huu = huv.block<3, 3>(0, 0), huv_ = huv.block<3, 3>(0, 3),
                        hvu = huv.block<3, 3>(3, 0), hvv = huv.block<3, 3>(3, 3);
  hess.block<3, 3>(3, 3) = huu;
  hess.block<3, 3>(3, 6) = huv_;
  hess.block<3, 3>(6, 3) = hvu;
  hess.block<3, 3>(6, 6) = hvv;
  hess.block<3, 3>(0, 3) = -(huu + hvu);
  hess.block<3, 3>(3, 0) = -(huu + huv_);
  hess.block<3, 3>(0, 6) = -(huv_ + hvv);
  hess.block<3, 3>(6, 0) = -(hvu + hvv);
  hess.block<3, 3>(0, 0) = huu + huv_ + hvu + hvv;

  // Bending derivatives through φ: dW/dφ = r, ∇²W = Σ Q_kk' ∇φ_k ∇φ_k'ᵀ + Σ r_k ∇²φ_k.
  const Eigen::Vector3d r = 2 * c.bending_weight * c.bending_map.transpose() * stress_b;
  const Eigen::Matrix3d q_b =
      2 * c.bending_weight * c.bending_map.transpose() * elasticity * c.bending_map;
  Eigen::Matrix<double, 3, kElementSize> jphi = Eigen::Matrix<double, 3, kElementSize>::Zero();
  for (int k = 0; k < 3; ++k) {
    if (ev(3 + k) < 0) continue;
    const int slot[4] = {k, (k + 1) % 3, (k + 2) % 3, 3 + k};
    for (int p = 0; p < 4; ++p) {
      jphi.block<1, 3>(k, 3 * slot[p]) = hinge[k].gradient.segment<3>(3 * p).transpose();
      for (int q = 0; q < 4; ++q) {
        hess.block<3, 3>(3 * slot[p], 3 * slot[q]) +=
            r(k) * hinge[k].hessian.block<3, 3>(3 * p, 3 * q);
      }
    }
  }
  grad += jphi.transpose() * r;
  const Eigen::Matrix<double, 3, kElementSize> q_jphi = q_b * jphi;
  hess += jphi.transpose().lazyProduct(q_jphi);
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

Eigen::Matrix2d inverse_checked(const Eigen::Matrix2d& m, int f, const char* what) {
  const double det = m.determinant();
  if (!(det > 0) || !std::isfinite(det)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("face {}: {} is not positive definite (determinant {}): check the "
                                "rest forms given for this face",
                                f, what, det));
  }
  return m.inverse();
}

}  // namespace

Stiffness stiffness_of(const Material& material) {
  return {material.young_modulus_along, material.young_modulus_across, material.poisson_ratio};
}

Eigen::Matrix3d orthotropic_elasticity_tensor(const Stiffness& s) {
  const double e1 = s.young_modulus_along, e2 = s.young_modulus_across, nu = s.poisson_ratio;
  const double g = std::sqrt(e1 * e2);
  Eigen::Matrix3d c;
  c << e1, nu * g, 0, nu * g, e2, 0, 0, 0, 0.5 * (1 - nu) * g;
  return c / (1 - nu * nu);  // Eq. 4
}

PlateEnergy make_plate_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const RestForms& rest_forms, const Stiffness& stiffness) {
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
      rest_forms.material_angle.size() != num_faces) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("the rest forms have {} faces but the plate has {}: compute them "
                                "for this plate",
                                rest_forms.num_faces(), num_faces));
  }
  if (!(stiffness.young_modulus_along > 0) || !(stiffness.young_modulus_across > 0) ||
      !(stiffness.poisson_ratio >= 0 && stiffness.poisson_ratio < 1)) {
    throw UserError(ErrorCategory::kOption,
                    "stiffness out of range: the Young's moduli must be positive and the Poisson "
                    "ratio in [0, 1)");
  }
  PlateEnergy out;
  out.num_vertices = static_cast<int>(plate.rows());
  out.F = F;
  out.elasticity = orthotropic_elasticity_tensor(stiffness);

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
    const Eigen::Matrix2d& a_bar = rest_forms.rest_first_fundamental_form[f];
    const Eigen::Matrix2d& b_bar = rest_forms.rest_second_fundamental_form[f];
    const Eigen::Matrix2d a_bar_inv = inverse_checked(a_bar, f, "the rest first fundamental form");
    const Eigen::Matrix2d rot = rotation(rest_forms.material_angle(f));
    // Eq. 3: the strain in the material frame, scaled by the rest metric.
    auto material_strain = [&](const Eigen::Matrix2d& eps) {
      return voigt(rot.transpose() * a_bar_inv * eps * rot);
    };

    PlateEnergy::FaceConstants& c = out.faces[f];
    c.inverse_rest_edges = rest_edges.inverse();
    const Eigen::Matrix2d& d = c.inverse_rest_edges;
    // a = Dᵀ G D with G = [[u·u, u·v], [u·v, v·v]] and D the inverse rest edges.
    const Eigen::Matrix2d unit[3] = {(Eigen::Matrix2d() << 1, 0, 0, 0).finished(),
                                     (Eigen::Matrix2d() << 0, 0, 0, 1).finished(),
                                     (Eigen::Matrix2d() << 0, 1, 1, 0).finished()};
    for (int j = 0; j < 3; ++j) {
      c.membrane_map.col(j) = material_strain(d.transpose() * unit[j] * d);
    }
    c.membrane_offset = material_strain(a_bar);
    // b = Σ_k φ_k K_k, K_k = m̂ m̂ᵀ ℓ̂²/(2Â)² for the rest edge k (corner k to k+1).
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d edge = p[(k + 1) % 3] - p[k];
      const Eigen::Vector2d normal(edge.y(), -edge.x());  // length ℓ̂: m̂ ℓ̂
      const Eigen::Matrix2d kk = normal * normal.transpose() / (double_area * double_area);
      c.bending_map.col(k) = material_strain(kk);
    }
    for (int j = 0; j < 3; ++j) c.rest_strain_map.col(j) = material_strain(unit[j]);
    c.bending_offset = material_strain(b_bar);
    const double volume_factor = 0.5 * double_area * std::sqrt(a_bar.determinant());
    c.membrane_weight = volume_factor * t / 4;  // Eq. 2, 8
    c.bending_weight = volume_factor * t * t * t / 12;
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

void set_rest_second_fundamental_forms(PlateEnergy& energy,
                                       const std::vector<Eigen::Matrix2d>& rest_second_forms) {
  if (rest_second_forms.size() != energy.faces.size()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} rest second fundamental forms for {} faces: give one per face",
                                rest_second_forms.size(), energy.faces.size()));
  }
  for (size_t f = 0; f < energy.faces.size(); ++f) {
    const Eigen::Matrix2d& b = rest_second_forms[f];
    energy.faces[f].bending_offset = energy.faces[f].rest_strain_map *
                                     Eigen::Vector3d(b(0, 0), b(1, 1), 0.5 * (b(0, 1) + b(1, 0)));
  }
}

Eigen::SparseMatrix<double> rest_curvature_mixed_derivative(
    const PlateEnergy& energy, const Eigen::VectorXd& x,
    const std::vector<Eigen::Matrix2d>& directions) {
  const int num_faces = static_cast<int>(energy.F.rows());
  if (static_cast<int>(directions.size()) != num_faces) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} rest curvature directions for {} faces: give one per face",
                                directions.size(), num_faces));
  }
  std::vector<Vec18> columns(num_faces);
  tbb::parallel_for(tbb::blocked_range<int>(0, num_faces, 64), [&](const tbb::blocked_range<int>&
                                                                       range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      const PlateEnergy::FaceConstants& c = energy.faces[f];
      const auto& ev = energy.element_vertices.row(f);
      const Eigen::Vector3d xs[3] = {position(x, ev(0)), position(x, ev(1)), position(x, ev(2))};
      Eigen::Matrix<double, 3, kElementSize> jphi = Eigen::Matrix<double, 3, kElementSize>::Zero();
      for (int k = 0; k < 3; ++k) {
        const int l = ev(3 + k);
        if (l < 0) continue;
        const HingeDerivatives h =
            hinge_derivatives(xs[k], xs[(k + 1) % 3], xs[(k + 2) % 3], position(x, l));
        const int slot[4] = {k, (k + 1) % 3, (k + 2) % 3, 3 + k};
        for (int p = 0; p < 4; ++p) {
          jphi.block<1, 3>(k, 3 * slot[p]) = h.gradient.segment<3>(3 * p).transpose();
        }
      }
      const Eigen::Matrix2d& g = directions[f];
      const Eigen::Vector3d strain_g =
          c.rest_strain_map * Eigen::Vector3d(g(0, 0), g(1, 1), 0.5 * (g(0, 1) + g(1, 0)));
      // ∂W/∂x = 2 w_b jphiᵀ Pᵀ C (P φ − c(s)), ∂c/∂s = strain_g.
      columns[f] = -2 * c.bending_weight * jphi.transpose() *
                   (c.bending_map.transpose() * (energy.elasticity * strain_g));
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
                          const Eigen::VectorXd& thickness, const Stiffness& stiffness) {
  double sum = 0;
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix2d edges;
    edges << (plate.row(F(f, 1)) - plate.row(F(f, 0))).transpose(),
        (plate.row(F(f, 2)) - plate.row(F(f, 0))).transpose();
    sum += 0.5 * std::abs(edges.determinant()) * thickness(f);
  }
  return stiffness.young_modulus_along * sum;
}

}  // namespace flatmorph
