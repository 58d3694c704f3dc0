#include "methods/shrink_morph/optimize_theta2.h"

#include <fmt/core.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "methods/shrink_morph/gauss_newton_step.h"
#include "numerics/newton.h"
#include "numerics/sparse_cholesky.h"
#include "plate/laminate.h"
#include "simulate/plate_energy.h"
#include "simulate/rigid_frame.h"

namespace flatmorph {
namespace {

// Symbolic analysis, numeric factorization and solve of a, each timed into `out`.
template <typename Solver>
bool factorize_and_solve(Solver& solver, const Eigen::SparseMatrix<double>& a,
                         const Eigen::VectorXd& b, Eigen::VectorXd& z, GaussNewtonStep& out) {
  auto t0 = Clock::now();
  solver.analyzePattern(a);
  out.analysis_seconds = seconds_since(t0);
  t0 = Clock::now();
  solver.factorize(a);
  out.factorization_seconds = seconds_since(t0);
  if (solver.info() != Eigen::Success) return false;
  t0 = Clock::now();
  z = solver.solve(b);
  out.solve_seconds = seconds_since(t0);
  return solver.info() == Eigen::Success && z.allFinite();
}

// Everything that stays fixed while theta2 changes, in the frame of the target's central face
// (first vertex at the origin, first edge along +x, face in the xy plane), where the 3-2-1
// constraint fixes coordinates that are exactly zero.
class Theta2Solver {
 public:
  Theta2Solver(const Theta2Problem& problem, const OptimizeTheta2Options& options)
      : options_(options) {
    const int nv = static_cast<int>(problem.plate.rows());
    const int nf = static_cast<int>(problem.F.rows());
    if (problem.target.rows() != nv || problem.target.cols() != 3 || problem.theta1.size() != nf) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("theta2 optimization: the target has {} x {} coordinates and "
                      "theta1 {} values for a plate of {} vertices and {} faces: give "
                      "one 3D position per vertex and one theta1 per face",
                      problem.target.rows(), problem.target.cols(), problem.theta1.size(), nv, nf));
    }
    if (!(options.w_M >= 0) || !(options.w_L >= 0)) {
      throw UserError(ErrorCategory::kOption,
                      "theta2 optimization: w_M and w_L must be non-negative");
    }
    nv_ = nv;
    problem_ = &problem;
    for (int k = 1; k <= problem.num_layers; ++k) {
      theta2_rates_.push_back(shrink_morph_layer_weight(k, problem.num_layers));
    }
    const RestForms zero = laminate(theta2_layer_stack(problem, Eigen::VectorXd::Zero(nv)));
    energy_ = make_plate_energy(problem.plate, problem.F, zero);
    newton_tolerance_ =
        options.forward.relative_tolerance * unit_strain_energy(problem.plate, problem.F, zero);
    frame_ = central_face_frame(problem.plate, problem.F, problem.target, "the target");
    target_ = flatmorph::to_frame(frame_, problem.target);

    // Normalization (docs/design.md): distance in units of 0.3 % of the bounding-box diagonal,
    // averaged over the target's area; the mass term averaged over the area.
    mass_ = lumped_mass(problem.target, problem.F);
    area_ = mass_.sum();
    const double diagonal =
        (problem.target.colwise().maxCoeff() - problem.target.colwise().minCoeff()).norm();
    const double length = 0.003 * diagonal;
    distance_weight_ = 1.0 / (area_ * length * length);
    laplacian_ = cotan_laplacian(problem.target, problem.F);

