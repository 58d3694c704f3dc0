// What the printer does, as data: per layer, an ordered list of polylines whose segments say how
// they are printed. Coordinates in millimetres in the plate's frame (as in flat.ply); the G-code
// writer alone maps them to bed coordinates. Variable layer height along a path (SCF 2020) and tool
// changes (Thermorph's PLA/TPU) are ordinary data here, not special cases.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace flatmorph {

// How one segment of a polyline is printed.
struct SegmentStyle {
  double width = 0.4;          // extrusion width, mm
  double layer_height = 0.08;  // bead height, mm (may vary along a path)
  double feed_rate = 0.0;      // mm/s; 0 means the material's speed for this layer and path type
  int tool = 0;                // extruder index
  bool travel = false;         // move without extruding
};

// Slicer path types, written as PrusaSlicer ;TYPE: annotations.
enum class PathType { kPerimeter, kExternalPerimeter, kSolidInfill, kSkirt, kCustom };

struct PathPolyline {
  Eigen::Matrix<double, Eigen::Dynamic, 3> points;  // #P x 3: x, y, z in mm
  std::vector<SegmentStyle> segments;               // #P - 1, segment i joins points i and i+1
  PathType type = PathType::kSolidInfill;
  bool closed = false;  // a loop: the last point equals the first
};

// One printed layer, bottom to top. `z` is the top of the layer (mm above the bed) and `height` its
// nominal thickness; segment styles may refine both.
struct ToolpathLayer {
  double z = 0;
  double height = 0;
  std::vector<PathPolyline> paths;  // in print order; the writer travels between consecutive ones
};

struct Toolpath {
  std::vector<ToolpathLayer> layers;  // layer 0 lies on the bed
};

// Sum of the lengths of the extruding segments (mm).
double extrusion_length(const ToolpathLayer& layer);
// Length of the travels between consecutive polylines and inside them (mm), in xy.
double travel_length(const ToolpathLayer& layer);
// Volume of material extruded (mm^3): sum over segments of length x width x layer_height.
double extrusion_volume(const ToolpathLayer& layer);

}  // namespace flatmorph
