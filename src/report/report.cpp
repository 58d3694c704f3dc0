#include "report/report.h"

#include <fmt/core.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/markup.h"
#include "gcode/preview.h"
#include "mesh/topology.h"
#include "report/pictures.h"
#include "report/viewer_template.h"

namespace flatmorph {
namespace {

static_assert(
    std::endian::native == std::endian::little,
    "the report stores typed arrays little-endian, as browsers on this machine read them");

using Json = nlohmann::ordered_json;

std::string base64(const void* data, size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t b0 = p[i], b1 = i + 1 < size ? p[i + 1] : 0, b2 = i + 2 < size ? p[i + 2] : 0;
    const uint32_t v = b0 << 16 | b1 << 8 | b2;
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += i + 1 < size ? kAlphabet[v >> 6 & 63] : '=';
    out += i + 2 < size ? kAlphabet[v & 63] : '=';
  }
  return out;
}

template <class T>
std::string base64(const std::vector<T>& values) {
  return base64(values.data(), values.size() * sizeof(T));
}

std::string float32(const Eigen::MatrixXd& m, int columns) {
  std::vector<float> v;
  v.reserve(static_cast<size_t>(m.rows()) * columns);
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (int c = 0; c < columns; ++c) v.push_back(c < m.cols() ? static_cast<float>(m(r, c)) : 0.f);
  }
  return base64(v);
}

std::string float32(const Eigen::VectorXd& x) {
  std::vector<float> v(x.data(), x.data() + x.size());
  return base64(v);
}

std::string uint32(const Eigen::MatrixXi& F) {
  std::vector<uint32_t> v;
  v.reserve(static_cast<size_t>(F.size()));
  for (Eigen::Index r = 0; r < F.rows(); ++r) {
    for (Eigen::Index c = 0; c < F.cols(); ++c) v.push_back(static_cast<uint32_t>(F(r, c)));
  }
  return base64(v);
}

Json mesh_json(const Mesh& mesh) {
  Json j;
  j["vertices"] = mesh.V.rows();
  j["faces"] = mesh.F.rows();
  j["positions"] = float32(mesh.V, 3);
  j["indices"] = uint32(mesh.F);
  return j;
}

// Print paths per layer: x, y quantized to 16 bits over the box of all paths (a step of at most
// 1/65535 of the plate: 1.5 micrometres on a 100 mm plate).
Json layers_json(const Toolpath& toolpath) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
        for (int k = 0; k < 2; ++k) {
          lo[k] = std::min(lo[k], path.points(i, k));
          hi[k] = std::max(hi[k], path.points(i, k));
        }
      }
    }
  }
  if (!(lo[0] <= hi[0])) lo[0] = lo[1] = hi[0] = hi[1] = 0;
  Json j;
  j["box"] = {lo[0], lo[1], hi[0], hi[1]};
  Json layers = Json::array();
  for (const ToolpathLayer& layer : toolpath.layers) {
    std::vector<uint16_t> q;
    std::vector<uint32_t> starts{0};
    double width = 0;
    size_t segments = 0;
    for (const PathPolyline& path : layer.paths) {
      for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
        for (int k = 0; k < 2; ++k) {
          const double span = hi[k] - lo[k];
          const double t = span > 0 ? (path.points(i, k) - lo[k]) / span : 0.0;
          q.push_back(static_cast<uint16_t>(std::lround(std::clamp(t, 0.0, 1.0) * 65535)));
        }
      }
      starts.push_back(static_cast<uint32_t>(q.size() / 2));
      for (const SegmentStyle& s : path.segments) {
        width += s.width;
        ++segments;
      }
    }
    Json l;
    l["z"] = layer.z;
    l["height"] = layer.height;
    l["width"] = segments ? width / static_cast<double>(segments) : 0.4;
    l["paths"] = layer.paths.size();
    l["extruded_mm"] = std::round(extrusion_length(layer) * 10) / 10;
    l["travel_mm"] = std::round(travel_length(layer) * 10) / 10;
    l["points"] = base64(q);
    l["starts"] = base64(starts);
    layers.push_back(std::move(l));
  }
  j["layers"] = std::move(layers);
  return j;
}

std::string value_text(const Json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  if (v.is_null()) return "";
  return v.dump();
}

