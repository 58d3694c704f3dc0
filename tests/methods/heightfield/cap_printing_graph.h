// A printing graph whose SCF flattening is known in closed form, for the tests of the rise
// prediction and the shrink optimization: a spherical cap of radius R and polar angle φ0, its
// isolines the circles of latitude (rings at φ_i = φ0 (1 − i/n), ring 0 the boundary), zipped
// into triangles between neighbouring rings by angle, with a fan (patch centre) at the pole.
//
// The flat plate: ring i keeps its vertices' azimuths α and lies at radius ρ(φ) = R φ / λ2, so that
// the bridges across the rings, which grow by λ2 when heated, come back to the meridian's length
// R dφ. A ring's target length is 2π R sin φ and its flat length 2π R φ / λ2, so it must shrink by
// σ(φ) = 1 − λ2 sin φ / φ (exactly, edge by edge: chords of regular polygons scale alike). Printed
// along the rings with σ, each face's rest metric R(θ) diag((1 − σ)², λ2²) R(θ)ᵀ is the cap's
// metric pulled back to the plate (to the error of a face's σ being the mean of its corners').
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "material/material.h"
#include "methods/heightfield/isoline_mesh.h"

namespace flatmorph::testing {

// The cap both tests use: 120 mm across (R sin φ0 = 60 mm), φ0 = 0.6 rad.
inline constexpr double kCapAngle = 0.6;
inline const double kCapRadius = 60.0 / std::sin(kCapAngle);

// pla-geodesy grows nothing across its paths (λ2 = 1), so the cap's rings would have to shrink by
// σ(φ) = 1 − sin φ / φ ≤ 5.9 %, less than the least its curve gives (7.9 %). The tests take the
// same material with λ2 = 0.85, for which the cap asks σ from 1 − λ2 = 15 % at the pole to
// 1 − λ2 sin φ0 / φ0 = 20.0 % at the rim, inside the curve's range.
inline Material cap_material() {
  Material m = load_material("pla-geodesy");
  m.lambda2 = 0.85;
  return m;
}

struct CapPrintingGraph {
  IsolineMesh mesh;
  Eigen::MatrixXd plate;           // #V x 2, mm
  Eigen::VectorXd edge_shrinkage;  // per edge of mesh.E: σ on rings, NaN on bridges
  Eigen::VectorXd ring_angle;      // per vertex: its polar angle φ (0 at the pole)
  Eigen::VectorXd azimuth;         // per vertex: α
};

// `radius` R (mm), `cap_angle` φ0 (rad), `rings` n (levels; ring 0 is the boundary), vertices on a
// ring about `spacing` mm apart (at least 6), `lambda2` the growth across the paths.
inline CapPrintingGraph cap_printing_graph(double radius, double cap_angle, int rings,
                                           double spacing, double lambda2) {
  CapPrintingGraph cap;
  std::vector<std::vector<int>> ring_vertices(rings);
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> flat;
  std::vector<double> phis, alphas;
  std::vector<int> levels;
  auto add_vertex = [&](double phi, double alpha, int level) {
    positions.emplace_back(radius * std::sin(phi) * std::cos(alpha),
                           radius * std::sin(phi) * std::sin(alpha),
                           radius * (std::cos(phi) - std::cos(cap_angle)));
    const double rho = radius * phi / lambda2;
    flat.emplace_back(rho * std::cos(alpha), rho * std::sin(alpha));
    phis.push_back(phi);
    alphas.push_back(alpha);
    levels.push_back(level);
    return static_cast<int>(positions.size()) - 1;
  };
  std::vector<int> counts(rings);
  for (int i = 0; i < rings; ++i) {
    const double phi = cap_angle * (1.0 - double(i) / rings);
    const int count = std::max(
        6, static_cast<int>(std::lround(2 * std::numbers::pi * radius * std::sin(phi) / spacing)));
    counts[i] = count;
    const double offset = 0.37 * i;  // rings turned against each other: a general zip
    for (int j = 0; j < count; ++j) {
      ring_vertices[i].push_back(add_vertex(phi, offset + 2 * std::numbers::pi * j / count, i));
    }
  }
  const int pole = add_vertex(0.0, 0.0, -1);
  std::vector<Eigen::Vector3i> faces;
  for (int i = 0; i + 1 < rings; ++i) {
    const std::vector<int>& lower = ring_vertices[i];
    const std::vector<int>& upper = ring_vertices[i + 1];
    const int nl = static_cast<int>(lower.size()), nu = static_cast<int>(upper.size());
    // Unwrapped azimuths: the upper ring starts at its vertex nearest the lower ring's first.
    const double a0 = alphas[lower[0]];
    int k0 = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < nu; ++k) {
      const double d = std::abs(std::remainder(alphas[upper[k]] - a0, 2 * std::numbers::pi));
      if (d < best) best = d, k0 = k;
    }
    auto lower_angle = [&](int j) { return a0 + 2 * std::numbers::pi * j / nl; };
    const double b0 = a0 + std::remainder(alphas[upper[k0]] - a0, 2 * std::numbers::pi);
    auto upper_angle = [&](int k) { return b0 + 2 * std::numbers::pi * k / nu; };
    int j = 0, k = 0;
    while (j < nl || k < nu) {
      const bool advance_lower = k == nu || (j < nl && lower_angle(j + 1) < upper_angle(k + 1));
      const int l0 = lower[j % nl], u0 = upper[(k0 + k) % nu];
      if (advance_lower) {
        faces.emplace_back(l0, lower[(j + 1) % nl], u0);
        ++j;
      } else {
        faces.emplace_back(upper[(k0 + k + 1) % nu], u0, l0);
        ++k;
      }
    }
  }
  const std::vector<int>& top = ring_vertices[rings - 1];
  for (size_t j = 0; j < top.size(); ++j) {
    faces.emplace_back(top[j], top[(j + 1) % top.size()], pole);
  }

