#include "methods/tiles/tile_plate.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "material/thickness_curve.h"

namespace flatmorph {

TilePlate tile_plate(const SheetMesh& mesh, const std::vector<TileOutline>& outlines,
                     const std::vector<TileLevels>& levels, double pitch, const Material& material,
                     const TilePlateLattice* lattice) {
  if (outlines.size() != levels.size()) {
    throw std::invalid_argument("tile_plate: one set of levels per outline");
  }
  const ThicknessCurve& curve = require_thickness_curve(material);
  const int num_faces = static_cast<int>(mesh.F.rows());
  const int num_tiles = static_cast<int>(outlines.size());
  TilePlate out;
  out.face_tile = Eigen::VectorXi::Constant(num_faces, -1);
  out.face_level = Eigen::VectorXi::Constant(num_faces, -1);
  out.vertex_depth = Eigen::VectorXd::Zero(mesh.V.rows());
  out.vertex_tile = Eigen::VectorXi::Constant(mesh.V.rows(), -1);
  Eigen::VectorXd direction = Eigen::VectorXd::Zero(num_faces);
  Eigen::VectorXd shrinkage = Eigen::VectorXd::Zero(num_faces);

  // Per tile: its faces' centroids and vertices, framed once.
  for (int t = 0; t < num_tiles; ++t) {
    std::vector<int> faces;
    for (int f = 0; f < num_faces; ++f) {
      if (mesh.face_region(f) == t) faces.push_back(f);
    }
    Eigen::MatrixX2d centroids(faces.size(), 2);
    for (size_t i = 0; i < faces.size(); ++i) {
      const int f = faces[i];
      centroids.row(static_cast<Eigen::Index>(i)) =
          (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2)))
              .leftCols(2) /
          3.0;
    }
    const RingFrame frame = ring_frame(outlines[t], centroids);
    const int last = static_cast<int>(levels[t].levels.size()) - 1;
    for (size_t i = 0; i < faces.size(); ++i) {
      const int f = faces[i];
      const Eigen::Index k = static_cast<Eigen::Index>(i);
      int m = static_cast<int>(std::lround(frame.depth(k) / pitch - 0.5));
      m = std::clamp(m, 0, last);
      // A hole's faces belong to no ring: the nearest printed level prints there (the mesh
      // leaves the hole out when the tile has one).
      while (m > 0 && !levels[t].levels[m].printed) --m;
      out.face_tile(f) = t;
      out.face_level(f) = m;
      direction(f) = frame.direction(k);
      shrinkage(f) = levels[t].levels[m].shrinkage;
    }
    std::vector<int> vertices;
    for (int f : faces) {
      for (int c = 0; c < 3; ++c) vertices.push_back(mesh.F(f, c));
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    Eigen::MatrixX2d points(vertices.size(), 2);
    for (size_t i = 0; i < vertices.size(); ++i) {
      points.row(static_cast<Eigen::Index>(i)) = mesh.V.row(vertices[i]).leftCols(2);
    }
    const RingFrame vertex_frame = ring_frame(outlines[t], points);
    for (size_t i = 0; i < vertices.size(); ++i) {
      out.vertex_depth(vertices[i]) = vertex_frame.depth(static_cast<Eigen::Index>(i));
      out.vertex_tile(vertices[i]) = t;
    }
  }

  LayerStack& stack = out.design.stack;
  stack.materials = {material};
  if (lattice && lattice->material.name != material.name)
    stack.materials.push_back(lattice->material);
  const int lattice_tool = lattice && lattice->material.name != material.name ? 1 : 0;
  int max_layers = lattice ? lattice->layers : 0;
  for (int t = 0; t < num_tiles; ++t) {
    for (const RingLevel& level : levels[t].levels)
      max_layers = std::max(max_layers, level.layers());
  }
  // A lattice of a thickness-controlled material shrinks as its layer height gives; any other as
  // its own λ1 (an elastic PP or TPU does not shrink).
  double lattice_lambda1 = 1;
  if (lattice) {
    const std::optional<ThicknessCurve>& lattice_curve = lattice->material.thickness_curve;
    lattice_lambda1 = lattice_curve && lattice->layer_height >= lattice_curve->min_layer_height &&
                              lattice->layer_height <= lattice_curve->max_layer_height
                          ? lambda1_at_layer_height(*lattice_curve, lattice->layer_height)
                          : lattice->material.lambda1;
  }
  for (int k = 0; k < max_layers; ++k) {
    Layer layer = uniform_layer(num_faces, 0, material, material.layer_height);
    for (int f = 0; f < num_faces; ++f) {
      const int t = out.face_tile(f);
      if (t < 0) {
        if (!lattice || k >= lattice->layers) {
          layer.material(f) = Layer::kNotCovered;
          continue;
        }
        // Two families of lines, alternating by layer, each covering its share of the area.
        const Material& lm = lattice->material;
        layer.material(f) = lattice_tool;
        layer.printed_thickness(f) = lattice->layer_height;
        layer.cover(f) = lattice->fill;
        layer.theta(f) = (k % 2) * std::numbers::pi / 2;
        layer.lambda1(f) = lattice_lambda1;
        layer.lambda2(f) = lm.lambda2;
        layer.lambda3(f) = lm.lambda3;
        layer.delta_lambda1(f) = 0;
        continue;
      }
      const RingLevel& level = levels[t].levels[out.face_level(f)];
      if (k >= level.layers()) {
        layer.material(f) = Layer::kNotCovered;
        continue;
      }
      const double h = level.pass_layer_height(k + 1);
      layer.printed_thickness(f) = h;
      layer.theta(f) = direction(f);
      layer.lambda1(f) = lambda1_at_layer_height(curve, h);
      layer.delta_lambda1(f) = 0;
    }
    stack.layers.push_back(std::move(layer));
  }
  out.design.plate = mesh.V.leftCols(2);
  out.design.F = mesh.F;
  out.design.method = "tiles";
  out.design.design_fields.set_face("tile", out.face_tile.cast<double>());
  out.design.design_fields.set_face("level", out.face_level.cast<double>());
  out.design.design_fields.set_face("shrinkage", shrinkage);
  out.design.design_fields.set_face("direction", direction);
  return out;
}

Eigen::MatrixXd tile_start(const TilePlate& plate, const std::vector<TileLevels>& levels) {
  const Eigen::Index n = plate.design.plate.rows();
  Eigen::MatrixXd start = Eigen::MatrixXd::Zero(n, 3);
  start.leftCols(2) = plate.design.plate;
  for (Eigen::Index v = 0; v < n; ++v) {
    const int t = plate.vertex_tile(v);
    if (t >= 0) start(v, 2) = levels[t].side * 0.02 * plate.vertex_depth(v);
  }
  return start;
}

}  // namespace flatmorph
