#include "methods/tiles/tile_levels.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "material/thickness_curve.h"

namespace flatmorph {
namespace {

// Floor(total / t) layers (CHI 2019 §3), at least one; the 1e-9 keeps 0.3 / 0.1 from giving 2
// (notes §2.3: in doubles it is 2.999...).
int layer_count(double total, double layer_height) {
  return std::max(1, static_cast<int>(std::floor(total / layer_height + 1e-9)));
}

// The two halves of the bilayer around `shrinkage`: the bed side shrinks side·δ/2 more, the top
// side·δ/2 less; near an end of the range the pair is shifted to stay inside it (the mean moves,
// the difference is kept while the range allows).
void split_bilayer(RingLevel& level, int side, double least, double most,
                   const ThicknessCurve& curve, double half) {
  const double difference = level.bilayer_difference;
  double bed = level.shrinkage + side * difference / 2;
  double top = level.shrinkage - side * difference / 2;
  const double low = std::min(bed, top), high = std::max(bed, top);
  double shift = 0;
  if (low < least) shift = least - low;
  if (high + shift > most) shift = most - high;
  bed = std::clamp(bed + shift, least, most);
  top = std::clamp(top + shift, least, most);
  level.bed_shrinkage = bed;
  level.top_shrinkage = top;
  level.bed_layer_height = layer_height_for_shrinkage(curve, bed);
  level.top_layer_height = layer_height_for_shrinkage(curve, top);
  // Floor(total / t) layers in all (CHI 2019 §3), t the halves' mean, shared between the halves
  // (the bed side takes the odd one): halving first would floor twice and print 2 layers of 0.16 mm
  // where the paper prints 3.
  const int layers =
      std::max(2, layer_count(2 * half, 0.5 * (level.bed_layer_height + level.top_layer_height)));
  level.top_layers = layers / 2;
  level.bed_layers = layers - level.top_layers;
  // What the ring prints: the halves' shrink weighted by their thickness (near an end of the range
  // the pair was shifted, and the mean with it).
  const double bed_thickness = level.bed_layers * level.bed_layer_height;
  const double top_thickness = level.top_layers * level.top_layer_height;
  level.shrinkage = (bed_thickness * bed + top_thickness * top) / (bed_thickness + top_thickness);
}

void fill_halves(TileLevels& tile, const Material& material, const RingLevelOptions& options) {
  const ThicknessCurve& curve = require_thickness_curve(material);
  const auto [least, most] = reachable_shrinkage(curve);
  for (RingLevel& level : tile.levels) {
    split_bilayer(level, tile.side, least, most, curve, options.sheet_thickness / 2);
  }
}

// The automatic δ's range: one point keeps the side chosen where the surface is nearly flat, six
// keep the halves' layer heights apart within the curve near a sharp apex.
constexpr double kLeastBilayer = 0.01;
constexpr double kMostBilayer = 0.06;

void check_options(const RingLevelOptions& options) {
  if (!(options.pitch > 0) || !(options.sheet_thickness > 0) ||
      !(options.bilayer_difference >= 0) || !(options.bilayer_difference < 0.5)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("ring levels: pitch {} mm and sheet thickness {} mm must be above "
                    "0 and the bilayer difference {} within [0, 0.5)",
                    options.pitch, options.sheet_thickness, options.bilayer_difference));
  }
}

}  // namespace

double RingLevel::pass_z(int pass) const {
  if (pass <= bed_layers) return pass * bed_layer_height;
  return bed_layers * bed_layer_height + (pass - bed_layers) * top_layer_height;
}

double RingLevel::pass_layer_height(int pass) const {
  return pass <= bed_layers ? bed_layer_height : top_layer_height;
}

TileLevels tile_levels(const TileProfile& profile, double design_radius, int num_levels, int side,
                       double hole_radius, const Material& material,
                       const RingLevelOptions& options) {
  check_options(options);
  const ThicknessCurve& curve = require_thickness_curve(material);
  const auto [least, most] = reachable_shrinkage(curve);
  if (num_levels < 1 || !(design_radius > 0)) {
    throw std::invalid_argument("tile_levels: no ring level or a tile radius that is not positive");
  }
  TileLevels tile;
  tile.design_radius = design_radius;
  tile.side = side >= 0 ? +1 : -1;
  Eigen::VectorXd radii(num_levels);
  for (int m = 0; m < num_levels; ++m) {
    // A ring can lie as deep as the tile's largest depth (a polygon's innermost ones): kept at a
    // small positive radius, distinct from its neighbours'.
    radii(m) = std::max(design_radius - (m + 0.5) * options.pitch, 1e-3 * (num_levels - m));
  }
  const RingShrinkage rings = tile_ring_shrinkage(profile, radii, least, most);
  tile.levels.resize(num_levels);
  for (int m = 0; m < num_levels; ++m) {
    RingLevel& level = tile.levels[m];
    level.depth = (m + 0.5) * options.pitch;
    level.flat_radius = radii(m);
    level.wanted = rings.wanted(m);
    level.shrinkage = rings.printed(m);
    level.clamped = rings.clamped(m);
    level.printed = radii(m) >= hole_radius;
  }
  tile.printability = printability(profile, rings, options.strict);
  const double length = profile_length(profile);
  for (RingLevel& level : tile.levels) {
    if (options.bilayer_difference > 0) {
      level.bilayer_difference = options.bilayer_difference;
      continue;
    }
    // The parallel's normal curvature sin α / ρ at the ring's arc length, α from a central
    // difference along the meridian.
    const double s = std::clamp(level.flat_radius, 0.0, length);
    const double ds = std::min(0.05, 0.25 * options.pitch);
    const Eigen::Vector2d a = profile_point_at_length(profile, std::max(0.0, s - ds));
    const Eigen::Vector2d b = profile_point_at_length(profile, std::min(length, s + ds));
    const double sin_slope = std::abs(b.y() - a.y()) / std::max((b - a).norm(), 1e-12);
    const double rho = profile_point_at_length(profile, s).x();
    const double curvature = sin_slope / std::max(rho, options.pitch);
    level.bilayer_difference =
        std::clamp(2.0 / 3.0 * curvature * options.sheet_thickness, kLeastBilayer, kMostBilayer);
  }
  fill_halves(tile, material, options);
  return tile;
}

void set_level_shrinkage(TileLevels& tile, const Eigen::VectorXd& shrinkage,
                         const Material& material, const RingLevelOptions& options) {
  if (shrinkage.size() != static_cast<Eigen::Index>(tile.levels.size())) {
    throw std::invalid_argument("set_level_shrinkage: one shrink per level");
  }
  const auto [least, most] = reachable_shrinkage(require_thickness_curve(material));
  for (size_t m = 0; m < tile.levels.size(); ++m) {
    RingLevel& level = tile.levels[m];
    level.shrinkage = std::clamp(shrinkage(static_cast<Eigen::Index>(m)), least, most);
    level.clamped = shrinkage(m) < least ? -1 : shrinkage(m) > most ? +1 : 0;
  }
  fill_halves(tile, material, options);
}

}  // namespace flatmorph
