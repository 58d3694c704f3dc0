// Eq. 12 of Shrink & Morph: the plate whose singular values best fit (1/lambda1, 1/lambda2) with a
// smooth field of maximal-stretch directions, by projected Newton with exact derivatives.
//
// Per face, J = [p_b - p_a, p_c - p_a] X^{-1} is linear in the face's six plate coordinates, and so
// are z2 = (J00 + J11, J10 - J01) and z1 = (J00 - J11, J10 + J01), whose moduli are twice the
// conformal and anticonformal parts p, q of J (flatten_internal.h). With sigma1,2 = p +- q and
// pbar, qbar the same split of the targets (s1, s2), the fit term of face f is
//   (A_f / A) [(sigma1 - s1)^2 + (sigma2 - s2)^2] = (A_f / A) 2 [(p - pbar)^2 + (q - qbar)^2],
// whose Hessian in (z2, z1) is known in closed form with known eigenvalues. The direction of
// maximal stretch is alpha = (arg z1 + arg z2)/2; with psi = 2 alpha and u = e^{i psi}, the
// smoothness term of interior edge e between faces f and g is
//   w_D kSmoothingScale w_e |u_f - u_g|^2 = w_D kSmoothingScale w_e (2 - 2 cos(psi_f - psi_g)),
// a function of one angle difference whose derivatives follow from those of arg z (a traceless
// 2x2 Hessian with eigenvalues +-1/|z|^2). Everything is in closed form, and every term's Hessian
// has known eigenvalues, so filtering its negative ones (projected Newton) needs no
// eigen-decomposition.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "methods/shrink_morph/flatten_internal.h"
#include "numerics/newton.h"

namespace flatmorph::shrink_morph_internal {
namespace {

// Rows z2_re, z2_im, z1_re, z1_im as linear functions of the face's plate coordinates
// (x_a, y_a, x_b, y_b, x_c, y_c).
Eigen::Matrix<double, 4, 6> split_map(const Eigen::Matrix2d& rest_inverse) {
  Eigen::Matrix<double, 3, 2> E;
  E << -1, -1, 1, 0, 0, 1;
  const Eigen::Matrix<double, 3, 2> D = E * rest_inverse;  // J(r, k) = sum_v D(v, k) x_{v, r}
  Eigen::Matrix<double, 4, 6> M;
  for (int v = 0; v < 3; ++v) {
    M.block<4, 2>(0, 2 * v) << D(v, 0), D(v, 1), -D(v, 1), D(v, 0), D(v, 0), -D(v, 1), D(v, 1),
        D(v, 0);
  }
  return M;
}

// How element Hessians are handed to Newton: exact; the reference implementation's blend
// 0.9 H + 0.1 H_psd (notes §3.6), which keeps 90 % of any negative curvature so that Newton can
// leave saddles quickly; or projected onto the PSD cone (always a descent direction).
enum class Curvature { kExact, kBlend, kProjected };

// The curvature a term with eigenvalue `lambda` contributes under `mode`.
double filtered(double lambda, Curvature mode) {
  if (lambda >= 0 || mode == Curvature::kExact) return lambda;
  return mode == Curvature::kBlend ? 0.9 * lambda : 0.0;
}

// (|z|/2 - c)^2 with its gradient and Hessian in z.
double modulus_penalty(const Eigen::Vector2d& z, double c, Eigen::Vector2d& gradient,
                       Eigen::Matrix2d& hessian, Curvature mode) {
  const double r = z.norm();
  const double residual = 0.5 * r - c;
  if (r < 1e-300) {  // the cone point: any subgradient will do, curvature 1/2 radially
    gradient.setZero();
    hessian = 0.5 * Eigen::Matrix2d::Identity();
    return c * c;
  }
  const Eigen::Vector2d n = z / r;
  gradient = residual * n;
  // Radial curvature 1/2; tangential residual / r, negative when |z|/2 < c.
  const double tangential = filtered(residual / r, mode);
  hessian =
      0.5 * n * n.transpose() + tangential * (Eigen::Matrix2d::Identity() - n * n.transpose());
  return residual * residual;
}

// arg z with its gradient and Hessian in z (the Hessian is traceless: eigenvalues +-1/|z|^2).
// Zero derivatives where the angle is undefined (z = 0: J conformal, no preferred direction).
double angle(const Eigen::Vector2d& z, Eigen::Vector2d& gradient, Eigen::Matrix2d& hessian) {
  const double r2 = z.squaredNorm();
  if (!(r2 > 1e-300)) {
    gradient.setZero();
    hessian.setZero();
    return 0.0;
  }
  const double x = z(0), y = z(1), r4 = r2 * r2;
  gradient << -y / r2, x / r2;
  hessian << 2 * x * y / r4, (y * y - x * x) / r4, (y * y - x * x) / r4, -2 * x * y / r4;
  return std::atan2(y, x);
}

// A traceless symmetric 2x2 matrix [[a, b], [b, -a]] (eigenvalues +-m, m = |(a, b)|) with its
// negative eigenvalue filtered: A = m (P+ - P-) with P+- = (I +- A/m)/2.
Eigen::Matrix2d filtered_traceless(const Eigen::Matrix2d& A, Curvature mode) {
  const double m = std::hypot(A(0, 0), A(0, 1));
  if (!(m > 0)) return Eigen::Matrix2d::Zero();
  const double negative = filtered(-m, mode);
  return 0.5 * (m + negative) * Eigen::Matrix2d::Identity() + 0.5 * (1 - negative / m) * A;
}

// What each face contributes, in its split coordinates z = (z2, z1).
struct FaceTerms {
  double fit = 0;
  Eigen::Vector4d fit_gradient;
  Eigen::Matrix4d fit_hessian;
  double psi = 0;  // 2 alpha = arg z1 + arg z2
  Eigen::Vector4d psi_gradient;
  Eigen::Matrix2d conformal_hessian, anticonformal_hessian;  // of arg z2, arg z1
};

class SmoothingProblem {
 public:
  SmoothingProblem(const Eigen::MatrixXi& F, const RestFrames& frames, const DualEdges& edges,
                   int num_vertices, double s1, double s2, double smoothing_weight);

  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                  Eigen::SparseMatrix<double>* hessian, Curvature mode) const;

