// Internals of the Shrink & Morph flattening shared by flatten.cpp, local_global.cpp and
// smoothing.cpp. Not part of the library's interface.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <vector>

namespace flatmorph::shrink_morph_internal {

// Each target triangle laid isometrically in its own plane (first corner at the origin, second on
// +x, third above): X_f = [x_b - x_a, x_c - x_a] in that frame. The differential of the target ->
// plate map on face f is J_f = [p_b - p_a, p_c - p_a] X_f^{-1}, in the target's units.
struct RestFrames {
  Eigen::VectorXd area;                  // #F target areas
  std::vector<Eigen::Matrix2d> inverse;  // X_f^{-1}
};

// Throws UserError(kGeometry) naming the first zero-area face.
RestFrames rest_frames(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

inline Eigen::Matrix2d plate_differential(const Eigen::MatrixXd& P, const Eigen::MatrixXi& F,
                                          const RestFrames& frames, int f) {
  Eigen::Matrix2d B;
  for (int r = 0; r < 2; ++r) {
    B(r, 0) = P(F(f, 1), r) - P(F(f, 0), r);
    B(r, 1) = P(F(f, 2), r) - P(F(f, 0), r);
  }
  return B * frames.inverse[f];
}

// A 2x2 matrix J as conformal plus anticonformal part: J = p R(conformal angle) + q S(anticonformal
// angle), R a rotation and S(t) = [[cos t, sin t], [sin t, -cos t]] a reflection, p, q >= 0. Then
// J = R(beta) diag(p + q, p - q) R(gamma)^T with beta = (anticonformal + conformal)/2: the signed
// singular values in closed form (p - q < 0 exactly when det J < 0), and beta the plate direction
// J stretches most. The unit complex numbers e^{i conformal}, e^{i anticonformal} are kept as
// (cos, sin) pairs so that no angle needs unwrapping.
struct ConformalSplit {
  double p = 0, q = 0;
  double conformal_cos = 1, conformal_sin = 0;
  double anticonformal_cos = 1, anticonformal_sin = 0;
  double sigma1() const { return p + q; }
  double sigma2() const { return p - q; }
};

inline ConformalSplit conformal_split(const Eigen::Matrix2d& J) {
  ConformalSplit s;
  const double c_re = J(0, 0) + J(1, 1), c_im = J(1, 0) - J(0, 1);
  const double a_re = J(0, 0) - J(1, 1), a_im = J(1, 0) + J(0, 1);
  // Plate differentials are O(1): no overflow for std::hypot to guard against, at several times
  // the cost of a square root in this innermost loop.
  const double c_norm = std::sqrt(c_re * c_re + c_im * c_im);
  const double a_norm = std::sqrt(a_re * a_re + a_im * a_im);
  s.p = 0.5 * c_norm;
  s.q = 0.5 * a_norm;
  // A purely (anti)conformal J leaves the other angle free; 0 is as good as any.
  if (c_norm > 0) s.conformal_cos = c_re / c_norm, s.conformal_sin = c_im / c_norm;
  if (a_norm > 0) s.anticonformal_cos = a_re / a_norm, s.anticonformal_sin = a_im / a_norm;
  return s;
}

// The orientation-preserving matrix with singular values (s1, s2), s1 >= s2 > 0, closest to J in
// the Frobenius norm (the local step of Eq. 11): same singular frames as J, with a reflected J's
// smaller singular direction flipped rather than copied, so the target never asks for a flip.
inline Eigen::Matrix2d closest_with_singular_values(const ConformalSplit& s, double s1, double s2) {
  const double p = 0.5 * (s1 + s2), q = 0.5 * (s1 - s2);
  Eigen::Matrix2d T;
  T << p * s.conformal_cos + q * s.anticonformal_cos,
      -p * s.conformal_sin + q * s.anticonformal_sin, p * s.conformal_sin + q * s.anticonformal_sin,
      p * s.conformal_cos - q * s.anticonformal_cos;
  return T;
}

// Tutte's embedding: the boundary loop on a circle of `radius` (counter-clockwise, at angles
// proportional to 3D arc length, first vertex at angle 0), every interior vertex at the average of
// its neighbours. Flip-free when `loop` has the surface on its left (Floater 2003).
Eigen::MatrixXd tutte_embedding(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                const std::vector<int>& loop, double radius);

struct LocalGlobalStats {
  int iterations = 0;  // global solves
  bool converged = false;
  double energy = 0;  // sum_f A_f ||J_f - T_f||^2 / sum_f A_f at the returned P (dimensionless)
};

// Liu et al. 2008 local/global minimization of sum_f A_f ||J_f - T_f||_F^2, T_f with singular
// values (s1, s2) (Eq. 11; s1 = s2 = 1 is ARAP). The global matrix depends only on the target, so
// it is factored once (CHOLMOD) and reused by every call.
class LocalGlobal {
 public:
  LocalGlobal(const Eigen::MatrixXi& F, const RestFrames& frames, int num_vertices);
  LocalGlobal(const LocalGlobal&) = delete;
  LocalGlobal& operator=(const LocalGlobal&) = delete;

  // Iterates from P (#V x 2) until the area-weighted RMS change of the singular values between two
  // local steps is below `tolerance` times their area-weighted RMS distance to (s1, s2), or
  // `max_iterations` global solves.
  LocalGlobalStats solve(Eigen::MatrixXd& P, double s1, double s2, double tolerance,
                         int max_iterations) const;

 private:
  const Eigen::MatrixXi& F_;
  const RestFrames& frames_;
  std::vector<Eigen::Matrix<double, 3, 2>> gradient_;  // A_f E X_f^{-1}, E = [[-1,-1],[1,0],[0,1]]
  Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>> solver_;
};

// Edge weights of the direction Dirichlet energy on the target: for each interior edge, its two
// faces and w_e = 3 l_e^2 / (2 (A_f + A_g)).
struct DualEdges {
  std::vector<int> face_f, face_g;
  std::vector<double> weight;
};
DualEdges dual_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const RestFrames& frames);

// The documented constant of the Eq. 12 normalization (docs/flatten.md): the smoothing term is
// w_D * kSmoothingScale * (Dirichlet energy of e^{2 i alpha}), the fit term the area-averaged
// squared singular-value error.
inline constexpr double kSmoothingScale = 3e-5;

// The Eq. 12 energy (fit + smoothing_weight * direction Dirichlet energy) of the plate
// x = (x_0, y_0, x_1, y_1, ...), with its gradient and the lower triangle of its Hessian, exact or
// with each element's Hessian replaced by a PSD approximation (`project`). For the tests.
double smoothing_energy(const Eigen::MatrixXi& F, const RestFrames& frames, const DualEdges& edges,
                        double s1, double s2, double smoothing_weight, const Eigen::VectorXd& x,
                        Eigen::VectorXd* gradient, Eigen::SparseMatrix<double>* hessian,
                        bool project);

struct SmoothingStats {
  int iterations = 0;
  bool converged = false;
};

// Eq. 12 by projected Newton over the plate positions P (#V x 2, flip-free on entry and exit).
SmoothingStats smooth_directions(Eigen::MatrixXd& P, const Eigen::MatrixXi& F,
                                 const RestFrames& frames, const DualEdges& edges, double s1,
                                 double s2, double w_D, double tolerance, int max_iterations);

}  // namespace flatmorph::shrink_morph_internal