    std::vector<Eigen::Triplet<double>> triplets;
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) triplets.emplace_back(f, problem.F(f, k), 1.0 / 3);
    }
    face_average_.resize(nf, nv);
    face_average_.setFromTriplets(triplets.begin(), triplets.end());

    is_fixed_.assign(3 * nv, false);
    for (int i : frame_.fixed_variables) is_fixed_[i] = true;
    const Eigen::SparseMatrix<double>& pat = energy_.hessian_pattern;
    for (int col = 0; col < pat.outerSize(); ++col) {
      for (int k = pat.outerIndexPtr()[col]; k < pat.outerIndexPtr()[col + 1]; ++k) {
        const int row = pat.innerIndexPtr()[k];
        if (is_fixed_[row] || is_fixed_[col]) fixed_entries_.push_back({k, row == col});
      }
    }
    configure_sparse_cholesky(solver_);
  }

  Eigen::VectorXd to_frame(const Eigen::MatrixXd& V) const {
    return flatmorph::to_frame(frame_, V);
  }
  Eigen::MatrixXd from_frame(const Eigen::VectorXd& x) const {
    return flatmorph::from_frame(frame_, x);
  }

  const Eigen::VectorXd& target() const { return target_; }

  // The equilibrium for theta2 (per vertex) from `start` (in the frame).
  // Line-search trials pass `trial`: their own iteration cap and tolerance.
  NewtonResult forward(const Eigen::VectorXd& theta2, Eigen::VectorXd start, bool trial = false) {
    stack_ = theta2_layer_stack(*problem_, theta2);
    set_rest_forms(energy_, laminate(stack_));
    for (int i : frame_.fixed_variables) start(i) = 0;
    NewtonProblem newton;
    newton.num_variables = 3 * nv_;
    newton.evaluate = [this](const Eigen::VectorXd& x, Eigen::VectorXd* g,
                             Eigen::SparseMatrix<double>* h, bool project) {
      return evaluate_plate_energy(energy_, x, g, h, project);
    };
    newton.fixed_variables = frame_.fixed_variables;
    NewtonOptions newton_options;
    newton_options.max_iterations =
        trial ? options_.max_trial_forward_iterations : options_.forward.max_iterations;
    newton_options.tolerance = newton_tolerance_ * (trial ? options_.trial_tolerance_factor : 1.0);
    const auto t0 = Clock::now();
    NewtonResult r = newton_minimize(newton, start, newton_options, &workspace_);
    forward_seconds_ += seconds_since(t0);
    forward_x_ = r.x;
    return r;
  }

  // The three terms of E at the equilibrium x.
  Eigen::Vector3d objective_terms(const Eigen::VectorXd& x, const Eigen::VectorXd& theta2) const {
    double distance = 0;
    for (int v = 0; v < nv_; ++v) {
      distance += mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v)).squaredNorm();
    }
    return {distance_weight_ * distance,
            options_.w_M * theta2.dot(mass_.cwiseProduct(theta2)) / area_,
            options_.w_L * theta2.dot(laplacian_ * theta2)};
  }

  // Factorizes H at x (the energy's current theta2) with the fixed variables decoupled (unit
  // rows/columns), and the sensitivity right-hand side J = ∂²W/∂x∂θ2 (3V x V, fixed rows zero).
  // When x is the converged result of the last forward solve, its final Newton factorization is
  // that of H at x already, and is reused.
  bool linearize(const Eigen::VectorXd& x) {
    LaminateDerivative derivative;
    laminate(stack_, theta2_rates_, derivative);
    Eigen::SparseMatrix<double> mixed =
        rest_forms_mixed_derivative(energy_, x, derivative) * face_average_;
    mixed.prune([this](Eigen::Index row, Eigen::Index, double) { return !is_fixed_[row]; });
    sensitivity_rhs_ = mixed;
    sensitivity_rhs_t_ = mixed.transpose();
    use_forward_factorization_ = workspace_.holds_exact_factorization() && x == forward_x_;
    if (use_forward_factorization_) return true;
    Eigen::VectorXd gradient;
    evaluate_plate_energy(energy_, x, &gradient, &hessian_, false);
    double* values = hessian_.valuePtr();
    for (const auto& [k, diagonal] : fixed_entries_) values[k] = diagonal ? 1.0 : 0.0;
    if (!analyzed_) {
      solver_.analyzePattern(hessian_);
      analyzed_ = true;
    }
    solver_.setShift(0.0);
    factorize(solver_, hessian_);
    if (solver_.info() != Eigen::Success) {
      ++shifted_factorizations_;
      // A stable equilibrium has a positive definite H; near a buckling point it is nearly
      // singular, so shift by growing multiples of its largest diagonal entry.
      const double scale = hessian_.diagonal().cwiseAbs().maxCoeff();
      for (double s = 1e-12; solver_.info() != Eigen::Success && s <= 1e-4; s *= 100) {
        solver_.setShift(s * scale);
        factorize(solver_, hessian_);
      }
      if (solver_.info() != Eigen::Success) return false;
    }
    return true;
  }

  // H⁻¹ b for b zero at the fixed variables (the result is zero there too).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    return use_forward_factorization_ ? workspace_.solve(b) : solver_.solve(b);
  }

  // dE/dx at x (zero at the fixed variables).
  Eigen::VectorXd distance_gradient(const Eigen::VectorXd& x) const {
    Eigen::VectorXd r(3 * nv_);
    for (int v = 0; v < nv_; ++v) {
      r.segment<3>(3 * v) =
          2 * distance_weight_ * mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v));
    }
    for (int i : frame_.fixed_variables) r(i) = 0;
    return r;
  }

  // Eq. 14 (after linearize at the equilibrium x).
  Eigen::VectorXd gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& theta2) const {
    const Eigen::VectorXd adjoint = solve(distance_gradient(x));
    return -(sensitivity_rhs_t_ * adjoint) + regularizer_product(theta2);
  }

  // (2 w_M M / A + 2 w_L L) v.
  Eigen::VectorXd regularizer_product(const Eigen::VectorXd& v) const {
    return 2 * options_.w_M / area_ * mass_.cwiseProduct(v) + 2 * options_.w_L * (laplacian_ * v);
  }

  // S v = dx/dθ2 · v = −H⁻¹ J v.
  Eigen::VectorXd sensitivity(const Eigen::VectorXd& v) const {
    return -solve(sensitivity_rhs_ * v);
  }

  // (Sᵀ 2D S + 2 w_M M / A + 2 w_L L) v, D the distance term's diagonal.
  Eigen::VectorXd gauss_newton_product(const Eigen::VectorXd& v) const {
    Eigen::VectorXd dx = sensitivity(v);
    for (int u = 0; u < nv_; ++u) dx.segment<3>(3 * u) *= 2 * distance_weight_ * mass_(u);
    for (int i : frame_.fixed_variables) dx(i) = 0;
    return -(sensitivity_rhs_t_ * solve(dx)) + regularizer_product(v);
  }

  // H at x with the fixed variables decoupled (lower triangle): linearize assembled it unless it
  // reused the forward solve's factorization, which only gives solves.
  Eigen::SparseMatrix<double> decoupled_hessian(const Eigen::VectorXd& x) const {
    if (!use_forward_factorization_) return hessian_;
    Eigen::VectorXd gradient;
    Eigen::SparseMatrix<double> h;
    evaluate_plate_energy(energy_, x, &gradient, &h, false);
    double* values = h.valuePtr();
    for (const auto& [k, diagonal] : fixed_entries_) values[k] = diagonal ? 1.0 : 0.0;
    return h;
  }

  // The SGN KKT matrix of gauss_newton_step.h, both triangles, unknowns (Δx, Δθ, λ). A fixed
  // coordinate's 2D entry is 1 instead of 0: its constraint row pins Δx_i = 0 whatever the entry
  // is, and a 0 would leave the exact zero pivot of [0 1; 1 0] to the LDLᵀ solvers.
  Eigen::SparseMatrix<double> kkt_matrix(const Eigen::SparseMatrix<double>& hessian) const {
    const int n = 3 * nv_, theta = n, lambda = n + nv_;
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(4 * hessian.nonZeros() + 2 * sensitivity_rhs_.nonZeros() + laplacian_.nonZeros() + n +
              nv_);
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, is_fixed_[i] ? 1.0 : 2 * distance_weight_ * mass_(i / 3));
    }
    for (int col = 0; col < hessian.outerSize(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(hessian, col); it; ++it) {
        const int row = static_cast<int>(it.row());
        t.emplace_back(row, lambda + col, it.value());
        t.emplace_back(lambda + col, row, it.value());
        if (row == col) continue;
        t.emplace_back(col, lambda + row, it.value());
        t.emplace_back(lambda + row, col, it.value());
      }
    }
    for (int col = 0; col < sensitivity_rhs_.outerSize(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(sensitivity_rhs_, col); it; ++it) {
        t.emplace_back(lambda + it.row(), theta + col, it.value());
        t.emplace_back(theta + col, lambda + it.row(), it.value());
      }
    }
    for (int v = 0; v < nv_; ++v)
      t.emplace_back(theta + v, theta + v, 2 * options_.w_M / area_ * mass_(v));
    for (int col = 0; col < laplacian_.outerSize(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian_, col); it; ++it) {
        t.emplace_back(theta + it.row(), theta + col, 2 * options_.w_L * it.value());
      }
    }
    Eigen::SparseMatrix<double> kkt(n + nv_ + n, n + nv_ + n);
    kkt.setFromTriplets(t.begin(), t.end());
    return kkt;
  }

  // The KKT unknowns grouped by vertex, x_v (3), θ_v, λ_v (3), the vertices in the AMD order of
  // the KKT matrix's vertex graph; returns each unknown's new position. Ordered as scalars, the
  // pairs (x_i, λ_i) are taken apart and the factor gets several times denser; grouped, λ_v's
  // pivot (a zero diagonal) comes after x_v's (2D > 0), which fills it.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> kkt_vertex_order(
      const Eigen::SparseMatrix<double>& kkt) const {
    const int n = 3 * nv_;
    auto vertex = [&](int i) { return i < n ? i / 3 : i < n + nv_ ? i - n : (i - n - nv_) / 3; };
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(kkt.nonZeros());
    for (int col = 0; col < kkt.outerSize(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(kkt, col); it; ++it) {
        t.emplace_back(vertex(static_cast<int>(it.row())), vertex(col), 1.0);
      }
    }
    Eigen::SparseMatrix<double> graph(nv_, nv_);
    graph.setFromTriplets(t.begin(), t.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> by_vertex;  // new -> old vertex
    Eigen::AMDOrdering<int>()(graph, by_vertex);
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> position(n + nv_ + n);
    for (int k = 0; k < nv_; ++k) {
      const int v = by_vertex.indices()(k);
      for (int c = 0; c < 3; ++c) {
        position.indices()(3 * v + c) = 7 * k + c;
        position.indices()(n + nv_ + 3 * v + c) = 7 * k + 4 + c;
      }
      position.indices()(n + v) = 7 * k + 3;
    }
    return position;
  }

  // The Gauss–Newton step by the KKT system (after linearize at the equilibrium x): fills the
  // step's direction, dx, sizes and timings; false when the factorization fails. H is the exact
  // one even when linearize had to shift its factorization.
  bool kkt_step(const Eigen::VectorXd& x, const Eigen::VectorXd& theta2, KktSolver kind,
                GaussNewtonStep& out) const {
    const int n = 3 * nv_;
    auto t0 = Clock::now();
    const Eigen::SparseMatrix<double> kkt = kkt_matrix(decoupled_hessian(x));
    // Stationarity of the model in Δx and Δθ (first two rows), linearized equilibrium (last).
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(kkt.rows());
    rhs.head(n) = -distance_gradient(x);
    rhs.segment(n, nv_) = -regularizer_product(theta2);
    out.assembly_seconds = seconds_since(t0);
    out.kkt_rows = static_cast<int>(kkt.rows());
    out.kkt_nonzeros = kkt.nonZeros();
    const bool by_vertex =
        kind == KktSolver::kSimplicialLDLTByVertex || kind == KktSolver::kCholmodLDLTByVertex;
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> position;
    Eigen::SparseMatrix<double> permuted;
    Eigen::VectorXd permuted_rhs;
    double ordering_seconds = 0;
    if (by_vertex) {
      t0 = Clock::now();
      position = kkt_vertex_order(kkt);
      permuted = position * kkt * position.transpose();
      permuted_rhs = position * rhs;
      ordering_seconds = seconds_since(t0);
    }
    Eigen::VectorXd z;
    auto run = [&](auto& solver) {
      return by_vertex ? factorize_and_solve(solver, permuted, permuted_rhs, z, out)
                       : factorize_and_solve(solver, kkt, rhs, z, out);
    };
    bool ok = false;
    switch (kind) {
      case KktSolver::kSparseLU: {
        Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
        ok = run(lu);
        if (ok) out.factor_nonzeros = lu.nnzL() + lu.nnzU();
        break;
      }
      case KktSolver::kSimplicialLDLT: {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
        ok = run(ldlt);
        if (ok) out.factor_nonzeros = ldlt.matrixL().nestedExpression().nonZeros();
        break;
      }
      case KktSolver::kSimplicialLDLTByVertex: {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                              Eigen::NaturalOrdering<int>>
            ldlt;
        ok = run(ldlt);
        if (ok) out.factor_nonzeros = ldlt.matrixL().nestedExpression().nonZeros();
        break;
      }
      case KktSolver::kCholmodLDLT:
      case KktSolver::kCholmodLDLTByVertex: {
        Eigen::CholmodSimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
        ldlt.cholmod().print = 0;
        if (by_vertex) {
          ldlt.cholmod().nmethods = 1;
          ldlt.cholmod().method[0].ordering = CHOLMOD_NATURAL;
        }
        ok = run(ldlt);
        if (ok) out.factor_nonzeros = static_cast<long>(ldlt.cholmod().lnz);
        break;
      }
    }
    out.analysis_seconds += ordering_seconds;
    if (ok && by_vertex) z = position.transpose() * z;
    out.seconds =
        out.assembly_seconds + out.analysis_seconds + out.factorization_seconds + out.solve_seconds;
    if (!ok) return false;
    out.dx = z.head(n);
    out.direction = z.segment(n, nv_);
    return true;
  }

  double forward_seconds() const { return forward_seconds_; }
  int shifted_factorizations() const { return shifted_factorizations_; }

 private:
  const OptimizeTheta2Options& options_;
  int nv_ = 0;
  PlateEnergy energy_;
  const Theta2Problem* problem_ = nullptr;
  std::vector<double> theta2_rates_;  // d theta^k / d theta2 of each layer
  LayerStack stack_;                  // printed for the energy's current theta2
  double newton_tolerance_ = 0;
  RigidFrame frame_;
  std::vector<bool> is_fixed_;
  std::vector<std::pair<int, bool>> fixed_entries_;  // Hessian nonzeros in a fixed row/column
  Eigen::VectorXd target_, mass_;
  double area_ = 0, distance_weight_ = 0;
  Eigen::SparseMatrix<double> laplacian_, face_average_;
  Eigen::SparseMatrix<double> hessian_, sensitivity_rhs_, sensitivity_rhs_t_;
  SparseCholesky solver_;
  bool analyzed_ = false;
  NewtonWorkspace workspace_;
  Eigen::VectorXd forward_x_;  // the last forward solve's result
  bool use_forward_factorization_ = false;
  double forward_seconds_ = 0;
  int shifted_factorizations_ = 0;
};

