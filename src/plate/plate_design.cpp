#include "plate/plate_design.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/file_text.h"
#include "common/memory.h"
#include "mesh/io.h"

namespace flatmorph {
namespace {

constexpr const char* kFormat = "flatmorph-stack";
constexpr int kVersion = 1;

// A layer's per-face quantities by the name the stack file gives them.
struct Quantity {
  const char* key;       // in the stack file
  const char* property;  // suffix of the per-face PLY property layer_K_<property>
};
constexpr Quantity kQuantities[] = {
    {"printed_thickness_mm", "thickness"},
    {"material", "material"},
    {"theta", "theta"},
    {"lambda1", "lambda1"},
    {"delta_lambda1", "delta_lambda1"},
    {"lambda2", "lambda2"},
    {"lambda3", "lambda3"},
    {"cover", "cover"},  // absent from files written before it: 1, solid layers
};

Eigen::VectorXd layer_values(const Layer& l, const std::string& key) {
  if (key == "printed_thickness_mm") return l.printed_thickness;
  if (key == "material") return l.material.cast<double>();
  if (key == "theta") return l.theta;
  if (key == "lambda1") return l.lambda1;
  if (key == "delta_lambda1") return l.delta_lambda1;
  if (key == "lambda2") return l.lambda2;
  if (key == "lambda3") return l.lambda3;
  return l.cover;
}

void set_layer_values(Layer& l, const std::string& key, const Eigen::VectorXd& v) {
  if (key == "printed_thickness_mm") l.printed_thickness = v;
  if (key == "material") l.material = v.cast<int>();
  if (key == "theta") l.theta = v;
  if (key == "lambda1") l.lambda1 = v;
  if (key == "delta_lambda1") l.delta_lambda1 = v;
  if (key == "lambda2") l.lambda2 = v;
  if (key == "lambda3") l.lambda3 = v;
  if (key == "cover") l.cover = v;
}

bool uniform(const Eigen::VectorXd& v) { return v.size() == 0 || (v.array() == v(0)).all(); }

[[noreturn]] void stack_error(const std::filesystem::path& path, const std::string& problem) {
  throw UserError(ErrorCategory::kFormat,
                  fmt::format("{}: {}; write the plate again with 'flatmorph design' or "
                              "'flatmorph flatten' (docs/plate.md describes the format)",
                              path.string(), problem));
}

PlateDesign read_flat_mesh(const std::filesystem::path& path, MeshProperties& properties) {
  const std::string name = path.string();
  MeshFile file = read_mesh(path);
  if (file.mesh.num_vertices() == 0 || file.mesh.num_faces() == 0) {
    throw UserError(ErrorCategory::kFormat, fmt::format("{}: the plate has no faces", name));
  }
  // Simulating or tracing a plate takes far more memory than reading it: refuse it up front.
  require_memory(
      static_cast<std::uint64_t>(file.mesh.num_faces()) * kDesignBytesPerFace,
      fmt::format("{}: simulating or printing this plate of {} faces", name, file.mesh.num_faces()),
      "design a coarser plate (flatmorph flatten/design --faces)");
  const double extent =
      (file.mesh.V.colwise().maxCoeff() - file.mesh.V.colwise().minCoeff()).head<2>().maxCoeff();
  if (!file.mesh.V.allFinite() ||
      file.mesh.V.col(2).cwiseAbs().maxCoeff() > 1e-9 * std::max(extent, 1.0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the plate is not flat (z != 0); pass the flat.ply written by "
                                "'flatmorph flatten' or 'flatmorph design'",
                                name));
  }
  PlateDesign design;
  design.plate = file.mesh.V.leftCols(2);
  design.F = file.mesh.F;
  properties = std::move(file.properties);
  return design;
}

}  // namespace

std::filesystem::path stack_file_path(const std::filesystem::path& plate_mesh_path) {
  std::filesystem::path p = plate_mesh_path;
  p.replace_extension(".stack.json");
  return p;
}

void write_plate_design(const std::filesystem::path& plate_mesh_path, const PlateDesign& design) {
  check_layer_stack(design.stack);
  const int num_faces = static_cast<int>(design.F.rows());
  if (design.stack.num_faces() != num_faces || design.plate.cols() != 2) {
    throw std::invalid_argument(fmt::format(
        "{}: the stack has {} faces for a plate of {} (and {} coordinates "
        "per vertex): give one value per face and a 2D plate",
        plate_mesh_path.string(), design.stack.num_faces(), num_faces, design.plate.cols()));
  }
  MeshProperties properties = design.design_fields;
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["units"] = "mm for lengths, radians for angles (from +x, counter-clockwise, plate frame)";
  j["method"] = design.method;
  j["plate"] = plate_mesh_path.filename().string();
  j["faces"] = num_faces;
  j["materials"] = nlohmann::ordered_json::array();
  for (const Material& m : design.stack.materials) {
    j["materials"].push_back(nlohmann::ordered_json::parse(material_json(m)));
  }
  j["layers"] = nlohmann::ordered_json::array();
  for (int k = 0; k < design.stack.num_layers(); ++k) {
    const Layer& l = design.stack.layers[k];
    nlohmann::ordered_json layer;
    layer["layer"] = k + 1;
    for (const Quantity& q : kQuantities) {
      const Eigen::VectorXd v = layer_values(l, q.key);
      if (uniform(v)) {
        if (std::string(q.key) == "material") {
          layer[q.key] = l.material(0);
        } else {
          layer[q.key] = v(0);
        }
      } else {
        const std::string property = fmt::format("layer_{}_{}", k + 1, q.property);
        properties.set_face(property, v);
        layer[q.key] = {{"property", property}};
      }
    }
    j["layers"].push_back(layer);
  }
  // The stack file first: a reader that finds the new mesh finds its stack beside it.
  write_file_atomically(stack_file_path(plate_mesh_path), false,
                        [&](std::ostream& out) { out << j.dump(2) << '\n'; });
  Mesh mesh;
  mesh.V = Eigen::MatrixXd::Zero(design.plate.rows(), 3);
  mesh.V.leftCols(2) = design.plate;
  mesh.F = design.F;
  write_ply(plate_mesh_path, mesh, properties);
}

