// The low-poly bunny the paper folds from 70 faces (Thermorph, CHI 2018, Fig. 15), made here from
// scratch: a sitting rabbit built from smoothly joined ellipsoids (body, chest, head, muzzle, two
// long ears, a tail) on a flat base, facing +x, z up, about 80 mm tall. Millimetres.
#pragma once

#include "mesh/mesh.h"
#include "methods/origami/polyhedron.h"

namespace flatmorph {

// The bunny as a fine, closed, manifold triangle mesh, outward oriented (about 2 mm triangles,
// some ten thousand of them). Deterministic.
Mesh bunny_mesh();

// bunny_mesh simplified by planar_faces to at most `max_faces` planar faces (source
// "example bunny"). Throws planar_faces' UserError (kOption) for fewer than 4 faces.
Polyhedron low_poly_bunny_solid(int max_faces = 70);

}  // namespace flatmorph