bool forward_ok(const NewtonResult& r) {
  return r.status == NewtonStatus::kConverged || r.status == NewtonStatus::kLineSearchFailed;
}

// Conjugate gradients on the SPD Gauss–Newton system A d = b, from d = 0 (so every iterate is a
// descent direction for E). Returns the iterations taken.
template <typename Product>
int conjugate_gradient(const Product& product, const Eigen::VectorXd& b, double tolerance,
                       int max_iterations, Eigen::VectorXd& d) {
  d.setZero(b.size());
  Eigen::VectorXd r = b, p = b;
  double rr = r.squaredNorm();
  const double stop = tolerance * tolerance * rr;
  int it = 0;
  for (; it < max_iterations && rr > stop; ++it) {
    const Eigen::VectorXd ap = product(p);
    const double pap = p.dot(ap);
    if (!(pap > 0)) break;
    const double alpha = rr / pap;
    d += alpha * p;
    r -= alpha * ap;
    const double rr_new = r.squaredNorm();
    p = r + (rr_new / rr) * p;
    rr = rr_new;
  }
  return it;
}

}  // namespace

Theta2Problem theta2_problem(const FlatPlate& flat, const Material& material, int num_layers) {
  Theta2Problem problem;
  problem.plate = flat.plate;
  problem.F = flat.target.F;
  problem.target = flat.target.V;
  problem.theta1 = flat.theta1;
  problem.material = material;
  problem.num_layers = num_layers;
  return problem;
}

