#include "methods/tiles/tile_passes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace flatmorph {
namespace {

// Everything one tile prints in one pass (or one lattice layer), and where it meets its
// neighbours: the nozzle height at its outermost ring.
struct PassGroup {
  std::vector<PathPolyline> paths;
  double key = 0;
  int pass = 0;  // 1-based; lattice layers are numbered apart (negative)
};

double lerp(double a, double b, double t) { return a + (b - a) * t; }

// z (or the layer height) at a fractional ring level c of pass p, between the levels around it.
template <typename F>
double at_level(const TileLevels& tile, double c, F&& value) {
  const int last = static_cast<int>(tile.levels.size()) - 1;
  const double clamped = std::clamp(c, 0.0, static_cast<double>(last));
  const int m = std::min(static_cast<int>(std::floor(clamped)), last);
  const int next = std::min(m + 1, last);
  return lerp(value(tile.levels[m]), value(tile.levels[next]), clamped - m);
}

PathPolyline to_polyline(const RingPath& path, const TileLevels& tile, int pass,
                         const TilePassOptions& options) {
  PathPolyline out;
  out.type = PathType::kPerimeter;
  const Eigen::Index n = path.points.rows();
  out.points.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    out.points(i, 0) = path.points(i, 0);
    out.points(i, 1) = path.points(i, 1);
    out.points(i, 2) = at_level(tile, path.ring_coordinate(i),
                                [pass](const RingLevel& l) { return l.pass_z(pass); });
  }
  out.segments.resize(n > 0 ? n - 1 : 0);
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    SegmentStyle& s = out.segments[i];
    s.width = options.pitch;
    s.feed_rate = options.feed_rate;
    s.layer_height = at_level(
        tile, 0.5 * (path.ring_coordinate(i) + path.ring_coordinate(i + 1)),
        [pass](const RingLevel& l) { return l.pass_layer_height(std::min(pass, l.layers())); });
  }
  return out;
}

// Splits `piece` (ring indices, outer to inner, one ring per level) into runs along which the
// nozzle height does not turn back by more than kTurnBack, each oriented to climb. A dip of a few
// micrometres (per-ring bilayers of slightly different heights) ploughs nothing: the replay's
// tolerance is min(0.25 t, 0.02) mm.
constexpr double kTurnBack = 0.01;  // mm

std::vector<std::vector<int>> climbing_runs(const std::vector<int>& piece,
                                            const std::vector<double>& z) {
  std::vector<std::vector<int>> runs;
  size_t start = 0;
  while (start < piece.size()) {
    size_t end = start + 1;
    int direction = 0;  // +1 rising inward, −1 falling
    double low = z[start], high = z[start];
    while (end < piece.size()) {
      if (direction == 0) {
        if (z[end] > low + kTurnBack) direction = +1;
        if (z[end] < high - kTurnBack) direction = -1;
      } else if ((direction > 0 && z[end] < high - kTurnBack) ||
                 (direction < 0 && z[end] > low + kTurnBack)) {
        break;
      }
      low = std::min(low, z[end]);
      high = std::max(high, z[end]);
      ++end;
    }
    std::vector<int> run(piece.begin() + start, piece.begin() + end);
    if (direction < 0) std::reverse(run.begin(), run.end());
    runs.push_back(std::move(run));
    start = end;
  }
  return runs;
}

