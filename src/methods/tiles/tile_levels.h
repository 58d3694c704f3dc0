// What each ring of a Geodesy tile prints (CHI 2019 §3, §4, §7): the shrink its place in the
// profile asks (tile_profile.h), clamped to what the material's thickness curve reaches, split
// into a bilayer that makes the tile rise to its chosen side (§4, Fig. 6), and turned into layer
// heights and layer counts Floor(total / t) (§3). Rings are counted by level m from the outline
// (m = 0 outermost, at depth (m + ½) w); all rings of one level print alike. Millimetres.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "material/material.h"
#include "methods/tiles/tile_profile.h"

namespace flatmorph {

struct RingLevelOptions {
  double pitch = 0.4;            // w: ring spacing = path width, mm
  double sheet_thickness = 0.6;  // printed: Floor(thickness / t) layers, half of them per half (§3)
  // δ: the bed-side half shrinks this much more than the top half for a tile rising to +z (the
  // side that shrinks more along the rings becomes concave; notes §5), less for one rising to −z.
  // 0: per ring, the δ whose rest curvature along the ring, 3δ / (2T) for two equal halves of a
  // sheet T thick (Timoshenko's bilayer), is the target's own normal curvature along that parallel,
  // sin α / ρ (α the profile's slope, ρ the distance to the axis), within [1, 6] points: the
  // bilayer then bends the rings as the risen surface does instead of against it. A fixed δ
  // over-bends a large tile's outer rings (a 60 mm cone with δ = 4 points rose 10 % short, in 81
  // Newton steps) or under-bends a small one's (a 30 mm cone with 2 points, 3 % short).
  double bilayer_difference = 0;
  bool strict = false;  // refuse a profile that needs a clamped ring rather than print it
};

// One ring level: ring m sits at depth (m + ½) w from the outline, at flat radius r = R − depth of
// the circular design tile of radius R (the tile's largest depth: its inradius; CHI 2019 §7
// reuses the circle's shrink on a polygon by ring, the notes' A10 by depth).
struct RingLevel {
  double depth = 0;        // mm from the outline
  double flat_radius = 0;  // r, mm, on the design circle
  double wanted = 0;       // Sh(r) the profile asks
  // Sh printed: the halves' shrink weighted by their thickness, around the clamped Sh(r)
  double shrinkage = 0;
  int clamped = 0;                // −1 raised to the least, +1 lowered to the most, 0 reached
  double bilayer_difference = 0;  // δ of this ring
  double bed_shrinkage = 0;       // of the bed-side half
  double top_shrinkage = 0;       // of the top half
  double bed_layer_height = 0, top_layer_height = 0;  // mm
  int bed_layers = 0, top_layers = 0;                 // Floor(total / t) shared, at least 1 each
  bool printed = true;                                // false inside a hole (CHI 2019 Fig. 7)

  int layers() const { return bed_layers + top_layers; }
  double thickness() const { return bed_layers * bed_layer_height + top_layers * top_layer_height; }
  // Nozzle height of this ring's pass p (1-based, up to layers()): its bead's top, mm.
  double pass_z(int pass) const;
  double pass_layer_height(int pass) const;
};

struct TileLevels {
  std::vector<RingLevel> levels;  // by m, outermost first
  double design_radius = 0;       // R, mm: the largest depth of the outline
  int side = +1;
  PrintabilityReport printability;
};

// The levels of a tile of `design_radius` R (mm) with `num_levels` ring levels, printing
// `profile` (rescaled to R, tile_profile.h) of `material` (a thickness curve needed), leaving out
// levels whose flat radius is below `hole_radius` (mm). Throws UserError (kInfeasible) from
// printability (no printable ring, or strict), kOption for a material without a thickness curve
// or options out of range.
TileLevels tile_levels(const TileProfile& profile, double design_radius, int num_levels, int side,
                       double hole_radius, const Material& material,
                       const RingLevelOptions& options);

// The same levels with other printed shrinks (one per level, e.g. optimized; clamped again).
void set_level_shrinkage(TileLevels& levels, const Eigen::VectorXd& shrinkage,
                         const Material& material, const RingLevelOptions& options);

}  // namespace flatmorph