LayerStack theta2_layer_stack(const Theta2Problem& problem, const Eigen::VectorXd& theta2) {
  return shrink_morph_layer_stack(problem.theta1, vertex_to_face_average(problem.F, theta2),
                                  problem.material, problem.num_layers,
                                  problem.material.layer_height);
}

PlateProblem theta2_plate_problem(const Theta2Problem& problem, const Eigen::VectorXd& theta2) {
  PlateProblem plate;
  plate.plate = problem.plate;
  plate.F = problem.F;
  plate.rest_forms = laminate(theta2_layer_stack(problem, theta2));
  return plate;
}

Theta2Evaluation evaluate_theta2_objective(const Theta2Problem& problem,
                                           const Eigen::VectorXd& theta2,
                                           const Eigen::MatrixXd& start,
                                           const OptimizeTheta2Options& options,
                                           bool with_gradient) {
  Theta2Solver solver(problem, options);
  const NewtonResult r = solver.forward(theta2, solver.to_frame(start));
  Theta2Evaluation out;
  out.forward_converged = forward_ok(r);
  out.objective = solver.objective_terms(r.x, theta2).sum();
  out.V = solver.from_frame(r.x);
  if (with_gradient && solver.linearize(r.x)) out.gradient = solver.gradient(r.x, theta2);
  return out;
}

