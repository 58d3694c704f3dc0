#include "gcode/bead_collision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace flatmorph::testing {
namespace {

constexpr double kNoBead = -std::numeric_limits<double>::infinity();
constexpr int kChunk = 64;             // cells per side of a stored block of the height map
constexpr double kDefaultWidth = 0.4;  // mm: a bead without ;WIDTH:
// mm: long moves are checked and laid in pieces this long, so that a diagonal move does not
// visit its whole bounding box.
constexpr double kPieceLength = 1.0;

// Bead tops on a raster of square cells (cell centres at x0 + (i + 1/2) cell), stored in blocks
// allocated where something is printed.
struct HeightMap {
  double x0 = 0, y0 = 0, cell = 1;
  int nx = 0, ny = 0, blocks_x = 0;
  std::vector<std::unique_ptr<std::vector<double>>> blocks;

  double top(int i, int j) const {
    const auto& block = blocks[(j / kChunk) * blocks_x + i / kChunk];
    return block ? (*block)[(j % kChunk) * kChunk + i % kChunk] : kNoBead;
  }
  void raise(int i, int j, double z) {
    auto& block = blocks[(j / kChunk) * blocks_x + i / kChunk];
    if (!block) block = std::make_unique<std::vector<double>>(kChunk * kChunk, kNoBead);
    double& t = (*block)[(j % kChunk) * kChunk + i % kChunk];
    t = std::max(t, z);
  }
  // Cells whose centres lie in [lo, hi] along x (or y).
  int first_i(double lo) const { return std::max(0, index(std::ceil((lo - x0) / cell - 0.5))); }
  int last_i(double hi) const {
    return std::min(nx - 1, index(std::floor((hi - x0) / cell - 0.5)));
  }
  int first_j(double lo) const { return std::max(0, index(std::ceil((lo - y0) / cell - 0.5))); }
  int last_j(double hi) const {
    return std::min(ny - 1, index(std::floor((hi - y0) / cell - 0.5)));
  }
  static int index(double v) { return static_cast<int>(std::clamp(v, -1.0, 1e9)); }
  double cx(int i) const { return x0 + (i + 0.5) * cell; }
  double cy(int j) const { return y0 + (j + 0.5) * cell; }
};

// A straight stretch of the nozzle axis, its height linear along it.
struct Piece {
  double ax, ay, az, bx, by, bz;
};

struct Worst {
  double depth = 0;  // how far the tip is below the bead top, beyond the tolerance
  double x = 0, y = 0, nozzle_z = 0, bead_top = 0;
  bool found = false;
};

bool usable(const ReadExtrusion& e) {
  return std::isfinite(e.x0) && std::isfinite(e.y0) && std::isfinite(e.x1) && std::isfinite(e.y1) &&
         std::isfinite(e.z);
}

// The tip (radius r around the axis) over each cell: the axis is within r of the cell's centre
// for t in an interval of the piece, and z is linear in t, so the lowest the tip gets over that
// cell is at one end of the interval. Exact; the limit of sampling the move ever more finely.
void check(const HeightMap& map, const Piece& p, double r, double tolerance, Worst& worst) {
  const double dx = p.bx - p.ax, dy = p.by - p.ay;
  const double a = dx * dx + dy * dy;
  const double lowest = std::min(p.az, p.bz);
  for (int j = map.first_j(std::min(p.ay, p.by) - r); j <= map.last_j(std::max(p.ay, p.by) + r);
       ++j) {
    for (int i = map.first_i(std::min(p.ax, p.bx) - r); i <= map.last_i(std::max(p.ax, p.bx) + r);
         ++i) {
      const double top = map.top(i, j);
      if (top <= lowest + tolerance) continue;
      const double ex = p.ax - map.cx(i), ey = p.ay - map.cy(j);
      const double b = ex * dx + ey * dy, c = ex * ex + ey * ey - r * r;
      double t0 = 0, t1 = 1;
      if (a == 0) {
        if (c > 0) continue;
      } else {
        const double disc = b * b - a * c;
        if (disc < 0) continue;
        t0 = std::max(0.0, (-b - std::sqrt(disc)) / a);
        t1 = std::min(1.0, (-b + std::sqrt(disc)) / a);
        if (t0 > t1) continue;
      }
      const double z0 = p.az + t0 * (p.bz - p.az), z1 = p.az + t1 * (p.bz - p.az);
      const double t = z0 <= z1 ? t0 : t1;
      const double z = std::min(z0, z1);
      const double depth = top - z - tolerance;
      if (depth > 0 && depth > worst.depth) {
        worst = {depth, p.ax + t * dx, p.ay + t * dy, z, top, true};
      }
    }
  }
}

// The bead: cells within half the width of the axis get the nozzle's height at their nearest
// point of it (the nozzle flattens the bead's top to its own height).
void deposit(HeightMap& map, const Piece& p, double half_width) {
  const double dx = p.bx - p.ax, dy = p.by - p.ay;
  const double a = dx * dx + dy * dy;
  const double h = half_width;
  for (int j = map.first_j(std::min(p.ay, p.by) - h); j <= map.last_j(std::max(p.ay, p.by) + h);
       ++j) {
    for (int i = map.first_i(std::min(p.ax, p.bx) - h); i <= map.last_i(std::max(p.ax, p.bx) + h);
         ++i) {
      const double ex = map.cx(i) - p.ax, ey = map.cy(j) - p.ay;
      const double t = a == 0 ? 0 : std::clamp((ex * dx + ey * dy) / a, 0.0, 1.0);
      const double qx = ex - t * dx, qy = ey - t * dy;
      if (qx * qx + qy * qy > h * h) continue;
      map.raise(i, j, p.az + t * (p.bz - p.az));
    }
  }
}

}  // namespace

