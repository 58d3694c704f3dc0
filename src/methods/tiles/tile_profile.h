// The inverse design of one Geodesy tile (CHI 2019 §7, Fig. 8): a side-view profile (the meridian
// of a surface of revolution) gives the shrink each concentric ring must have, Sh(s) = 1 − ρ(s)/s,
// where ρ(s) is the profile's distance to the axis at arc length s from the apex: the ring printed
// at flat radius s shortens by Sh while the spacing between rings stays put, so the meridian keeps
// its length and the ring lands at radius ρ(s). Also: the built-in profile shapes, user profiles
// from CSV, the clamp to the material's reachable shrink, the forward model (shrink → shape) and
// the mapping of a circular tile's shrink onto polygonal tiles.
//
// Millimetres everywhere; shrink as a fraction (0.0793 for 7.93 %); angles in radians.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

struct TileProfile {
  // For messages: the library name or the file the profile came from.
  std::string name;
  // #P x 2, mm: the meridian as a polyline of (ρ, z) points, ρ the distance to the axis, from the
  // apex on the axis (ρ = 0) to the rim. Library profiles rise to +z: the apex at z = height, the
  // rim at z = 0. Overhangs (ρ decreasing) are allowed; a profile that starts off the axis (a tile
  // with a hole cut from the profile's inside) is not: give the full profile from the apex and drop
  // the inner rings instead (note A7).
  Eigen::MatrixX2d meridian;
};

// Throws UserError(kGeometry) naming `source` and the point when `profile` is not a meridian:
// fewer than 2 points, NaN/Inf or absurd (> 1e6 mm) coordinates, ρ < 0, a first point off the axis
// (|ρ| > 1e-9 mm), or a point repeating the one before it (arc length must strictly increase).
void check_tile_profile(const TileProfile& profile, const std::string& source);

// The library's names, in a fixed order.
std::vector<std::string> tile_profile_names();

// A library profile as a shape scaled to one tile (note A11): its meridian is exactly
// `flat_radius_mm` long (the flat tile's radius R: the meridian keeps its length) and it rises
// `height_mm` (0 < height < R). Shapes: "spherical-cap"; "cone" (slope asin(H/R)); "paraboloid";
// "gaussian" (a bump to 3σ, round top and concave foot); "concave" (a horn z ∝ (1 − r)²: concave
// flanks, pointed top); "transition" (note A5: a pointed concave top over a convex steep skirt);
// "subtle-cone" and "dramatic-cone", the cones whose uniform shrink is the least (7.93 %, 22.97°)
// and the most (37.27 %, 51.15°) Geodesy's PLA gives (note §3.2): their slope is fixed, so their
// height follows from R and `height_mm` is ignored. Curves are sampled with chords within 1e-7 R
// (at most 1e-3 mm) of the curve, the same points at every scale. Throws UserError(kOption) for an
// unknown name (listing the names), a radius or height that is not positive and finite, a height ≥
// R, or a height the shape cannot reach (a spherical cap rises at most 0.7246 R).
TileProfile tile_profile(const std::string& name, double flat_radius_mm, double height_mm);

// A user profile from CSV text: one "r,z" row per point (mm, r the distance to the axis), in order
// from the apex on the axis (r = 0) to the rim; an optional header line, '#' comments, blank lines.
// Throws UserError(kFormat) as "SOURCE:LINE: problem; what to do" for a cell that is not a number,
// NaN/Inf, r < 0, a first point off the axis, a repeated point, fewer than 2 points or more than
// 100 000 rows. The profile is named `source`.
TileProfile read_profile_csv(std::string_view text, const std::string& source);

// The same shape scaled uniformly so that its meridian is `flat_radius_mm` long (a user profile
// fitted to a tile; Sh is scale-invariant, note A11).
TileProfile scale_profile_to_length(const TileProfile& profile, double flat_radius_mm);

// The meridian's arc length (mm).
double profile_length(const TileProfile& profile);

// Greatest minus least z of the meridian (mm).
double profile_height(const TileProfile& profile);

// The (ρ, z) point (mm) at arc length `s` mm from the apex, by linear interpolation along the
// polyline. Throws UserError(kGeometry) when s exceeds the profile's length (the profile is shorter
// than the tile) and std::invalid_argument when s is negative or NaN.
Eigen::Vector2d profile_point_at_length(const TileProfile& profile, double s);