Theta2Result optimize_theta2(const Theta2Problem& problem, const Eigen::VectorXd& theta2_start,
                             const OptimizeTheta2Options& options) {
  const auto t0 = Clock::now();
  Theta2Solver solver(problem, options);
  const int nv = static_cast<int>(problem.plate.rows());
  Eigen::VectorXd theta2 =
      theta2_start.size() == 0 ? Eigen::VectorXd::Zero(nv) : Eigen::VectorXd(theta2_start);
  if (theta2.size() != nv) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("theta2 start has {} values for {} vertices: give one per vertex",
                                theta2.size(), nv));
  }
  Theta2Result out;
  const NewtonResult initial = solver.forward(
      theta2, problem.start.size() ? solver.to_frame(problem.start) : solver.target());
  out.initial_forward_converged = forward_ok(initial);
  Eigen::VectorXd x = initial.x;
  out.initial_V = solver.from_frame(x);
  out.initial_seconds = seconds_since(t0);
  Eigen::Vector3d terms = solver.objective_terms(x, theta2);
  double objective = terms.sum();
  out.initial_objective = objective;
  out.stop_reason = "iteration limit";
  double trust_radius = options.max_step_rad;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    Theta2Iteration record;
    record.iteration = iteration;
    record.objective = objective;
    record.distance_term = terms(0);
    const int shifted_before = solver.shifted_factorizations();
    const bool linearized = solver.linearize(x);
    record.shifted_hessian = solver.shifted_factorizations() > shifted_before;
    if (!linearized) {
      out.stop_reason = "the equilibrium's Hessian could not be factorized";
      break;
    }
    const Eigen::VectorXd g = solver.gradient(x, theta2);
    if (!g.allFinite() || !std::isfinite(objective)) {
      // Keep the last finite state rather than report a stationary point of NaNs.
      out.stop_reason = "the objective or its gradient is not finite";
      out.history.push_back(record);
      break;
    }
    const auto t_cg = Clock::now();
    Eigen::VectorXd direction;
    record.cg_iterations =
        conjugate_gradient([&](const Eigen::VectorXd& v) { return solver.gauss_newton_product(v); },
                           -g, options.cg_tolerance, options.max_cg_iterations, direction);
    const Eigen::VectorXd dx = solver.sensitivity(direction);
    out.cg_seconds += seconds_since(t_cg);
    const double slope = g.dot(direction);
    record.decrement = -0.5 * slope;
    if (!(slope < 0)) {
      out.converged = true;
      out.stop_reason = "no descent direction (stationary point)";
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
      break;
    }
    if (record.decrement < options.decrement_tolerance) {
      out.converged = true;
      out.stop_reason = "predicted decrease below tolerance";
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
      break;
    }
    // A step that turns some θ2 by more than max_step_rad leaves the range where the linear
    // prediction warm-starts the forward solve well (soft modes make S Δθ huge): shorten it.
    // The length accepted last time is remembered (a trust radius), so that the trials it took
    // to find it are not repeated at every iteration.
    const double direction_max = direction.cwiseAbs().maxCoeff();
    double step = std::min(1.0, trust_radius / direction_max);
    bool accepted = false;
    for (int k = 0;
         k < options.max_line_search_steps && step * direction_max >= options.min_step_rad;
         ++k, step *= 0.5) {
      const Eigen::VectorXd trial_theta2 = theta2 + step * direction;
      // Warm start at the linear prediction x + s S Δθ.
      const NewtonResult trial = solver.forward(trial_theta2, x + step * dx, true);
      ++record.line_search_trials;
      record.forward_iterations += trial.iterations;
      if (!forward_ok(trial)) continue;
      const Eigen::Vector3d trial_terms = solver.objective_terms(trial.x, trial_theta2);
      const double trial_objective = trial_terms.sum();
      if (trial_objective <= objective + options.armijo_constant * step * slope) {
        accepted = true;
        theta2 = trial_theta2;
        x = trial.x;
        terms = trial_terms;
        trust_radius = std::min(options.max_step_rad, (k == 0 ? 2.0 : 1.0) * step * direction_max);
        break;
      }
    }
    // The accepted trial was the last forward solve, so the energy holds its b̄ for the next
    // linearization.
    record.step = accepted ? step : 0;
    record.elapsed_seconds = seconds_since(t0);
    out.history.push_back(record);
    if (options.progress) options.progress(record);
    if (!accepted) {
      // Every step longer than min_step_rad leaves the current equilibrium branch (the forward
      // solve of each trial turns unstable): the equilibrium sits near a fold, and the shapes
      // closer to the target lie beyond it. Solving such a trial to the end (a snap) took the hat
      // 200 Newton iterations without settling, so the optimization stops here.
      out.stop_reason = step * direction_max < options.min_step_rad
                            ? "stalled: every step leaves the current equilibrium branch"
                            : "line search failed";
      break;
    }
    ++out.iterations;
    const double decrease = record.objective - terms.sum();
    objective = terms.sum();
    if (decrease < options.relative_decrease * record.objective) {
      out.converged = true;
      out.stop_reason = "relative decrease below tolerance";
      break;
    }
  }
  // Line-search trials stop at a looser tolerance; a soft plate (the saddle) can still creep by
  // millimetres from there. The result is the equilibrium itself, so that the design's figures
  // are those any simulation of the printed plate gives.
  const NewtonResult final_solve = solver.forward(theta2, x);
  if (forward_ok(final_solve)) {
    x = final_solve.x;
    terms = solver.objective_terms(x, theta2);
    objective = terms.sum();
  }
  out.theta2 = theta2;
  out.V = solver.from_frame(x);
  out.objective = objective;
  out.distance_term = terms(0);
  out.forward_seconds = solver.forward_seconds();
  out.shifted_factorizations = solver.shifted_factorizations();
  out.seconds = seconds_since(t0);
  return out;
}

