// The built-in solids of `flatmorph origami --example`, generated so that the method runs without
// files: the Platonic solids, a square pyramid and the low-poly bunny (bunny.h). Millimetres.
#pragma once

#include <string>
#include <vector>

#include "examples/examples.h"
#include "methods/origami/polyhedron.h"

namespace flatmorph {

// The built-in solids, every edge `edge_mm` long: tetrahedron, cube, octahedron, dodecahedron,
// icosahedron, and a square pyramid whose triangles are equilateral.
std::vector<std::string> polyhedron_example_names();
// Throws UserError (kOption) naming the examples for any other name or a non-positive edge.
Polyhedron polyhedron_example(const std::string& name, double edge_mm);

// The built-in solids of `flatmorph origami --example`: polyhedron_example_names() and "bunny"
// (low_poly_bunny_solid with at most `max_faces` faces), each at a size (the longest side, mm)
// where every face keeps some of itself after its trims with the default hinge curve, the Platonic
// solids' nets fit a 220 mm bed and the bunny's (160 mm tall, six nets) the default printer's
// 360 mm one. Throws UserError (kOption) listing them for another name.
std::vector<ExampleInfo> origami_example_list();
std::vector<std::string> origami_example_names();
Polyhedron origami_example(const std::string& name, int max_faces);

}  // namespace flatmorph
