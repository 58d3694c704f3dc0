// Validation and repair of input meshes. Most methods need a disk-like surface: one connected,
// orientable, manifold component with exactly one boundary loop (Euler characteristic 1).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "mesh/mesh.h"

namespace flatmorph {

// What repair_mesh changed.
struct RepairReport {
  int welded_vertices = 0;        // vertices merged into an earlier coincident one
  int unreferenced_vertices = 0;  // vertices no face used, removed
  int degenerate_faces = 0;       // zero-area faces (repeated index or collinear corners), removed
  int duplicate_faces = 0;        // faces on the same three vertices as an earlier one, removed
  int flipped_faces = 0;          // faces reoriented to agree with their neighbours
};

// Weld tolerance: vertices closer than `weld_tolerance` x (bounding-box diagonal) are merged.
struct RepairOptions {
  double weld_tolerance = 1e-9;
  bool fix_orientation = true;
};

// Welds coincident vertices, removes unreferenced vertices, zero-area and duplicate faces, and
// makes the orientation consistent per component when it can (keeping the orientation of each
// component's first face). Never throws: what cannot be repaired is left to validate_mesh.
// Deterministic.
RepairReport repair_mesh(Mesh& mesh, const RepairOptions& options = {});

// Which check found a MeshProblem, so that a caller can word some problems itself (a height field
// names where its holes are) without parsing `what`.
enum class MeshProblemKind {
  kEmpty,
  kNotTriangles,
  kBadCoordinates,
  kMissingVertices,
  kZeroAreaFaces,
  kNonManifoldEdges,
  kNonManifoldVertices,
  kNonOrientable,
  kInconsistentOrientation,
  kSeveralPieces,
  kClosed,
  kHoles,
};

// One problem found in a mesh. `element` is the first offending vertex/edge/face index, or -1.
struct MeshProblem {
  MeshProblemKind kind;
  ErrorCategory category;  // kGeometry or kTopology
  std::string what;        // e.g. "non-manifold edge", "NaN or infinite coordinate"
  int count;               // how many elements have the problem
  std::string first;       // the first offending element, e.g. "vertex 17 (nan, 0, 1)"
  std::string fix;         // what the user can do, e.g. "remove the extra faces in a mesh editor"
};

// Everything `flatmorph info` shows about a mesh's validity.
struct MeshDiagnosis {
  int num_vertices = 0;
  int num_faces = 0;
  int num_edges = 0;
  int num_boundary_loops = 0;
  int num_components = 0;
  int euler_characteristic = 0;
  std::vector<MeshProblem> problems;  // empty when the mesh is a valid disk
  bool is_disk() const { return problems.empty(); }
};

// Checks, in this order: empty mesh, NaN/Inf or absurd (|x| > 1e12) coordinates, face indices out
// of range, zero-area faces, non-manifold edges (more than two faces), non-manifold vertices (a fan
// that is not one disk or half-disk), inconsistent orientation that cannot be fixed
// (non-orientable), more than one connected component, a closed surface (no boundary), holes (more
// than one boundary loop). Never throws.
MeshDiagnosis diagnose_mesh(const Mesh& mesh);

// The one-line message for a problem: "<source>: <what>: <count> (first: <first>); <fix>".
std::string problem_line(const std::string& source, const MeshProblem& problem);

// Throws UserError for the first problem of diagnose_mesh, with its problem_line.
void require_disk(const Mesh& mesh, const std::string& source);

}  // namespace flatmorph
