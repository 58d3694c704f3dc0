#include "gcode/deposited_plate.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/angles.h"
#include "common/error.h"
#include "material/material.h"
#include "mesh/topology.h"

namespace flatmorph {
namespace {

// Rasterizing a long diagonal bead over its bounding box would test length² / 2 of lattice area
// for length × width of bead: pieces of at most this length (mm) keep the two close.
constexpr double kMaxPieceLength = 2.0;

bool is_part(const DepositedBead& bead, const DepositedPlateOptions& options) {
  if (!options.skip_non_part || bead.type.empty()) return true;
  std::string type = bead.type;
  std::transform(type.begin(), type.end(), type.begin(), ::tolower);
  for (const char* word : {"skirt", "brim", "wipe", "prime", "purge", "flush"}) {
    if (type.find(word) != std::string::npos) return false;
  }
  return true;
}

std::vector<const DepositedBead*> part_beads(const GcodeDeposition& deposition,
                                             const DepositedPlateOptions& options) {
  std::vector<const DepositedBead*> beads;
  for (const DepositedBead& bead : deposition.beads) {
    if (is_part(bead, options) && bead.width > 0 && bead.height > 0 &&
        (bead.end - bead.start).head<2>().squaredNorm() > 0) {
      beads.push_back(&bead);
    }
  }
  return beads;
}

// Samples of each face at the centroids of its m x m sub-triangles (m from the face's longest
// edge and the spacing): equal areas, so counts are areas, and fixed to the face, so a turned or
// mirrored plate printed by the turned or mirrored file is sampled at the turned points.
struct Samples {
  std::vector<Eigen::Vector2d> point;
  std::vector<int> face;
  std::vector<int> face_count;  // samples per face
};

Samples sample_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double spacing) {
  Samples s;
  s.face_count.assign(F.rows(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector2d a = V.row(F(f, 0)).head<2>(), b = V.row(F(f, 1)).head<2>(),
                          c = V.row(F(f, 2)).head<2>();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int m = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, 64);
    auto add = [&](double u, double v) {
      s.point.push_back(a + u / m * (b - a) + v / m * (c - a));
      s.face.push_back(static_cast<int>(f));
    };
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        add(i + 1.0 / 3, j + 1.0 / 3);
        if (i + j < m - 1) add(i + 2.0 / 3, j + 2.0 / 3);
      }
    }
    s.face_count[f] = m * m;
  }
  return s;
}

// Samples bucketed on a square grid, for the beads' range queries.
struct Buckets {
  Eigen::Vector2d origin;
  double size = 1;
  long nx = 0, ny = 0;
  std::vector<int> start;  // CSR: samples of bucket b are index[start[b] .. start[b + 1])
  std::vector<int> index;

  long bucket_x(double x) const {
    return std::clamp(static_cast<long>(std::floor((x - origin.x()) / size)), 0L, nx - 1);
  }
  long bucket_y(double y) const {
    return std::clamp(static_cast<long>(std::floor((y - origin.y()) / size)), 0L, ny - 1);
  }
};