  const int nv = static_cast<int>(positions.size());
  IsolineMesh& m = cap.mesh;
  m.V.resize(nv, 3);
  cap.plate.resize(nv, 2);
  cap.ring_angle.resize(nv);
  cap.azimuth.resize(nv);
  m.vertex_level.resize(nv);
  m.vertex_loop.resize(nv);
  for (int v = 0; v < nv; ++v) {
    m.V.row(v) = positions[v].transpose();
    cap.plate.row(v) = flat[v].transpose();
    cap.ring_angle(v) = phis[v];
    cap.azimuth(v) = alphas[v];
    m.vertex_level(v) = levels[v];
    m.vertex_loop(v) = levels[v];
  }
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) m.F.row(f) = faces[f].transpose();
  std::map<std::pair<int, int>, int> edges;
  for (const Eigen::Vector3i& face : faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = face(c), b = face((c + 1) % 3);
      edges.emplace(std::minmax(a, b), 0);
    }
  }
  m.E.resize(static_cast<Eigen::Index>(edges.size()), 2);
  cap.edge_shrinkage.resize(m.E.rows());
  int e = 0;
  for (auto& [ends, index] : edges) {
    index = e;
    m.E.row(e) << ends.first, ends.second;
    const int la = levels[ends.first], lb = levels[ends.second];
    if (la == lb && la >= 0) {
      m.edge_kind.push_back(la == 0 ? EdgeKind::kBoundary : EdgeKind::kPrinting);
      const double target = (m.V.row(ends.first) - m.V.row(ends.second)).norm();
      const double printed = (cap.plate.row(ends.first) - cap.plate.row(ends.second)).norm();
      cap.edge_shrinkage(e) = 1 - target / printed;
    } else {
      m.edge_kind.push_back(EdgeKind::kBridge);
      cap.edge_shrinkage(e) = std::numeric_limits<double>::quiet_NaN();
    }
    ++e;
  }
  m.levels.resize(rings);
  for (int i = 0; i < rings; ++i) {
    m.levels(i) = radius * (std::cos(cap_angle * (1.0 - double(i) / rings)) - std::cos(cap_angle));
    m.loops.push_back({i, i - 1, ring_vertices[i]});
  }
  return cap;
}

}  // namespace flatmorph::testing