PlateDesignFile read_plate_design(const std::filesystem::path& plate_mesh_path,
                                  const Material& fallback_material, int fallback_layers) {
  MeshProperties properties;
  PlateDesignFile out;
  out.design = read_flat_mesh(plate_mesh_path, properties);
  PlateDesign& design = out.design;
  const int num_faces = static_cast<int>(design.F.rows());
  const std::filesystem::path stack_path = stack_file_path(plate_mesh_path);
  std::error_code error;
  if (!std::filesystem::exists(stack_path, error)) {
    const Eigen::VectorXd* theta1 = properties.find_face("theta1");
    if (theta1 == nullptr) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: no stack file ({}) and no per-face property 'theta1' (the "
                                  "print direction in radians); pass the flat.ply written by "
                                  "'flatmorph flatten' or 'flatmorph design'",
                                  plate_mesh_path.string(), stack_path.filename().string()));
    }
    const Eigen::VectorXd* theta2 = properties.find_vertex("theta2");
    const Eigen::VectorXd theta2_vertex =
        theta2 ? *theta2 : Eigen::VectorXd::Zero(design.plate.rows());
    if (!theta1->allFinite() || !theta2_vertex.allFinite()) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: theta1 or theta2 holds NaN or infinite values",
                                  plate_mesh_path.string()));
    }
    design.stack = shrink_morph_layer_stack(
        *theta1, vertex_to_face_average(design.F, theta2_vertex), fallback_material,
        fallback_layers, fallback_material.layer_height);
    design.method = "shrink_morph";
    design.design_fields.set_face("theta1", *theta1);
    design.design_fields.set_vertex("theta2", theta2_vertex);
    return out;
  }

  const std::string text = read_file_text(stack_path, "stack file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    stack_error(stack_path, fmt::format("not valid JSON ({})", e.what()));
  }
  try {
    if (!j.is_object() || j.value("format", "") != kFormat) {
      stack_error(stack_path,
                  fmt::format("not a flatmorph stack file (no \"format\": \"{}\")", kFormat));
    }
    if (j.at("version").get<int>() != kVersion) {
      stack_error(stack_path, fmt::format("version {} is not one this flatmorph reads ({})",
                                          j.at("version").dump(), kVersion));
    }
    if (j.at("faces").get<int>() != num_faces) {
      stack_error(stack_path, fmt::format("it describes {} faces but {} has {}: the two files do "
                                          "not belong together",
                                          j.at("faces").get<int>(),
                                          plate_mesh_path.filename().string(), num_faces));
    }
    design.method = j.value("method", "");
    int index = 0;
    for (const auto& m : j.at("materials")) {
      design.stack.materials.push_back(parse_material_json(
          m.dump(), fmt::format("{}, material {}", stack_path.string(), index)));
      ++index;
    }
    std::vector<std::string> used_properties;
    int k = 0;
    for (const auto& layer_json : j.at("layers")) {
      ++k;
      Layer layer;
      for (const Quantity& q : kQuantities) {
        if (std::string(q.key) == "cover" && !layer_json.contains(q.key)) {
          layer.cover = Eigen::VectorXd::Ones(num_faces);
          continue;
        }
        const nlohmann::json& value = layer_json.at(q.key);
        Eigen::VectorXd v;
        if (value.is_object()) {
          const std::string property = value.at("property").get<std::string>();
          const Eigen::VectorXd* found = properties.find_face(property);
          if (found == nullptr) {
            stack_error(stack_path,
                        fmt::format("layer {}'s {} is the per-face property '{}', "
                                    "which {} does not have",
                                    k, q.key, property, plate_mesh_path.filename().string()));
          }
          v = *found;
          used_properties.push_back(property);
        } else {
          v = Eigen::VectorXd::Constant(num_faces, value.get<double>());
        }
        if (!v.allFinite()) {
          stack_error(stack_path,
                      fmt::format("layer {}'s {} holds NaN or infinite values", k, q.key));
        }
        if (std::string(q.key) == "material" && (v.array() != v.array().round()).any()) {
          stack_error(stack_path, fmt::format("layer {}'s material is not a whole number", k));
        }
        set_layer_values(layer, q.key, v);
      }
      design.stack.layers.push_back(std::move(layer));
    }
    // What stays of the PLY's properties are the design method's own fields.
    for (const ScalarProperty& p : properties.face) {
      if (std::find(used_properties.begin(), used_properties.end(), p.name) ==
          used_properties.end()) {
        design.design_fields.set_face(p.name, p.values);
      }
    }
    for (const ScalarProperty& p : properties.vertex) {
      design.design_fields.set_vertex(p.name, p.values);
    }
  } catch (const nlohmann::json::exception& e) {
    stack_error(stack_path, fmt::format("a key is missing or has the wrong type ({})", e.what()));
  }
  if (design.stack.layers.empty()) stack_error(stack_path, "it has no layer");
  try {
    check_layer_stack(design.stack);
  } catch (const UserError& e) {
    stack_error(stack_path, e.what());
  }
  out.from_stack_file = true;
  return out;
}

}  // namespace flatmorph
