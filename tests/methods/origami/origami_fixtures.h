// Crease patterns shared by the origami tests: a built-in solid's net, and small sheets drawn by
// hand (as the SVG reader will give them).
#pragma once

#include <Eigen/Core>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "examples/origami_examples.h"
#include "methods/origami/actuators.h"
#include "methods/origami/crease_pattern.h"

namespace flatmorph::testing {

// The first net of a built-in solid, folds below 1° flat, as the inverse flow makes it.
inline CreasePattern example_sheet(const std::string& solid, double edge_mm) {
  return crease_pattern_of_net(unfold(polyhedron_example(solid, edge_mm)), 0, "net 1",
                               std::numbers::pi / 180);
}

// A sheet from its corners and faces (counter-clockwise): a side two faces share is a crease, any
// other a border. `folds` lists the tree in fold order from face 0, the root: (child, parent, fold
// angle in rad; 0 for a flat crease). Shared sides off the tree stay flat creases.
inline CreasePattern drawn_sheet(const Eigen::MatrixX2d& V,
                                 const std::vector<std::vector<int>>& faces,
                                 const std::vector<std::tuple<int, int, double>>& folds) {
  CreasePattern out;
  out.name = "drawn";
  out.V = V;
  out.faces = faces;
  std::map<std::pair<int, int>, int> crease_of;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    for (size_t k = 0; k < faces[f].size(); ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % faces[f].size()];
      const auto twin = crease_of.find({b, a});
      if (twin != crease_of.end()) {
        out.creases[twin->second].right = f;
        out.creases[twin->second].kind = CreaseKind::kFlat;
        continue;
      }
      crease_of[{a, b}] = static_cast<int>(out.creases.size());
      out.creases.push_back({a, b, f, -1, CreaseKind::kBorder, 0});
    }
  }
  out.root = 0;
  out.parent_crease.assign(faces.size(), -1);
  out.fold_order = {0};
  out.solid_face.assign(faces.size(), -1);
  for (const auto& [child, parent, angle] : folds) {
    int found = -1;
    for (int c = 0; c < static_cast<int>(out.creases.size()); ++c) {
      const Crease& crease = out.creases[c];
      if ((crease.left == child && crease.right == parent) ||
          (crease.left == parent && crease.right == child)) {
        found = c;
      }
    }
    if (found < 0) throw std::invalid_argument("drawn_sheet: the faces share no side");
    Crease& crease = out.creases[found];
    crease.fold_angle = angle;
    crease.kind = angle > 0   ? CreaseKind::kValley
                  : angle < 0 ? CreaseKind::kMountain
                              : CreaseKind::kFlat;
    out.parent_crease[child] = found;
    out.fold_order.push_back(child);
  }
  return out;
}

// A design for every hinge of the pattern on arcs of `radius` mm (case A for mountains, 150 mm/s).
inline std::vector<HingeDesign> hinges_of(const CreasePattern& pattern, double radius) {
  std::vector<HingeDesign> out;
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    if (!pattern.is_hinge(c)) continue;
    const double angle = pattern.creases[c].fold_angle;
    out.push_back(hinge_design(c, angle, radius, angle < 0, 150));
  }
  return out;
}

}  // namespace flatmorph::testing