Buckets bucket_samples(const std::vector<Eigen::Vector2d>& points, double size) {
  Buckets b;
  b.size = size;
  Eigen::Vector2d lo = points.front(), hi = points.front();
  for (const Eigen::Vector2d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  b.origin = lo;
  b.nx = static_cast<long>(std::floor((hi.x() - lo.x()) / size)) + 1;
  b.ny = static_cast<long>(std::floor((hi.y() - lo.y()) / size)) + 1;
  std::vector<int> count(b.nx * b.ny + 1, 0);
  std::vector<long> of(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    of[i] = b.bucket_y(points[i].y()) * b.nx + b.bucket_x(points[i].x());
    ++count[of[i] + 1];
  }
  for (size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  b.start = count;
  b.index.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) b.index[count[of[i]]++] = static_cast<int>(i);
  return b;
}

// The part's beads of the lowest layer that has any.
std::vector<const DepositedBead*> first_layer_beads(const GcodeDeposition& deposition,
                                                    const DepositedPlateOptions& options) {
  std::vector<const DepositedBead*> beads = part_beads(deposition, options);
  int first = deposition.num_layers;
  for (const DepositedBead* bead : beads) first = std::min(first, bead->layer);
  std::erase_if(beads, [&](const DepositedBead* b) { return b->layer != first; });
  return beads;
}

double median_width(const std::vector<const DepositedBead*>& beads) {
  std::vector<double> widths;
  widths.reserve(beads.size());
  for (const DepositedBead* bead : beads) widths.push_back(bead->width);
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  return widths[widths.size() / 2];
}

// Calls visit(sample, t) for every sample within half the bead's width of its axis (t in [0, 1]
// along it), once per sample.
template <typename Visit>
void for_samples_under(const DepositedBead& bead, const Samples& samples, const Buckets& buckets,
                       std::vector<int>& stamp, int bead_id, Visit visit) {
  const Eigen::Vector2d a = bead.start.head<2>(), b = bead.end.head<2>();
  const double length = (b - a).norm();
  // Beads laid at their width apart touch: a sample on the line between them is under both, not
  // between them, whatever the rounding of its distance or of an arc's chords (0.005 mm off the
  // arc: gcode_reader.h). Molten beads spread that much.
  const double r = bead.width / 2 * 1.02;
  const int pieces = std::max(1, static_cast<int>(std::ceil(length / kMaxPieceLength)));
  for (int piece = 0; piece < pieces; ++piece) {
    const Eigen::Vector2d p0 = a + (b - a) * (double(piece) / pieces);
    const Eigen::Vector2d p1 = a + (b - a) * (double(piece + 1) / pieces);
    const Eigen::Vector2d lo = p0.cwiseMin(p1).array() - r, hi = p0.cwiseMax(p1).array() + r;
    const long bx0 = buckets.bucket_x(lo.x()), bx1 = buckets.bucket_x(hi.x());
    const long by0 = buckets.bucket_y(lo.y()), by1 = buckets.bucket_y(hi.y());
    for (long by = by0; by <= by1; ++by) {
      for (long bx = bx0; bx <= bx1; ++bx) {
        const long bucket = by * buckets.nx + bx;
        for (int k = buckets.start[bucket]; k < buckets.start[bucket + 1]; ++k) {
          const int i = buckets.index[k];
          if (stamp[i] == bead_id) continue;
          const Eigen::Vector2d& p = samples.point[i];
          const double t = std::clamp((p - a).dot(b - a) / (length * length), 0.0, 1.0);
          if ((a + t * (b - a) - p).squaredNorm() > r * r) continue;
          stamp[i] = bead_id;
          visit(i, t);
        }
      }
    }
  }
}

}  // namespace