const Json* find(const Json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

double number(const Json* v) { return v && v->is_number() ? v->get<double>() : NAN; }

struct Section {
  std::string title;
  Json rows = Json::array();
  void add(const std::string& label, const std::string& value) {
    if (!value.empty()) rows.push_back({label, value});
  }
};

Json metrics_json(const RunFolder& run) {
  const Json& design = run.design;
  const Json* metrics = find(design, "metrics");
  static const Json kEmpty = Json::object();
  const Json& m = metrics ? *metrics : kEmpty;
  std::vector<Section> sections;

  Section shape{"Shape"};
  const double sim_avg = number(find(m, "dist_to_sim_avg_pct"));
  const double sim_max = number(find(m, "dist_to_sim_max_pct"));
  const double opt_avg = number(find(m, "dist_to_optim_avg_pct"));
  const double opt_max = number(find(m, "dist_to_optim_max_pct"));
  if (std::isfinite(sim_avg)) {
    shape.add("distance to target with θ2 = 0 (avg / max, % of diagonal)",
              fmt::format("{:.3f} % / {:.3f} %", sim_avg, sim_max));
  }
  if (std::isfinite(opt_avg)) {
    shape.add("distance to target with optimized θ2 (avg / max, % of diagonal)",
              fmt::format("{:.3f} % / {:.3f} %", opt_avg, opt_max));
  }
  if (run.simulated) {
    if (const Eigen::VectorXd* d = run.simulated->properties.find_vertex("deviation_mm");
        d && d->size() > 0) {
      shape.add("predicted shape to target (mean / max, mm)",
                fmt::format("{:.3f} mm / {:.3f} mm", d->mean(), d->maxCoeff()));
    }
  }
  const double gcode_avg = number(find(m, "gcode_dist_avg_pct"));
  if (std::isfinite(gcode_avg)) {
    shape.add("distance to target of the shape plate.gcode prints (avg / max, % of diagonal)",
              fmt::format("{:.3f} % / {:.3f} %", gcode_avg, number(find(m, "gcode_dist_max_pct"))));
  }
  const double vs_fields = number(find(m, "gcode_vs_fields_avg_pct"));
  if (std::isfinite(vs_fields)) {
    shape.add(
        "plate.gcode's shape to the design's (avg / max, % of diagonal)",
        fmt::format("{:.3f} % / {:.3f} %", vs_fields, number(find(m, "gcode_vs_fields_max_pct"))));
  }
  if (run.flat) {
    shape.add("plate",
              fmt::format("{} vertices, {} faces", run.flat->plate.rows(), run.flat->F.rows()));
    const LayerStack& stack = run.flat->stack;
    const auto [thinnest, thickest] = printed_thickness_range(stack);
    std::string materials;
    for (const Material& m : stack.materials) materials += (materials.empty() ? "" : ", ") + m.name;
    shape.add("printed layers (flat.stack.json)",
              fmt::format("{} layers, {}, of {}", stack.num_layers(),
                          thickest - thinnest < 0.005
                              ? fmt::format("{:.3g} mm", thickest)
                              : fmt::format("{:.3g} to {:.3g} mm", thinnest, thickest),
                          materials));
    if (const Eigen::VectorXd* theta2 = run.flat->design_fields.find_vertex("theta2");
        theta2 && theta2->size() > 0) {
      const double t = theta2->cwiseAbs().maxCoeff();
      shape.add("max |θ2|", fmt::format("{:.4f} rad ({:.2f}°)", t, t * 180 / std::numbers::pi));
    }
  }
  sections.push_back(shape);

  Section times{"Time per stage"};
  if (metrics && metrics->is_object()) {
    double total = 0;
    for (const auto& [key, value] : metrics->items()) {
      if (key.starts_with("t_") && key.ends_with("_s") && value.is_number()) {
        times.add(key.substr(2, key.size() - 4), fmt::format("{:.2f} s", value.get<double>()));
        total += value.get<double>();
      }
    }
    if (!times.rows.empty()) times.add("total", fmt::format("{:.2f} s", total));
  }
  sections.push_back(times);

  Section print{"Print"};
  if (run.print) {
    const ToolpathFile& g = *run.print;
    print.add("estimated print time", summary_value(g, "estimated printing time (normal mode)"));
    const std::string mm = summary_value(g, "filament used [mm]");
    if (!mm.empty()) {
      print.add("filament",
                fmt::format("{} mm, {} cm³, {} g", mm, summary_value(g, "filament used [cm3]"),
                            summary_value(g, "filament used [g]")));
    }
    double extruded = 0, travel = 0;
    size_t paths = 0;
    for (const ToolpathLayer& layer : g.toolpath.layers) {
      extruded += extrusion_length(layer);
      travel += travel_length(layer);
      paths += layer.paths.size();
    }
    print.add("layers", std::to_string(g.toolpath.layers.size()));
    print.add("paths", std::to_string(paths));
    print.add("printed length", fmt::format("{:.0f} mm", extruded));
    print.add("travel length", fmt::format("{:.0f} mm", travel));
  }
  sections.push_back(print);

  Section material{"Material and printer"};
  const std::string printer =
      design.is_object() && find(design, "printer") ? value_text(*find(design, "printer")) : "";
  if (run.print) {
    const ToolpathFile& g = *run.print;
    for (const char* key :
         {"material", "material_description", "nozzle_temperature", "bed_temperature", "shrink",
          "density", "printer", "printer_description", "bed", "nozzle_diameter", "speeds"}) {
      material.add(key, summary_value(g, key));
    }
  } else {
    if (const Json* name = find(design, "material")) material.add("material", value_text(*name));
    material.add("printer", printer);
  }
  sections.push_back(material);

  Section parameters{"Parameters (design.json)"};
  if (design.is_object()) {
    for (const auto& [key, value] : design.items()) {
      if (key != "metrics") parameters.add(key, value_text(value));
    }
  }
  sections.push_back(parameters);

  Section all_metrics{"Metrics (design.json)"};
  if (metrics && metrics->is_object()) {
    for (const auto& [key, value] : metrics->items()) all_metrics.add(key, value_text(value));
  }
  sections.push_back(all_metrics);

  Section header{"G-code (plate.gcode header, from toolpath.json)"};
  if (run.print) {
    for (const auto& [key, value] : run.print->summary) header.add(key, value);
  }
  sections.push_back(header);

  Section files{"Run folder"};
  files.add("folder", run.name);
  std::string missing;
  for (const std::string& name : run.missing) missing += (missing.empty() ? "" : ", ") + name;
  files.add("missing files", missing);
  sections.push_back(files);

  Json out = Json::array();
  for (Section& s : sections) {
    if (!s.rows.empty()) out.push_back({{"title", s.title}, {"rows", std::move(s.rows)}});
  }
  return out;
}

std::string title(const RunFolder& run) {
  if (const Json* input = find(run.design, "input"); input && input->is_string()) {
    return input->get<std::string>();
  }
  return run.name;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

// The plate's mean print direction per face: the design's theta1 when it has one, else its bottom
// layer's direction.
Eigen::VectorXd plate_theta1(const PlateDesign& plate) {
  if (const Eigen::VectorXd* theta1 = plate.design_fields.find_face("theta1")) return *theta1;
  return plate.stack.layers.front().theta;
}

std::vector<Eigen::MatrixX2d> outline(const PlateDesign& plate) {
  std::vector<Eigen::MatrixX2d> loops;
  for (const std::vector<int>& loop : boundary_loops(plate.F)) {
    Eigen::MatrixX2d o(loop.size(), 2);
    for (size_t i = 0; i < loop.size(); ++i) o.row(i) = plate.plate.row(loop[i]).head<2>();
    loops.push_back(o);
  }
  return loops;
}

void write_png(const std::filesystem::path& path, const std::vector<unsigned char>& png) {
  write_file_atomically(path, true, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

}  // namespace

std::string report_html(const RunFolder& run) {
  Json data;
  data["title"] = title(run);
  if (run.flat) {
    const PlateDesign& p = *run.flat;
    Json plate;
    plate["vertices"] = p.plate.rows();
    plate["faces"] = p.F.rows();
    plate["positions"] = float32(p.plate, 2);
    plate["indices"] = uint32(p.F);
    const Eigen::VectorXd theta1 = plate_theta1(p);
    plate["theta1"] = float32(theta1);
    if (const Eigen::VectorXd* theta2 = p.design_fields.find_vertex("theta2");
        theta2 && theta2->size() == p.plate.rows()) {
      plate["theta2"] = float32(*theta2);
    }
    if (const Eigen::VectorXd* shrinkage = p.design_fields.find_face("shrinkage");
        shrinkage && shrinkage->size() == p.F.rows()) {
      plate["shrinkage"] = float32(*shrinkage);
    }
    data["plate"] = std::move(plate);
  }
  if (run.target) data["target"] = mesh_json(run.target->mesh);
  if (run.simulated) {
    Json predicted = mesh_json(run.simulated->mesh);
    const Eigen::VectorXd* d = run.simulated->properties.find_vertex("deviation_mm");
    if (d && d->size() == run.simulated->mesh.V.rows()) predicted["deviation_mm"] = float32(*d);
    data["predicted"] = std::move(predicted);
  }
  if (run.gcode_simulated) data["gcode_predicted"] = mesh_json(run.gcode_simulated->mesh);
  if (run.print) data["toolpath"] = layers_json(run.print->toolpath);
  data["metrics"] = metrics_json(run);
  data["missing"] = run.missing;
  Json drawings = Json::array();
  for (const auto& [name, svg] : run.drawings) {
    drawings.push_back({{"name", name}, {"svg", base64(svg.data(), svg.size())}});
  }
  if (!drawings.empty()) data["drawings"] = std::move(drawings);

  // Inside <script>, "</script" or "<!--" in a string would end or confuse the element: '<' only
  // occurs in JSON strings, where \u003c reads back the same.
  std::string json = data.dump();
  replace_all(json, "<", "\\u003c");
  std::string html(viewer_html_template());
  replace_all(html, "__FLATMORPH_TITLE__", xml_escape(title(run)));
  const size_t at = html.find("__FLATMORPH_DATA__");
  if (at == std::string::npos) throw std::logic_error("viewer template without data placeholder");
  html.replace(at, std::string_view("__FLATMORPH_DATA__").size(), json);
  return html;
}

std::vector<std::filesystem::path> write_report_pictures(const RunFolder& run, int pixels) {
  std::vector<std::filesystem::path> written;
  if (run.flat) {
    const auto path = run.dir / "plate_theta1.png";
    const PlateDesign& p = *run.flat;
    write_png(path, encode_png(
                        plate_picture(p.plate, p.F, plate_theta1(p), PlateField::kTheta1, pixels)));
    written.push_back(path);
    const Eigen::VectorXd* theta2 = p.design_fields.find_vertex("theta2");
    if (theta2 && theta2->size() > 0 && theta2->cwiseAbs().maxCoeff() > 0) {
      const auto path2 = run.dir / "plate_theta2.png";
      write_png(path2,
                encode_png(plate_picture(p.plate, p.F, *theta2, PlateField::kTheta2, pixels)));
      written.push_back(path2);
    }
    const Eigen::VectorXd* shrinkage = p.design_fields.find_face("shrinkage");
    if (shrinkage && shrinkage->size() == p.F.rows()) {
      const auto path3 = run.dir / "plate_shrinkage.png";
      write_png(path3, encode_png(plate_picture(p.plate, p.F, *shrinkage, PlateField::kShrinkage,
                                                pixels)));
      written.push_back(path3);
    }
  }
  if (run.simulated) {
    const Eigen::VectorXd* d = run.simulated->properties.find_vertex("deviation_mm");
    const auto path = run.dir / "predicted.png";
    write_png(path, encode_png(shape_picture(run.simulated->mesh.V, run.simulated->mesh.F,
                                             d ? *d : Eigen::VectorXd(), pixels)));
    written.push_back(path);
  }
  if (run.print && !run.print->toolpath.layers.empty()) {
    PreviewOptions options;
    if (run.flat) options.outline = outline(*run.flat);
    options.travels = false;
    options.panel_pixels = pixels * 3 / 8;
    options.max_panels = 16;
    const auto path = run.dir / "layers.png";
    write_png(path, overview_png(run.print->toolpath, options));
    written.push_back(path);
  }
  return written;
}

std::vector<std::filesystem::path> write_report(const std::filesystem::path& run_dir,
                                                const std::string& name, int pixels) {
  RunFolder run = read_run_folder(run_dir);
  if (!name.empty()) run.name = name;
  const std::string html = report_html(run);
  const auto path = run_dir / "report.html";
  write_file_atomically(path, true, [&](std::ostream& out) { out << html; });
  std::vector<std::filesystem::path> written{path};
  for (auto& p : write_report_pictures(run, pixels)) written.push_back(std::move(p));
  return written;
}

}  // namespace flatmorph