 private:
  std::array<int, 6> face_dofs(int f) const {
    return {2 * F_(f, 0),     2 * F_(f, 0) + 1, 2 * F_(f, 1),
            2 * F_(f, 1) + 1, 2 * F_(f, 2),     2 * F_(f, 2) + 1};
  }
  std::array<int, 8> edge_dofs(int e) const {
    std::array<int, 8> dofs;
    for (int k = 0; k < 4; ++k) {
      dofs[2 * k] = 2 * edge_vertices_[e][k];
      dofs[2 * k + 1] = dofs[2 * k] + 1;
    }
    return dofs;
  }

  const Eigen::MatrixXi& F_;
  const DualEdges& edges_;
  std::vector<Eigen::Matrix<double, 4, 6>> maps_;  // per face, DOFs -> z
  Eigen::VectorXd fit_weight_;                     // 2 A_f / A
  double pbar_ = 0, qbar_ = 0;                     // targets for |z2|/2 and |z1|/2
  double smoothing_weight_ = 0;                    // w_D kSmoothingScale
  // Per interior edge: the four vertices (face f's three in f's order, then g's third) and the
  // map from their eight coordinates to (z_f, z_g).
  std::vector<std::array<int, 4>> edge_vertices_;
  std::vector<Eigen::Matrix<double, 8, 8>> edge_maps_;
  Eigen::SparseMatrix<double> pattern_;            // lower triangle of the Hessian
  std::vector<std::array<int, 36>> face_entries_;  // value index per local (a, b); -1 above
  std::vector<std::array<int, 64>> edge_entries_;
};

// Slot of (row, col), row >= col, in a compressed column-major lower-triangular matrix.
int slot(const Eigen::SparseMatrix<double>& m, int row, int col) {
  const int* begin = m.innerIndexPtr() + m.outerIndexPtr()[col];
  const int* end = m.innerIndexPtr() + m.outerIndexPtr()[col + 1];
  return static_cast<int>(std::lower_bound(begin, end, row) - m.innerIndexPtr());
}

template <size_t N>
void entries_for(const Eigen::SparseMatrix<double>& m, const std::array<int, N>& dofs,
                 std::array<int, N * N>& entries) {
  for (size_t a = 0; a < N; ++a) {
    for (size_t b = 0; b < N; ++b) {
      entries[a * N + b] = dofs[a] >= dofs[b] ? slot(m, dofs[a], dofs[b]) : -1;
    }
  }
}

SmoothingProblem::SmoothingProblem(const Eigen::MatrixXi& F, const RestFrames& frames,
                                   const DualEdges& edges, int num_vertices, double s1, double s2,
                                   double smoothing_weight)
    : F_(F), edges_(edges) {
  const int nf = static_cast<int>(F.rows());
  const int ne = smoothing_weight > 0 ? static_cast<int>(edges.weight.size()) : 0;
  maps_.resize(nf);
  for (int f = 0; f < nf; ++f) maps_[f] = split_map(frames.inverse[f]);
  fit_weight_ = 2.0 * frames.area / frames.area.sum();
  pbar_ = 0.5 * (s1 + s2);
  qbar_ = 0.5 * (s1 - s2);
  smoothing_weight_ = smoothing_weight;

  edge_vertices_.resize(ne);
  edge_maps_.resize(ne);
  for (int e = 0; e < ne; ++e) {
    const int f = edges.face_f[e], g = edges.face_g[e];
    std::array<int, 4>& v = edge_vertices_[e];
    for (int k = 0; k < 3; ++k) v[k] = F(f, k);
    v[3] = -1;
    Eigen::Matrix<double, 8, 8>& M = edge_maps_[e];
    M.setZero();
    for (int k = 0; k < 3; ++k) M.block<4, 2>(0, 2 * k) = maps_[f].middleCols<2>(2 * k);
    for (int k = 0; k < 3; ++k) {
      const int* found = std::find(v.begin(), v.begin() + 3, F(g, k));
      int local = static_cast<int>(found - v.begin());
      if (found == v.begin() + 3) v[3] = F(g, k), local = 3;
      M.block<4, 2>(4, 2 * local) = maps_[g].middleCols<2>(2 * k);
    }
  }

  std::vector<Eigen::Triplet<double>> triplets;
  auto add_pattern = [&](const auto& dofs) {
    for (int a : dofs) {
      for (int b : dofs) {
        if (a >= b) triplets.emplace_back(a, b, 0.0);
      }
    }
  };
  for (int f = 0; f < nf; ++f) add_pattern(face_dofs(f));
  for (int e = 0; e < ne; ++e) add_pattern(edge_dofs(e));
  pattern_.resize(2 * num_vertices, 2 * num_vertices);
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
  face_entries_.resize(nf);
  for (int f = 0; f < nf; ++f) entries_for(pattern_, face_dofs(f), face_entries_[f]);
  edge_entries_.resize(ne);
  for (int e = 0; e < ne; ++e) entries_for(pattern_, edge_dofs(e), edge_entries_[e]);
}

double SmoothingProblem::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                                  Eigen::SparseMatrix<double>* hessian, Curvature mode) const {
  const int nf = static_cast<int>(F_.rows());
  const int ne = static_cast<int>(edge_vertices_.size());
  const bool derivatives = gradient != nullptr || hessian != nullptr;

  std::vector<FaceTerms> faces(nf);
  tbb::parallel_for(tbb::blocked_range<int>(0, nf), [&](const tbb::blocked_range<int>& range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      Eigen::Matrix<double, 6, 1> xf;
      const std::array<int, 6> dofs = face_dofs(f);
      for (int k = 0; k < 6; ++k) xf(k) = x(dofs[k]);
      const Eigen::Vector4d z = maps_[f] * xf;
      FaceTerms& t = faces[f];
      Eigen::Vector2d g2, g1;
      Eigen::Matrix2d h2, h1;
      t.fit = fit_weight_(f) * (modulus_penalty(z.head<2>(), pbar_, g2, h2, mode) +
                                modulus_penalty(z.tail<2>(), qbar_, g1, h1, mode));
      t.fit_gradient << fit_weight_(f) * g2, fit_weight_(f) * g1;
      t.fit_hessian.setZero();
      t.fit_hessian.topLeftCorner<2, 2>() = fit_weight_(f) * h2;
      t.fit_hessian.bottomRightCorner<2, 2>() = fit_weight_(f) * h1;
      if (ne > 0) {
        t.psi = angle(z.head<2>(), g2, t.conformal_hessian) +
                angle(z.tail<2>(), g1, t.anticonformal_hessian);
        t.psi_gradient << g2, g1;
      }
    }
  });

  // Per interior edge, in (z_f, z_g): W (2 - 2 cos(psi_f - psi_g)) = W |u_f - u_g|^2.
  std::vector<Eigen::Matrix<double, 8, 1>> edge_gradient(derivatives ? ne : 0);
  std::vector<Eigen::Matrix<double, 8, 8>> edge_hessian(hessian ? ne : 0);
  Eigen::VectorXd edge_energy(ne);
  tbb::parallel_for(tbb::blocked_range<int>(0, ne), [&](const tbb::blocked_range<int>& range) {
    for (int e = range.begin(); e != range.end(); ++e) {
      const FaceTerms& a = faces[edges_.face_f[e]];
      const FaceTerms& b = faces[edges_.face_g[e]];
      const double w = smoothing_weight_ * edges_.weight[e];
      const double delta = a.psi - b.psi;
      edge_energy(e) = w * (2 - 2 * std::cos(delta));
      if (!derivatives) continue;
      const double d1 = 2 * w * std::sin(delta), d2 = 2 * w * std::cos(delta);
      Eigen::Matrix<double, 8, 1> grad_delta;
      grad_delta << a.psi_gradient, -b.psi_gradient;
      const Eigen::Matrix<double, 8, 8>& M = edge_maps_[e];
      edge_gradient[e] = M.transpose() * (d1 * grad_delta);
      if (!hessian) continue;
      // d2 grad grad^T + d1 Hess(delta), filtered term by term: the rank-one term and each
      // traceless angle block have known eigenvalues.
      Eigen::Matrix<double, 8, 8> hz = filtered(d2, mode) * grad_delta * grad_delta.transpose();
      const std::array<Eigen::Matrix2d, 4> blocks = {
          d1 * a.conformal_hessian, d1 * a.anticonformal_hessian, -d1 * b.conformal_hessian,
          -d1 * b.anticonformal_hessian};
      for (int k = 0; k < 4; ++k) {
        hz.block<2, 2>(2 * k, 2 * k) += filtered_traceless(blocks[k], mode);
      }
      edge_hessian[e] = M.transpose() * hz * M;
    }
  });

  // Sums and scatters in a fixed order, so that the result does not depend on the threads.
  if (gradient) {
    gradient->setZero(x.size());
    for (int f = 0; f < nf; ++f) {
      const std::array<int, 6> dofs = face_dofs(f);
      const Eigen::Matrix<double, 6, 1> g = maps_[f].transpose() * faces[f].fit_gradient;
      for (int k = 0; k < 6; ++k) (*gradient)(dofs[k]) += g(k);
    }
    for (int e = 0; e < ne; ++e) {
      const std::array<int, 8> dofs = edge_dofs(e);
      for (int k = 0; k < 8; ++k) (*gradient)(dofs[k]) += edge_gradient[e](k);
    }
  }
  if (hessian) {
    if (hessian->nonZeros() != pattern_.nonZeros()) *hessian = pattern_;
    double* values = hessian->valuePtr();
    std::fill(values, values + hessian->nonZeros(), 0.0);
    for (int f = 0; f < nf; ++f) {
      const Eigen::Matrix<double, 6, 6> h = maps_[f].transpose() * faces[f].fit_hessian * maps_[f];
      for (int k = 0; k < 36; ++k) {
        if (face_entries_[f][k] >= 0) values[face_entries_[f][k]] += h(k / 6, k % 6);
      }
    }
    for (int e = 0; e < ne; ++e) {
      for (int k = 0; k < 64; ++k) {
        if (edge_entries_[e][k] >= 0) values[edge_entries_[e][k]] += edge_hessian[e](k / 8, k % 8);
      }
    }
  }
  double energy = 0;
  for (int f = 0; f < nf; ++f) energy += faces[f].fit;
  return energy + edge_energy.sum();
}

}  // namespace

