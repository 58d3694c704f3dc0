// How well one layer's paths do their job (issue 6 acceptance): equally spaced, covering the
// plate, inside it, and along the layer's print direction. Used by the tests and by reports.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "toolpath/toolpath.h"

namespace flatmorph {

struct PathQualityOptions {
  double spacing = 0.4;                // mm, the intended distance between neighbouring paths
  double sample_step = 0.25;           // samples along paths every sample_step x spacing
  double spacing_low = 0.8;            // (a) accepted band for the nearest-other-path distance,
  double spacing_high = 1.25;          //     in spacings
  double raster_step = 0.1;            // (b) plate raster pixel, in spacings
  double coverage_radius = 0.6;        // (b) a pixel is covered within this many spacings
  double outside_tolerance_mm = 1e-6;  // (c)
  // (d) samples closer than this (mm) to a singular point are not judged: the field has no
  // direction there. 1.5 spacings from a singular face's centroid is about one spacing from the
  // face itself when faces are at most a spacing wide.
  double singular_exclusion_mm = 0.6;
};

struct PathQuality {
  int samples = 0;
  double spacing_in_range = 0;  // (a) fraction of samples in [low, high] x spacing
  double spacing_median = 0;    // median nearest-other-path distance, in spacings
  double covered_area = 0;      // (b) fraction of the plate's area near a path
  int points_outside = 0;       // (c) path points farther than the tolerance from the plate
  double max_outside_mm = 0;    // (c) their largest distance (an upper bound), mm
  int angle_samples = 0;        // (d) samples judged
  double angle_median_deg = 0;  // (d) line angle between path tangent and theta^k, degrees
  double angle_p95_deg = 0;     //     in [0, 90]
};

// One sample of the evaluation, for pictures and diagnostics.
struct PathSample {
  Eigen::Vector2d position;  // mm
  double nearest_other = 0;  // distance to the nearest other path, in spacings (inf if > 2)
                             // (a stretch of the same path > 3 spacings away along it counts)
  double angle_deg = -1;     // line angle to theta^k, or -1 where not judged
};

// Judges `paths` (the extruding polylines of one layer; x, y used) on the plate (V #V x 2 mm,
// F counter-clockwise) against the layer's print direction theta_vertex (rad per vertex of V,
// interpolated as a line field). singular_points (mm) are where that field is singular.
// Deterministic. For (a) the nearest other path is searched within 2 spacings (farther counts as
// out of range); parts of the sample's own path more than 3 spacings away along it count as other
// paths (the next turn of a spiral, the far side of a hairpin).
PathQuality evaluate_path_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                  const Eigen::VectorXd& theta_vertex,
                                  const std::vector<PathPolyline>& paths,
                                  const std::vector<Eigen::Vector2d>& singular_points,
                                  const PathQualityOptions& options,
                                  std::vector<PathSample>* samples = nullptr);

}  // namespace flatmorph