// Sh(s) = 1 − ρ(s)/s of the ring at flat radius `s` mm (CHI 2019 §7: Sh = 1 − F(G(R_i))/R_i); at
// s = 0 the limit 1 − dρ/ds at the apex. Throws as profile_point_at_length.
double ring_shrinkage(const TileProfile& profile, double s);

// The rings of one tile: what the profile asks of each, and what the material can print.
struct RingShrinkage {
  Eigen::VectorXd
      flat_radius;          // mm, the rings' centrelines on the flat sheet, as the caller gave them
  Eigen::VectorXd wanted;   // Sh the profile asks, fraction
  Eigen::VectorXd printed;  // wanted clamped to [least, most]
  // −1 raised to the least, +1 lowered to the most, 0 printed as wanted (within 1e-9).
  Eigen::VectorXi clamped;
  double least = 0;  // the material's reachable range (fractions), note §3.7
  double most = 0;
};

// The rings at `flat_radii` (mm, each > 0, distinct, any order; note A8: pass the bead centrelines
// r = R − (m + ½)w), their wanted Sh from `profile` and Sh clamped to [least, most] (the material's
// reachable range, reachable_shrinkage in material/thickness_curve.h). Throws UserError(kGeometry)
// when a ring lies beyond the profile's length; std::invalid_argument for bad radii or a range
// without 0 ≤ least < most < 1.
RingShrinkage tile_ring_shrinkage(const TileProfile& profile, const Eigen::VectorXd& flat_radii,
                                  double least, double most);

// The shape a table of ring shrinks gives, by the model of note §3.1 ("Forward"): ring k lands at
// ρ_k = (1 − Sh_k) r_k and the meridian keeps its length r_k − r_(k−1) between neighbouring rings,
// starting from the apex (r = 0, ρ = 0, z = 0) and always going down.
struct ForwardProfile {
  // One row per ring, in the order of the input: (ρ, z) in mm, z ≤ 0 measured from the apex.
  Eigen::MatrixX2d points;
  // Steps where |Δρ| > Δr (r·Sh decreasing, or a ring that grows): the meridian cannot keep its
  // length. The ring keeps the radius its shrink gives, the step is taken horizontal (Δz = 0), and
  // `stretch` (mm) sums the length the meridian would have to gain there.
  int horizontal_steps = 0;
  double stretch = 0;
};
// `flat_radii` as for tile_ring_shrinkage; `shrinkage` the same size, each ≤ 1.
ForwardProfile profile_from_shrinkage(const Eigen::VectorXd& flat_radii,
                                      const Eigen::VectorXd& shrinkage);

struct PrintabilityReport {
  bool any_clamped = false;
  // One line naming the clamped rings' flat radii, the shrink they needed and the height the
  // clamped tile reaches; empty when nothing is clamped.
  std::string warning;
  double target_height_mm = 0;   // the profile's height
  double clamped_height_mm = 0;  // apex to rim of the forward model of the printed shrink
  int horizontal_steps = 0;      // of that forward model (ForwardProfile)
};
// Judges `rings` (from tile_ring_shrinkage on `profile`). The clamped height comes from the forward
// model of the printed shrink, extended from the outermost ring to the rim at the profile's length
// with the rim's own shrink clamped. Throws UserError(kInfeasible) when no ring is printable as
// wanted, or when `strict` and some ring is clamped, saying what to change.
PrintabilityReport printability(const TileProfile& profile, const RingShrinkage& rings,
                                bool strict);

// Polygonal tiles (CHI 2019 §7, note A10): the printed shrink of the circular design tile
// (`circle`, flat radius `circle_radius` mm) at normalised depth `depth_fraction` = d / d_max ∈ [0,
// 1] (0 on the outline, 1 at the polygon's deepest point), i.e. at flat radius r = (1 − d/d_max)·R
// of the circle, by linear interpolation between its rings (constant beyond the innermost and
// outermost ring). A circle's own rings (d_max = R) get back exactly their shrink.
double polygon_ring_shrinkage(const RingShrinkage& circle, double circle_radius,
                              double depth_fraction);

// The paper's mapping ("paper mode"): ring j = 1 … N′ of a polygon counted from the centre gets
// Sh(Floor(j·N/N′)) of the circle's N rings counted from the centre (index clamped to ≥ 1, note
// A10). Returns the N′ printed shrinks, innermost first.
Eigen::VectorXd paper_polygon_shrinkage(const RingShrinkage& circle, int polygon_rings);

}  // namespace flatmorph