std::vector<DepositedLayer> rasterize_deposition(const GcodeDeposition& deposition,
                                                 const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                 const DepositedPlateOptions& options) {
  const std::vector<const DepositedBead*> beads = part_beads(deposition, options);
  const Eigen::Index num_faces = F.rows();
  std::vector<DepositedLayer> layers(deposition.num_layers);
  for (DepositedLayer& layer : layers) {
    layer.coverage = Eigen::VectorXd::Zero(num_faces);
    layer.theta = Eigen::VectorXd::Zero(num_faces);
    layer.thickness = Eigen::VectorXd::Zero(num_faces);
    layer.tool = Eigen::VectorXi::Constant(num_faces, -1);
    layer.feed_rate = Eigen::VectorXd::Zero(num_faces);
  }
  if (beads.empty() || num_faces == 0) return layers;

  // A third of the typical bead width resolves each bead by about three samples across, and the
  // direction and coverage of a face by several beads; no more than about 4 million samples
  double area = 0;
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    const Eigen::Vector2d a = V.row(F(f, 0)).head<2>(), b = V.row(F(f, 1)).head<2>(),
                          c = V.row(F(f, 2)).head<2>();
    area += std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / 2;
  }
  const double spacing = std::max(median_width(beads) / 3, std::sqrt(area / 4e6));
  const Samples samples = sample_faces(V, F, spacing);
  const Buckets buckets = bucket_samples(samples.point, std::max(1.0, 4 * spacing));
  const size_t n = samples.point.size();

  std::vector<double> below(n, 0.0);  // top of what lies under each sample, mm (the bed: 0)
  std::vector<int> stamp(n, -1);
  std::vector<int> covered(n);
  std::vector<double> cos2(n), sin2(n), top(n), top_height(n), feed(n);
  std::vector<int> tool(n);
  size_t next = 0;
  int bead_id = 0;
  for (int k = 0; k < deposition.num_layers; ++k) {
    std::fill(covered.begin(), covered.end(), 0);
    std::fill(cos2.begin(), cos2.end(), 0.0);
    std::fill(sin2.begin(), sin2.end(), 0.0);
    std::fill(top.begin(), top.end(), -INFINITY);
    std::fill(feed.begin(), feed.end(), 0.0);
    std::fill(tool.begin(), tool.end(), -1);
    // Beads come in file order, and so in layer order.
    for (; next < beads.size() && beads[next]->layer <= k; ++next) {
      const DepositedBead& bead = *beads[next];
      if (bead.layer < k) continue;
      const Eigen::Vector2d d = (bead.end - bead.start).head<2>();
      const double angle = 2 * std::atan2(d.y(), d.x());
      const double c = std::cos(angle) * bead.height, s = std::sin(angle) * bead.height;
      for_samples_under(bead, samples, buckets, stamp, bead_id++, [&](int i, double t) {
        const double z = bead.start.z() + t * (bead.end.z() - bead.start.z());
        ++covered[i];
        cos2[i] += c;
        sin2[i] += s;
        feed[i] += bead.feed_rate;
        if (z > top[i]) {
          top[i] = z;
          top_height[i] = bead.height;
          tool[i] = bead.tool;
        }
      });
    }
    DepositedLayer& layer = layers[k];
    Eigen::VectorXd sum_cos = Eigen::VectorXd::Zero(num_faces), sum_sin = sum_cos;
    Eigen::VectorXi samples_covered = Eigen::VectorXi::Zero(num_faces);
    std::vector<std::map<int, int>> tool_count(num_faces);
    for (size_t i = 0; i < n; ++i) {
      if (covered[i] == 0) continue;
      // A bead fills down to what lies below it, but no deeper than its own height: laid over a
      // gap (a lattice's second family between the first's lines) it keeps its volume.
      const double thickness = std::min(top[i] - below[i], top_height[i]);
      if (!(thickness > 0)) continue;  // ironing over what is there deposits nothing measurable
      below[i] = top[i];
      const int f = samples.face[i];
      ++samples_covered(f);
      layer.thickness(f) += thickness;
      sum_cos(f) += cos2[i];
      sum_sin(f) += sin2[i];
      layer.feed_rate(f) += feed[i] / covered[i];
      ++tool_count[f][tool[i]];
    }
    for (Eigen::Index f = 0; f < num_faces; ++f) {
      if (samples_covered(f) == 0) continue;
      const int count = samples.face_count[f];
      layer.coverage(f) = double(samples_covered(f)) / count;
      layer.thickness(f) /= count;
      layer.feed_rate(f) /= samples_covered(f);
      layer.theta(f) = std::atan2(sum_sin(f), sum_cos(f)) / 2;
      int best = -1, best_count = 0;
      for (const auto& [t, c] : tool_count[f]) {
        if (c > best_count) best = t, best_count = c;
      }
      layer.tool(f) = best;
    }
  }
  return layers;
}

Eigen::AlignedBox2d first_layer_bounds(const GcodeDeposition& deposition,
                                       const DepositedPlateOptions& options) {
  Eigen::AlignedBox2d bounds;  // empty
  for (const DepositedBead* bead : first_layer_beads(deposition, options)) {
    const Eigen::Vector2d w = Eigen::Vector2d::Constant(bead->width / 2);
    bounds.extend(Eigen::Vector2d(bead->start.head<2>() - w));
    bounds.extend(Eigen::Vector2d(bead->end.head<2>() - w));
    bounds.extend(Eigen::Vector2d(bead->start.head<2>() + w));
    bounds.extend(Eigen::Vector2d(bead->end.head<2>() + w));
  }
  return bounds;
}

