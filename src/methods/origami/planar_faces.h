// Thermorph Step 1 (CHI 2018, "Meshlab simplification"; notes §6): a triangle mesh turned into a
// solid of at most N planar polygon faces, the faces a self-folding sheet can print rigid.
// Millimetres and radians.
#pragma once

#include <numbers>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "methods/origami/polyhedron.h"

namespace flatmorph {

struct PlanarFacesOptions {
  int max_faces = 70;  // the paper's bunny
  // Neighbouring triangles whose normals differ by less than this merge into one face, rad.
  double coplanar_angle = std::numbers::pi / 180;
  // Every corner of a face lies within this fraction of the face's diameter of its plane.
  double planarity = 0.005;
};

// The mesh (V in mm, F counter-clockwise seen from the side its normals point to) as planar
// polygon faces: quadric-error edge collapse (Garland–Heckbert) while merging its triangles gives
// more than max_faces faces, then edge-adjacent triangles within coplanar_angle of a region's
// first triangle merged into simple polygons (one boundary loop, no corner twice), and the corners
// in the middle of a straight side between two faces dropped. A closed piece whose triangles face
// inward is turned outward (said in `notes`); an open piece keeps its orientation, its border
// edges become cuts. The result passes polyhedron_edges, faces counter-clockwise seen from
// outside. Throws UserError naming the triangles (by row of F) or faces: kGeometry for a
// non-finite coordinate, an index out of range, zero-area triangles, or a face not planar within
// `planarity`; kTopology for an edge of three or more triangles, two triangles running an edge the
// same way, or a vertex where separate fans of triangles meet; kOption when max_faces is below what
// the mesh's pieces need (4 for a closed one, 1 for an open one); kInfeasible when no further
// collapse keeps the mesh manifold and unfolded. `notes` (when given) receives one line per change
// made to the mesh.
Polyhedron planar_faces(const Mesh& mesh, const std::string& source,
                        const PlanarFacesOptions& options = {},
                        std::vector<std::string>* notes = nullptr);

}  // namespace flatmorph
