#include "methods/origami/fold_file.h"
#include "common/angles.h"

#include <nlohmann/json.hpp>

#include <numbers>
#include <stdexcept>

namespace flatmorph {
namespace {

using Json = nlohmann::ordered_json;

// +0 for −0, so that a coordinate on an axis reads "0.0" whichever side it came from.
double tidy(double v) { return v + 0.0; }

char assignment(CreaseKind kind) {
  switch (kind) {
    case CreaseKind::kBorder:
      return 'B';
    case CreaseKind::kMountain:
      return 'M';
    case CreaseKind::kValley:
      return 'V';
    case CreaseKind::kFlat:
      return 'F';
  }
  return 'U';
}

// Indented one property a line, and one entry a line in arrays of arrays (a vertex, an edge, a
// face each on a line), so the file reads and diffs well.
void write(const Json& value, int indent, std::string& out) {
  const std::string pad(static_cast<size_t>(indent), ' ');
  if (value.is_object()) {
    out += "{\n";
    bool first = true;
    for (const auto& [key, item] : value.items()) {
      if (!first) out += ",\n";
      first = false;
      out += pad + "  " + Json(key).dump() + ": ";
      write(item, indent + 2, out);
    }
    out += "\n" + pad + "}";
  } else if (value.is_array() && !value.empty() && (value[0].is_array() || value[0].is_object())) {
    out += "[\n";
    for (size_t i = 0; i < value.size(); ++i) {
      out += pad + "  ";
      if (value[i].is_object()) {
        write(value[i], indent + 2, out);
      } else {
        out += value[i].dump();
      }
      out += i + 1 < value.size() ? ",\n" : "\n";
    }
    out += pad + "]";
  } else {
    out += value.dump();
  }
}

}  // namespace

std::string fold_json(const CreasePattern& pattern, const std::vector<HingeDesign>* hinges,
                      const std::vector<Eigen::MatrixX3d>* folded) {
  const int num_creases = static_cast<int>(pattern.creases.size());
  std::vector<const HingeDesign*> hinge_of(pattern.creases.size(), nullptr);
  if (hinges != nullptr) {
    for (const HingeDesign& hinge : *hinges) {
      if (hinge.crease < 0 || hinge.crease >= num_creases || hinge_of[hinge.crease] != nullptr) {
        throw std::invalid_argument("fold_json: a hinge on no crease of the pattern, or twice");
      }
      hinge_of[hinge.crease] = &hinge;
    }
  }

  Json j;
  j["file_spec"] = 1.2;
  j["file_creator"] = "flatmorph";
  j["file_classes"] = Json::array({"singleModel"});
  j["frame_title"] = pattern.name;
  j["frame_classes"] = Json::array({"creasePattern"});
  j["frame_attributes"] = Json::array({"2D"});
  j["frame_unit"] = "mm";
  Json& coords = j["vertices_coords"] = Json::array();
  for (Eigen::Index v = 0; v < pattern.V.rows(); ++v) {
    coords.push_back(Json::array({tidy(pattern.V(v, 0)), tidy(pattern.V(v, 1))}));
  }
  Json& edges = j["edges_vertices"] = Json::array();
  Json& assignments = j["edges_assignment"] = Json::array();
  Json& angles = j["edges_foldAngle"] = Json::array();
  for (const Crease& crease : pattern.creases) {
    edges.push_back(Json::array({crease.v0, crease.v1}));
    assignments.push_back(std::string(1, assignment(crease.kind)));
    const bool folds = crease.kind == CreaseKind::kMountain || crease.kind == CreaseKind::kValley;
    angles.push_back(folds ? tidy(crease.fold_angle * kDegreesPerRadian) : 0.0);
  }
  if (hinges != nullptr) {
    Json width = Json::array(), radius = Json::array(), speed = Json::array(),
         stacking = Json::array();
    for (const HingeDesign* hinge : hinge_of) {
      width.push_back(hinge != nullptr ? Json(hinge->width) : Json());
      radius.push_back(hinge != nullptr ? Json(hinge->radius) : Json());
      speed.push_back(hinge != nullptr ? Json(hinge->pla_speed) : Json());
      stacking.push_back(hinge != nullptr ? Json(hinge->pla_on_bed ? "A" : "B") : Json());
    }
    j["edges_flatmorph:actuatorWidth"] = std::move(width);
    j["edges_flatmorph:radius"] = std::move(radius);
    j["edges_flatmorph:speed"] = std::move(speed);
    j["edges_flatmorph:case"] = std::move(stacking);
  }
  Json& faces = j["faces_vertices"] = Json::array();
  for (const std::vector<int>& face : pattern.faces) faces.push_back(face);

  if (folded != nullptr) {
    if (folded->size() != pattern.faces.size()) {
      throw std::invalid_argument("fold_json: folded corners for another number of faces");
    }
    // Each sheet vertex where the first face that has it puts it: the faces around a vertex
    // agree to rounding, the tree's hinges joining them.
    Eigen::MatrixX3d at = Eigen::MatrixX3d::Zero(pattern.V.rows(), 3);
    std::vector<bool> placed(static_cast<size_t>(pattern.V.rows()), false);
    for (size_t f = 0; f < pattern.faces.size(); ++f) {
      const std::vector<int>& face = pattern.faces[f];
      if ((*folded)[f].rows() != static_cast<Eigen::Index>(face.size())) {
        throw std::invalid_argument("fold_json: folded corners that do not match a face");
      }
      for (size_t k = 0; k < face.size(); ++k) {
        if (placed[static_cast<size_t>(face[k])]) continue;
        placed[static_cast<size_t>(face[k])] = true;
        at.row(face[k]) = (*folded)[f].row(static_cast<Eigen::Index>(k));
      }
    }
    Json frame;
    frame["frame_classes"] = Json::array({"foldedForm"});
    frame["frame_attributes"] = Json::array({"3D"});
    frame["frame_parent"] = 0;
    frame["frame_inherit"] = true;
    Json& folded_coords = frame["vertices_coords"] = Json::array();
    for (Eigen::Index v = 0; v < at.rows(); ++v) {
      folded_coords.push_back(Json::array({tidy(at(v, 0)), tidy(at(v, 1)), tidy(at(v, 2))}));
    }
    j["file_frames"] = Json::array({std::move(frame)});
  }

  std::string out;
  write(j, 0, out);
  out += '\n';
  return out;
}

}  // namespace flatmorph