PartFrame first_layer_frame(const GcodeDeposition& deposition,
                            const DepositedPlateOptions& options) {
  const std::vector<const DepositedBead*> beads = first_layer_beads(deposition, options);
  PartFrame frame;
  // Each bead as its rectangle, length × width: its area, centroid and second moments in closed
  // form, so that the frame turns and moves with the beads exactly (no sampling on the bed).
  double area = 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const DepositedBead* bead : beads) {
    const double a = (bead->end - bead->start).head<2>().norm() * bead->width;
    area += a;
    centroid += a * (bead->start + bead->end).head<2>() / 2;
  }
  if (!(area > 0)) return frame;
  centroid /= area;
  // Σ ∫ (p − c)(p − c)ᵀ dA and, once the axis e is known, Σ ∫ (e · (p − c))³ dA.
  auto bead_frame = [](const DepositedBead& bead, Eigen::Vector2d& along, Eigen::Vector2d& across,
                       double& length) {
    const Eigen::Vector2d d = (bead.end - bead.start).head<2>();
    length = d.norm();
    along = d / length;
    across = Eigen::Vector2d(-along.y(), along.x());
  };
  Eigen::Matrix2d moment = Eigen::Matrix2d::Zero();
  for (const DepositedBead* bead : beads) {
    Eigen::Vector2d along, across;
    double length = 0;
    bead_frame(*bead, along, across, length);
    const double a = length * bead->width;
    const Eigen::Vector2d m = (bead->start + bead->end).head<2>() / 2 - centroid;
    moment += a * (m * m.transpose() + length * length / 12 * along * along.transpose() +
                   bead->width * bead->width / 12 * across * across.transpose());
  }
  double angle = std::atan2(2 * moment(0, 1), moment(0, 0) - moment(1, 1)) / 2;
  Eigen::Vector2d axis(std::cos(angle), std::sin(angle));
  double skew = 0;
  for (const DepositedBead* bead : beads) {
    Eigen::Vector2d along, across;
    double length = 0;
    bead_frame(*bead, along, across, length);
    const double u = axis.dot((bead->start + bead->end).head<2>() / 2 - centroid);
    const double s = axis.dot(along), t = axis.dot(across);
    skew += length * bead->width *
            (u * u * u + u * (s * s * length * length + t * t * bead->width * bead->width) / 4);
  }
  // The axis is a line; its sign follows the skew so that it turns with the part through any
  // angle. A part symmetric about its centre has no skew but rounding's, which would pick a side
  // at random between two files differing in rounding only: it points to +x (+y along the y axis)
  // instead, and a turned file may mesh it from the other end, the same mesh turned half a turn.
  const double spread = axis.dot(moment * axis) / area;  // mm²
  const bool skewed = std::abs(skew) > 1e-6 * area * spread * std::sqrt(spread);
  const bool backwards = skewed ? skew < 0 : axis.x() < -1e-9 || (axis.x() <= 1e-9 && axis.y() < 0);
  if (backwards) angle += angle > 0 ? -kPi : kPi;
  frame.origin = centroid;
  frame.angle = angle;
  return frame;
}