double smoothing_energy(const Eigen::MatrixXi& F, const RestFrames& frames, const DualEdges& edges,
                        double s1, double s2, double smoothing_weight, const Eigen::VectorXd& x,
                        Eigen::VectorXd* gradient, Eigen::SparseMatrix<double>* hessian,
                        bool project) {
  const SmoothingProblem problem(F, frames, edges, static_cast<int>(x.size() / 2), s1, s2,
                                 smoothing_weight);
  return problem.evaluate(x, gradient, hessian,
                          project ? Curvature::kProjected : Curvature::kExact);
}

SmoothingStats smooth_directions(Eigen::MatrixXd& P, const Eigen::MatrixXi& F,
                                 const RestFrames& frames, const DualEdges& edges, double s1,
                                 double s2, double w_D, double tolerance, int max_iterations) {
  const int nv = static_cast<int>(P.rows());
  const SmoothingProblem problem(F, frames, edges, nv, s1, s2, w_D * kSmoothingScale);

  // Newton tries the exact Hessian first and, when it is not positive definite, the fallback this
  // problem provides: first the blend (fast near saddles), and if even a shifted blend cannot be
  // factorized, the per-element PSD projection (always factorizable) for the rest of the solve.
  Curvature fallback = Curvature::kBlend;
  NewtonProblem newton;
  newton.num_variables = 2 * nv;
  newton.evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                        Eigen::SparseMatrix<double>* hessian, bool project) {
    return problem.evaluate(x, gradient, hessian, project ? fallback : Curvature::kExact);
  };
  // The energy does not see rigid motions of the plate: pin vertex 0, and block the rotation about
  // it with the coordinate of the farthest vertex that a rotation would move most.
  Eigen::Index far = 0;
  (P.rowwise() - P.row(0)).rowwise().squaredNorm().maxCoeff(&far);
  const Eigen::RowVector2d arm = P.row(far) - P.row(0);
  newton.fixed_variables = {0, 1,
                            static_cast<int>(2 * far + (std::abs(arm(0)) >= std::abs(arm(1))))};
  // Line-search points that flip a triangle are rejected: the plate must stay printable.
  newton.is_feasible = [&](const Eigen::VectorXd& x) {
    for (int f = 0; f < F.rows(); ++f) {
      const Eigen::Vector2d a(x(2 * F(f, 0)), x(2 * F(f, 0) + 1));
      const Eigen::Vector2d ab = Eigen::Vector2d(x(2 * F(f, 1)), x(2 * F(f, 1) + 1)) - a;
      const Eigen::Vector2d ac = Eigen::Vector2d(x(2 * F(f, 2)), x(2 * F(f, 2) + 1)) - a;
      if (!(ab(0) * ac(1) - ab(1) * ac(0) > 0)) return false;
    }
    return true;
  };
  NewtonOptions options;
  options.max_iterations = max_iterations;
  options.tolerance = tolerance;

  Eigen::VectorXd x(2 * nv);
  for (int v = 0; v < nv; ++v) x(2 * v) = P(v, 0), x(2 * v + 1) = P(v, 1);
  NewtonResult result = newton_minimize(newton, x, options);
  SmoothingStats stats{result.iterations, result.converged()};
  if (result.status == NewtonStatus::kFactorizationFailed && result.iterations < max_iterations) {
    fallback = Curvature::kProjected;
    options.max_iterations = max_iterations - result.iterations;
    result = newton_minimize(newton, result.x, options);
    stats.iterations += result.iterations;
    stats.converged = result.converged();
  }
  for (int v = 0; v < nv; ++v) P(v, 0) = result.x(2 * v), P(v, 1) = result.x(2 * v + 1);
  return stats;
}

}  // namespace flatmorph::shrink_morph_internal
