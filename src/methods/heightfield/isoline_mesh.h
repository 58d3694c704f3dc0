// The printing graph of a height field (SCF 2020 §6.1, "Graph generation"): isolines of the height
// at chosen levels, gradient lines between them, and the quad-dominant graph they make,
// triangulated into printing edges (along the isolines: the paths that will shrink) and bridge
// edges (across them), upsampled so that no printing edge is longer than l_u. Every later stage of
// the method (flattening, toolpaths, the layer stack) reads this mesh. Units: millimetres.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "methods/heightfield/height_field.h"

namespace flatmorph {

// What an edge of the printing graph is.
enum class EdgeKind : std::uint8_t {
  kPrinting,  // along an isoline (or a saddle chain at one level): printed, it shrinks by σ
  kBridge,    // across the levels (gradient lines, diagonals, fan spokes): keeps its length
  kBoundary,  // along the outer boundary, the lowest isoline: printed like a printing edge
};

// A closed isoline. Loops form a tree: the boundary (loop 0) is the root, and a loop's parent is
// the loop one level below that encloses it (a saddle level has two or more loops over one
// parent).
struct IsolineLoop {
  int level = 0;              // index into IsolineMesh::levels
  int parent = -1;            // -1 for the boundary
  std::vector<int> vertices;  // counter-clockwise seen from +z; closed (the last joins the first)
};

struct IsolineMesh {
  Eigen::MatrixXd V;                // #V x 3, mm, on the height field: the target positions
  Eigen::MatrixXi F;                // #F x 3, counter-clockwise seen from +z
  Eigen::MatrixXi E;                // #E x 2 unique edges, E(e, 0) < E(e, 1)
  std::vector<EdgeKind> edge_kind;  // per edge
  // Ascending heights (mm) of the levels; levels[0] is the boundary's height. Index = depth in the
  // loop tree: twin peaks share their levels.
  Eigen::VectorXd levels;
  std::vector<IsolineLoop> loops;  // loops[0] is the outer boundary
  // Per vertex: the index of the level it lies at (isoline and saddle-chain vertices), or -1 for a
  // patch centre (the centre vertex of a summit cap or of a saddle polygon).
  Eigen::VectorXi vertex_level;
  // Per vertex: the loop it lies on, or -1 (saddle-chain vertices, patch centres).
  Eigen::VectorXi vertex_loop;
};

// The structure every consumer relies on (checked by the tests of isoline_mesh):
// - every printing and boundary edge joins two vertices of the same vertex_level; boundary edges
//   are exactly the edges of loop 0, which is the mesh's boundary;
// - every face without a patch centre has exactly one edge whose two vertices share a level (its
//   base, a printing or boundary edge) and its third vertex (the apex) one level above or below;
// - faces with a patch centre form fans ("patches": caps above the top loop of a summit, saddle
//   polygons) whose spokes are bridges.

// The boundary may vary in height by at most max(1e-3 x the field's height, 0.01 mm): far below a
// printed layer, and above the rounding of an exported mesh or a resampled image. Its vertices are
// set to the boundary level (their mean height), i.e. moved by at most that much.
inline constexpr double kBoundaryLevelTolerance = 1e-3;
inline constexpr double kBoundaryLevelToleranceMinMm = 0.01;

// Settings of isoline_mesh; lengths in millimetres of the printed plate (the field's own size).
struct IsolineMeshOptions {
  // Height between two equidistant isolines. 0: automatic, a twelfth of the field's height: the
  // paper's models show 9 to 27 loops (Hawaii's step is 1/6 of its height before its saddle and
  // summit levels), and a twelfth keeps the strips between loops about as wide as the gradient
  // lines are apart on the usual 20-40 degree slopes.
  double level_spacing_mm = 0.0;
  // l_u: no printing edge (along an isoline, a saddle chain or the boundary) is longer. The paper
  // uses 0.25 mm; 2 mm keeps a 160 mm design at a few thousand vertices so that the whole method
  // runs in seconds (the toolpath stage subdivides the rows again). Isolines are also split
  // where a straight edge would stray from the isoline by a quarter of the room to the next.
  double upsample_length_mm = 2.0;
  // Arc length between the points of an isoline from which gradient lines are traced, up and
  // down. 0: automatic, twice the level spacing and at least l_u (square cells on a slope of
  // about 27 degrees). Each loop gets at least 8.
  double gradient_spacing_mm = 0.0;
  // Two extra levels at each saddle (peaks rising less than half a spacing above it are noise
  // and get none): a quarter spacing below and above it (less near a low peak or the boundary).
  // The loop below pinches towards the saddle, the two above start beside it; the band between
  // holds only the saddle polygon. Equidistant levels within a quarter spacing of a band go.
  bool saddle_levels = true;
  // An extra level half-way between a summit and the highest level below it when that gap is
  // more than 3/4 of the spacing, so that the summit cap stays small.
  bool summit_levels = true;
};

// The printing graph of `field` (which has passed check_height_field: a disk, a graph over xy,
// without depressions; faces either way round), meshed by SCF 2020 §6.1: loop 0 is the field's
// boundary (all its input vertices are kept, so the mesh covers exactly the field's footprint);
// the levels are equidistant plus the saddle and summit levels, one global set, so that all loops
// at one depth of the loop tree lie at one height (twin peaks share their levels); loops are the
// isolines of the piecewise-linear height, resampled so that no printing edge is longer than l_u;
// gradient lines (steepest ascent and descent of the height, its gradient averaged at the
// vertices) join each loop to its parent and children, one more follows each saddle's
// separatrix down to the boundary, and each strip between two of them is zipped by the shortest
// diagonal; a summit cap fans from the summit's true highest point, a saddle polygon from the
// saddle vertex (each from a point that sees all the polygon when that one does not). Every
// vertex lies on the field (isoline vertices exactly at their level; boundary vertices at the
// boundary's mean height). `source` names the field in messages. Throws UserError: kGeometry when
// the boundary is not level (its range, where its highest point is, what to do), the field has no
// height, or an isoline bounds a pit (deeper than check_height_field lets through only at a level
// that happens to cut it); kOption when an option is negative or not finite, l_u is 0, or the
// spacing makes more than 10000 levels; kResource when the mesh would pass 5 million vertices.
// Throws std::logic_error when the meshing fails its own checks (a strip it cannot zip, a face
// flipped seen from above): a bug, met so far only with a spacing of a few percent of the height
// on meshes coarser than 3 mm.
IsolineMesh isoline_mesh(const HeightField& field, const IsolineMeshOptions& options,
                         const std::string& source);

}  // namespace flatmorph