FootprintMesh footprint_plate(const GcodeDeposition& deposition, const std::string& source,
                              const DepositedPlateOptions& options) {
  if (!(options.resolution_mm > 0) || !std::isfinite(options.resolution_mm)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--resolution {}: give the plate mesh's edge length in mm (e.g. 1)",
                                options.resolution_mm));
  }
  const std::vector<const DepositedBead*> first = first_layer_beads(deposition, options);
  if (first.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no bead of the part to take the plate's footprint from; give "
                                "the plate mesh (--plate flat.ply)",
                                source));
  }
  // The lattice is laid in the part's own frame: a file turned or moved on the bed gives the same
  // mesh turned or moved. On the bed's axes a strip turned by 30° met the lattice in a staircase
  // and bent across its edges and diagonals, which a triangle mesh can only do by stretching: 2 to
  // 3 % less curvature, hundreds of times the membrane energy (docs/gcode.md).
  FootprintMesh mesh;
  mesh.frame = first_layer_frame(deposition, options);
  const Eigen::Rotation2Dd to_bed(mesh.frame.angle);
  const Eigen::Matrix2d to_part = to_bed.toRotationMatrix().transpose();
  std::vector<DepositedBead> beads;  // the first layer in the part's frame
  beads.reserve(first.size());
  Eigen::AlignedBox2d bounds;
  for (const DepositedBead* bead : first) {
    DepositedBead b = *bead;
    b.start.head<2>() = to_part * (bead->start.head<2>() - mesh.frame.origin);
    b.end.head<2>() = to_part * (bead->end.head<2>() - mesh.frame.origin);
    const Eigen::Vector2d w = Eigen::Vector2d::Constant(b.width / 2);
    for (const Eigen::Vector3d& p : {b.start, b.end}) {
      bounds.extend(Eigen::Vector2d(p.head<2>() - w));
      bounds.extend(Eigen::Vector2d(p.head<2>() + w));
    }
    beads.push_back(std::move(b));
  }
  // As many cells along each axis as fit the beads' extent at about the resolution, so that a
  // rectangular part is cells exactly and no face of its edge is partly printed.
  const double r = options.resolution_mm;
  const Eigen::Vector2d lo = bounds.min(), extent = bounds.sizes();
  const double cells_x = std::max(1.0, std::round(extent.x() / r));
  const double cells_y = std::max(1.0, std::round(extent.y() / r));
  if (cells_x * cells_y > 4e6) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--resolution {} mm: the footprint ({:.0f} x {:.0f} mm) would need "
                                "{:.0f} cells; give a coarser resolution",
                                r, extent.x(), extent.y(), cells_x * cells_y));
  }
  const long nx = static_cast<long>(cells_x), ny = static_cast<long>(cells_y);
  const Eigen::Vector2d cell(extent.x() / cells_x, extent.y() / cells_y);
  // A cell is in when beads cover at least half of it (4 x 4 samples): a polygonal ring leaves
  // slivers between its chords and the next ring, which single points would fall into as holes.
  constexpr int kSub = 4;
  Samples samples;
  samples.point.reserve(nx * ny * kSub * kSub);
  for (long j = 0; j < ny; ++j) {
    for (long i = 0; i < nx; ++i) {
      for (int b = 0; b < kSub; ++b) {
        for (int a = 0; a < kSub; ++a) {
          samples.point.emplace_back(lo.x() + (i + (a + 0.5) / kSub) * cell.x(),
                                     lo.y() + (j + (b + 0.5) / kSub) * cell.y());
        }
      }
    }
  }
  const Buckets buckets = bucket_samples(samples.point, std::max(1.0, r));
  std::vector<int> stamp(samples.point.size(), -1);
  std::vector<char> under(samples.point.size(), 0);
  int id = 0;
  for (const DepositedBead& bead : beads) {
    for_samples_under(bead, samples, buckets, stamp, id++, [&](int i, double) { under[i] = 1; });
  }
  std::vector<char> in(nx * ny, 0);
  for (long c = 0; c < nx * ny; ++c) {
    int count = 0;
    for (int k = 0; k < kSub * kSub; ++k) count += under[c * kSub * kSub + k];
    in[c] = 2 * count >= kSub * kSub;
  }
  std::vector<int> vertex((nx + 1) * (ny + 1), -1);
  std::vector<Eigen::Vector2d> points;
  auto corner = [&](long i, long j) {
    int& v = vertex[j * (nx + 1) + i];
    if (v < 0) {
      v = static_cast<int>(points.size());
      points.push_back(mesh.frame.origin +
                       to_bed * Eigen::Vector2d(lo.x() + i * cell.x(), lo.y() + j * cell.y()));
    }
    return v;
  };
  std::vector<Eigen::Vector3i> faces;
  for (long j = 0; j < ny; ++j) {
    for (long i = 0; i < nx; ++i) {
      if (!in[j * nx + i]) continue;
      const int a = corner(i, j), b = corner(i + 1, j), c = corner(i + 1, j + 1),
                d = corner(i, j + 1);
      // Diagonals alternate, so the mesh has no preferred diagonal direction.
      if ((i + j) % 2 == 0) {
        faces.emplace_back(a, b, c);
        faces.emplace_back(a, c, d);
      } else {
        faces.emplace_back(a, b, d);
        faces.emplace_back(b, c, d);
      }
    }
  }
  if (faces.empty()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: at --resolution {} mm the first layer covers no cell of "
                                "the plate's lattice by half; give a finer resolution",
                                source, r));
  }
  Eigen::MatrixXi F(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose();
  Eigen::VectorXi component;
  const int num_components = face_components(F, component);
  std::vector<int> size(num_components, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) ++size[component(f)];
  const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<int> new_index(points.size(), -1);
  std::vector<Eigen::Vector3i> kept;
  int num_vertices = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (component(f) != largest) continue;
    Eigen::Vector3i face;
    for (int c = 0; c < 3; ++c) {
      int& v = new_index[F(f, c)];
      if (v < 0) v = num_vertices++;
      face(c) = v;
    }
    kept.push_back(face);
  }
  mesh.V.resize(num_vertices, 2);
  for (size_t v = 0; v < points.size(); ++v) {
    if (new_index[v] >= 0) mesh.V.row(new_index[v]) = points[v].transpose();
  }
  mesh.F.resize(kept.size(), 3);
  for (size_t f = 0; f < kept.size(); ++f) mesh.F.row(f) = kept[f].transpose();
  return mesh;
}