PassGroup tile_pass(const TileRings& rings, const std::vector<std::vector<int>>& chains,
                    const TileLevels& tile, int pass, const TilePassOptions& options,
                    int& num_paths) {
  PassGroup group;
  group.pass = pass;
  group.key = std::numeric_limits<double>::infinity();
  int outermost = std::numeric_limits<int>::max();
  struct Run {
    std::vector<int> sequence;
    double min_z;
  };
  std::vector<Run> runs;
  for (const std::vector<int>& chain : chains) {
    std::vector<int> piece;
    std::vector<double> z;
    auto flush = [&] {
      for (std::vector<int>& run : climbing_runs(piece, z)) {
        double min_z = std::numeric_limits<double>::infinity();
        for (int r : run) min_z = std::min(min_z, tile.levels[rings.rings[r].level].pass_z(pass));
        runs.push_back({std::move(run), min_z});
      }
      piece.clear();
      z.clear();
    };
    for (int r : chain) {
      const RingLevel& level = tile.levels[rings.rings[r].level];
      if (!level.printed || level.layers() < pass) {
        flush();
        continue;
      }
      piece.push_back(r);
      z.push_back(level.pass_z(pass));
      if (rings.rings[r].level < outermost) {
        outermost = rings.rings[r].level;
        group.key = level.pass_z(pass);
      }
    }
    flush();
  }
  // Lower runs first: a run ends where the next one's rings are at least as high.
  std::stable_sort(runs.begin(), runs.end(),
                   [](const Run& a, const Run& b) { return a.min_z < b.min_z; });
  JoinOptions join;
  join.seam = std::fmod((pass - 1) * options.seam_step, 1.0);
  for (const Run& run : runs) {
    group.paths.push_back(to_polyline(join_rings(rings, run.sequence, join), tile, pass, options));
  }
  num_paths = static_cast<int>(runs.size());
  return group;
}

}  // namespace

TilesToolpath tiles_toolpath(const std::vector<TileRings>& rings,
                             const std::vector<TileLevels>& levels,
                             const std::vector<LatticePass>& lattice,
                             const TilePassOptions& options) {
  if (rings.size() != levels.size()) {
    throw std::invalid_argument("tiles_toolpath: one set of levels per tile");
  }
  TilesToolpath out;
  std::vector<std::vector<PassGroup>> queues;
  out.paths_per_pass.resize(rings.size());
  for (size_t t = 0; t < rings.size(); ++t) {
    const std::vector<std::vector<int>> chains = ring_chains(rings[t]);
    int passes = 0;
    for (const RingLevel& level : levels[t].levels) {
      if (level.printed) passes = std::max(passes, level.layers());
    }
    std::vector<PassGroup> queue;
    for (int p = 1; p <= passes; ++p) {
      int num_paths = 0;
      PassGroup group = tile_pass(rings[t], chains, levels[t], p, options, num_paths);
      out.paths_per_pass[t].push_back(num_paths);
      if (!group.paths.empty()) queue.push_back(std::move(group));
    }
    queues.push_back(std::move(queue));
  }
  std::vector<PassGroup> lattice_queue;
  for (size_t l = 0; l < lattice.size(); ++l) {
    if (lattice[l].lines.empty()) continue;
    lattice_queue.push_back({lattice[l].lines, lattice[l].z, -1 - static_cast<int>(l)});
  }
  queues.push_back(std::move(lattice_queue));

  // Interleave: always the lowest next group, each queue in its own order.
  std::vector<size_t> next(queues.size(), 0);
  int current_pass = 0;
  out.min_layer_height = std::numeric_limits<double>::infinity();
  out.max_layer_height = 0;
  while (true) {
    int best = -1;
    for (size_t q = 0; q < queues.size(); ++q) {
      if (next[q] >= queues[q].size()) continue;
      if (best < 0 || queues[q][next[q]].key < queues[best][next[best]].key - 1e-9) {
        best = static_cast<int>(q);
      }
    }
    if (best < 0) break;
    PassGroup& group = queues[best][next[best]++];
    if (out.toolpath.layers.empty() || group.pass != current_pass) {
      out.toolpath.layers.emplace_back();
      current_pass = group.pass;
    }
    ToolpathLayer& layer = out.toolpath.layers.back();
    for (PathPolyline& path : group.paths) {
      for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
        layer.z = std::max(layer.z, path.points(i, 2));
      }
      for (size_t s = 0; s < path.segments.size(); ++s) {
        const SegmentStyle& style = path.segments[s];
        if (style.travel) continue;
        out.min_layer_height = std::min(out.min_layer_height, style.layer_height);
        out.max_layer_height = std::max(out.max_layer_height, style.layer_height);
        layer.height = std::max(layer.height, style.layer_height);
        out.path_length +=
            (path.points.row(static_cast<Eigen::Index>(s) + 1) - path.points.row(s)).norm();
      }
      layer.paths.push_back(std::move(path));
    }
  }
  if (out.toolpath.layers.empty()) out.min_layer_height = 0;
  return out;
}

}  // namespace flatmorph