std::vector<BeadCollision> replay_collisions(const ReadGcode& gcode,
                                             const CollisionOptions& options) {
  if (!(options.cell > 0) || !(options.tip_diameter >= 0)) {
    throw std::invalid_argument("replay_collisions: cell must be > 0 and tip_diameter >= 0");
  }
  const double r = options.tip_diameter / 2;

  // The map covers every extrusion with room for the tip and the widest bead.
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300, reach = r;
  for (const ReadLayer& layer : gcode.layers) {
    for (const ReadExtrusion& e : layer.extrusions) {
      if (!usable(e)) continue;
      min_x = std::min({min_x, e.x0, e.x1});
      max_x = std::max({max_x, e.x0, e.x1});
      min_y = std::min({min_y, e.y0, e.y1});
      max_y = std::max({max_y, e.y0, e.y1});
      reach = std::max(reach, (e.width > 0 ? e.width : kDefaultWidth) / 2);
    }
  }
  if (min_x > max_x) return {};
  HeightMap map;
  map.cell = options.cell;
  const double margin = reach + 2 * options.cell;
  map.x0 = min_x - margin;
  map.y0 = min_y - margin;
  map.nx = static_cast<int>(std::ceil((max_x - min_x + 2 * margin) / options.cell)) + 1;
  map.ny = static_cast<int>(std::ceil((max_y - min_y + 2 * margin) / options.cell)) + 1;
  map.blocks_x = (map.nx + kChunk - 1) / kChunk;
  map.blocks.resize(static_cast<size_t>(map.blocks_x) * ((map.ny + kChunk - 1) / kChunk));

  // Each move is checked before its own bead is laid, so it never meets itself. Its earlier
  // neighbours along the same path do count: a path that rises (note §4.6 rule 1) only passes
  // over its own beads at or below its current height, since a bead's top is the height the
  // nozzle had there, so it is never flagged; a path that descends by more than the tolerance
  // within the tip's radius of its own bead is, because the trailing half of the tip does drag
  // through that bead. The tolerance also absorbs Z rounded to the G-code's decimals.
  std::vector<BeadCollision> found;
  std::vector<Piece> pieces;
  for (size_t l = 0; l < gcode.layers.size(); ++l) {
    const std::vector<ReadExtrusion>& extrusions = gcode.layers[l].extrusions;
    for (size_t k = 0; k < extrusions.size(); ++k) {
      const ReadExtrusion& e = extrusions[k];
      if (!usable(e)) continue;
      const double z0 = std::isfinite(e.z0) ? e.z0 : e.z;
      const double tolerance = options.tolerance >= 0
                                   ? options.tolerance
                                   : (e.height > 0 ? std::min(0.25 * e.height, 0.02) : 0.02);
      const double length = std::hypot(e.x1 - e.x0, e.y1 - e.y0);
      const int n = std::max(1, static_cast<int>(std::ceil(length / kPieceLength)));
      pieces.clear();
      for (int i = 0; i < n; ++i) {
        const double s = static_cast<double>(i) / n, u = static_cast<double>(i + 1) / n;
        pieces.push_back({e.x0 + s * (e.x1 - e.x0), e.y0 + s * (e.y1 - e.y0), z0 + s * (e.z - z0),
                          e.x0 + u * (e.x1 - e.x0), e.y0 + u * (e.y1 - e.y0), z0 + u * (e.z - z0)});
      }
      Worst worst;
      for (const Piece& p : pieces) check(map, p, r, tolerance, worst);
      if (worst.found) {
        found.push_back({static_cast<int>(l), k, worst.x, worst.y, worst.nozzle_z, worst.bead_top});
      }
      const double half_width = (e.width > 0 ? e.width : kDefaultWidth) / 2;
      for (const Piece& p : pieces) deposit(map, p, half_width);
    }
  }
  return found;
}

}  // namespace flatmorph::testing