DepositedPlate deposited_plate(const GcodeDeposition& deposition, const Eigen::MatrixXd& V,
                               const Eigen::MatrixXi& F,
                               const std::vector<Material>& tool_materials,
                               const std::string& source, const DepositedPlateOptions& options) {
  const std::vector<DepositedLayer> all = rasterize_deposition(deposition, V, F, options);
  const Eigen::Index num_faces = F.rows();
  auto covers = [&](const DepositedLayer& layer, Eigen::Index f) {
    return layer.tool(f) >= 0 && layer.coverage(f) >= options.min_coverage &&
           layer.thickness(f) > 0;
  };
  for (const DepositedLayer& layer : all) {
    for (Eigen::Index f = 0; f < num_faces; ++f) {
      if (covers(layer, f) && layer.tool(f) >= static_cast<int>(tool_materials.size())) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("{}: tool T{} prints on the plate but {} material(s) were "
                                    "given; name one per tool (--material A,B)",
                                    source, layer.tool(f), tool_materials.size()));
      }
    }
  }

  // Faces no layer covers leave the plate; of what remains the largest edge-connected piece is
  // the plate (a loose piece would float free in the simulation).
  std::vector<char> keep(num_faces, 0);
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    for (const DepositedLayer& layer : all) keep[f] = keep[f] || covers(layer, f);
  }
  std::vector<int> kept_faces;
  for (Eigen::Index f = 0; f < num_faces; ++f) {
    if (keep[f]) kept_faces.push_back(static_cast<int>(f));
  }
  int loose_faces = 0;
  if (kept_faces.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no bead of the file lies on the plate; check that the plate "
                                "mesh (--plate) is the one the file was printed from",
                                source));
  }
  {
    Eigen::MatrixXi sub(kept_faces.size(), 3);
    for (size_t i = 0; i < kept_faces.size(); ++i) sub.row(i) = F.row(kept_faces[i]);
    Eigen::VectorXi component;
    const int num_components = face_components(sub, component);
    std::vector<int> size(num_components, 0);
    for (Eigen::Index i = 0; i < sub.rows(); ++i) ++size[component(i)];
    const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
    std::vector<int> in_largest;
    for (size_t i = 0; i < kept_faces.size(); ++i) {
      if (component(i) == largest) in_largest.push_back(kept_faces[i]);
    }
    loose_faces = static_cast<int>(kept_faces.size() - in_largest.size());
    kept_faces = std::move(in_largest);
  }

  DepositedPlate out;
  out.removed_faces = static_cast<int>(num_faces - kept_faces.size());
  out.loose_faces = loose_faces;
  std::vector<int> new_vertex(V.rows(), -1);
  std::vector<int> kept_vertices;
  Eigen::MatrixXi kept_F(kept_faces.size(), 3);
  for (size_t i = 0; i < kept_faces.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      int& v = new_vertex[F(kept_faces[i], c)];
      if (v < 0) {
        v = static_cast<int>(kept_vertices.size());
        kept_vertices.push_back(F(kept_faces[i], c));
      }
      kept_F(i, c) = v;
    }
  }
  out.kept_faces = Eigen::Map<Eigen::VectorXi>(kept_faces.data(), kept_faces.size());
  out.kept_vertices = Eigen::Map<Eigen::VectorXi>(kept_vertices.data(), kept_vertices.size());
  PlateDesign& design = out.design;
  design.method = "gcode";
  design.F = kept_F;
  design.plate.resize(kept_vertices.size(), 2);
  for (size_t v = 0; v < kept_vertices.size(); ++v) {
    design.plate.row(v) = V.row(kept_vertices[v]).head<2>();
  }
  design.stack.materials = tool_materials;

  const Eigen::Index n = kept_F.rows();
  for (const DepositedLayer& layer_all : all) {
    DepositedLayer layer;
    layer.coverage.resize(n);
    layer.theta.resize(n);
    layer.thickness.resize(n);
    layer.tool.resize(n);
    layer.feed_rate.resize(n);
    bool any = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int f = kept_faces[i];
      layer.coverage(i) = layer_all.coverage(f);
      layer.theta(i) = layer_all.theta(f);
      layer.thickness(i) = layer_all.thickness(f);
      layer.tool(i) = covers(layer_all, f) ? layer_all.tool(f) : -1;
      layer.feed_rate(i) = layer_all.feed_rate(f);
      any = any || layer.tool(i) >= 0;
    }
    if (any) out.layers.push_back(std::move(layer));
  }

  // A layer is as thick as its beads are high where they lie (its deposited volume over the
  // area they cover) and covers that share of the face (Layer::cover): a lattice's sparse lines
  // keep their height and their stiffness scales with their share.
  auto bead_height = [](const DepositedLayer& layer, Eigen::Index i) {
    return layer.thickness(i) / std::max(layer.coverage(i), 1e-9);
  };
  // Each face's printed thickness, for the bilayer gradient spread over it (Eq. 15).
  Eigen::VectorXd total = Eigen::VectorXd::Zero(n);
  for (const DepositedLayer& layer : out.layers) {
    for (Eigen::Index i = 0; i < n; ++i) {
      if (layer.tool(i) >= 0) total(i) += bead_height(layer, i);
    }
  }
  Eigen::VectorXd z = Eigen::VectorXd::Zero(n);  // bottom of the next layer above each face
  for (const DepositedLayer& layer : out.layers) {
    Layer printed =
        uniform_layer(static_cast<int>(n), Layer::kNotCovered, tool_materials.front(), 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const int t = layer.tool(i);
      if (t < 0) continue;
      const Material& m = tool_materials[t];
      const double height = bead_height(layer, i);
      printed.material(i) = t;
      printed.printed_thickness(i) = height;
      printed.cover(i) = std::min(layer.coverage(i), 1.0);
      printed.theta(i) = layer.theta(i);
      // The curves are functions of the bead's height and of the speed it was laid at (feed
      // rates are mm/min).
      const double lambda1 = printed_lambda1(m, height, layer.feed_rate(i) / 60);
      const double mid = (z(i) + height / 2) / total(i) - 0.5;
      printed.lambda1(i) = lambda1 + mid * m.delta_lambda1;
      printed.delta_lambda1(i) = m.delta_lambda1 * height / total(i);
      printed.lambda2(i) = m.lambda2;
      printed.lambda3(i) = m.lambda3;
      z(i) += height;
    }
    design.stack.layers.push_back(std::move(printed));
  }
  check_layer_stack(design.stack);
  return out;
}

}  // namespace flatmorph