GaussNewtonStep theta2_gauss_newton_step(const Theta2Problem& problem,
                                         const Eigen::VectorXd& theta2, GaussNewtonSystem system,
                                         const OptimizeTheta2Options& options,
                                         KktSolver kkt_solver) {
  Theta2Solver solver(problem, options);
  if (theta2.size() != problem.plate.rows()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("theta2 has {} values for {} vertices: give one per vertex",
                                theta2.size(), problem.plate.rows()));
  }
  const NewtonResult r = solver.forward(
      theta2, problem.start.size() ? solver.to_frame(problem.start) : solver.target());
  GaussNewtonStep out;
  out.forward_converged = forward_ok(r);
  if (!solver.linearize(r.x)) return out;
  out.gradient = solver.gradient(r.x, theta2);
  if (system == GaussNewtonSystem::kReducedCG) {
    const auto t0 = Clock::now();
    out.cg_iterations = conjugate_gradient(
        [&](const Eigen::VectorXd& v) { return solver.gauss_newton_product(v); }, -out.gradient,
        options.cg_tolerance, options.max_cg_iterations, out.direction);
    // optimize_theta2 needs S Δθ too (the line search's warm start); the KKT system gives it.
    out.dx = solver.sensitivity(out.direction);
    out.seconds = out.solve_seconds = seconds_since(t0);
    out.solved = true;
  } else {
    out.solved = solver.kkt_step(r.x, theta2, kkt_solver, out);
  }
  if (out.solved) {
    out.reduced_residual =
        (solver.gauss_newton_product(out.direction) + out.gradient).norm() / out.gradient.norm();
  }
  return out;
}

}  // namespace flatmorph
