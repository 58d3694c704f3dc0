#include "run/run_folder.h"

#include <fmt/core.h>

#include <cmath>

#include "common/atomic_file.h"
#include "common/error.h"
#include "mesh/io.h"
#include "report/report.h"

namespace flatmorph {

// A folder a user may keep other files in: replacing it would delete them.
void require_run_folder_destination(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) return;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: exists and is not a folder; choose another -o", dir.string()));
  }
  if (std::filesystem::is_empty(dir, ec)) return;
  for (const char* name : {"design.json", "flat.ply", "plate.gcode", "report.html"}) {
    if (std::filesystem::exists(dir / name, ec)) return;
  }
  throw UserError(ErrorCategory::kFile,
                  fmt::format("{}: the folder holds other files and no earlier run; a run "
                              "replaces its whole folder, so choose a new or empty folder for -o",
                              dir.string()));
}

nlohmann::ordered_json run_record(const RunOutputs& run) {
  nlohmann::ordered_json j =
      run.parameters.is_object() ? run.parameters : nlohmann::ordered_json::object();
  j["method"] = run.method;
  j["flatmorph_version"] = FLATMORPH_VERSION;
  j["metrics"] = run.metrics.is_object() ? run.metrics : nlohmann::ordered_json::object();
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const RunMetric& m : run.metric_list) {
    list.push_back({{"name", m.name},
                    {"value", std::isfinite(m.value) ? nlohmann::ordered_json(m.value)
                                                     : nlohmann::ordered_json()},
                    {"unit", m.unit}});
  }
  j["metrics_list"] = list;
  return j;
}

void write_run_folder(const std::filesystem::path& dir, const RunOutputs& run,
                      const PrinterProfile* printer, const ProgressCallback& progress) {
  if (run.print && printer == nullptr) {
    throw std::invalid_argument("write_run_folder: a run with a print needs its printer");
  }
  require_run_folder_destination(dir);
  if (dir.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(dir.parent_path(), ec);
    if (ec) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: cannot create the output folder ({}); choose another -o",
                                  dir.parent_path().string(), ec.message()));
    }
  }
  // "out/." or "out/" name the folder itself.
  const std::filesystem::path folder =
      dir.filename().empty() || dir.filename() == "." ? dir.parent_path() : dir;
  write_folder_atomically(folder, [&](const std::filesystem::path& tmp) {
    write_plate_design(tmp / "flat.ply", run.plate);
    if (run.target) write_ply(tmp / "target.ply", *run.target);
    if (run.predicted) {
      MeshProperties properties;
      if (run.predicted_deviation_mm.size() > 0) {
        properties.set_vertex("deviation_mm", run.predicted_deviation_mm);
      }
      write_ply(tmp / "simulated.ply", *run.predicted, properties);
    }
    if (run.gcode_predicted) {
      MeshProperties properties;
      if (run.gcode_predicted_deviation_mm.size() > 0) {
        properties.set_vertex("deviation_mm", run.gcode_predicted_deviation_mm);
      }
      write_ply(tmp / "gcode_simulated.ply", *run.gcode_predicted, properties);
    }
    if (run.print) write_print_files(tmp, *run.print, *printer, run.plate.stack);
    for (const RunFile& file : run.files) {
      write_file_atomically(tmp / file.name, true, [&](std::ostream& out) {
        out.write(file.bytes.data(), file.bytes.size());
      });
    }
    const std::string record = run_record(run).dump(2) + "\n";
    write_file_atomically(tmp / "design.json", false, [&](std::ostream& out) { out << record; });
    // Last, so that it shows every file above.
    report_progress(progress, {"report", 0, 0, NAN, "report.html and pictures"});
    write_report(tmp, folder.filename().string());
  });
}

std::vector<std::string> drawing_names(const std::vector<RunFile>& files, std::string_view prefix) {
  std::vector<std::string> names;
  for (const RunFile& file : files) {
    if (file.name.starts_with(prefix) && file.name.ends_with(".svg")) names.push_back(file.name);
  }
  return names;
}

std::vector<RunMetric> run_metric_list(const nlohmann::ordered_json& metrics) {
  constexpr std::pair<const char*, const char*> kUnits[] = {
      {"_pct", "% of the target's bounding-box diagonal"},
      {"_s", "s"},
      {"_rad", "rad"},
      {"_mm", "mm"},
      {"_g", "g"}};
  std::vector<RunMetric> list;
  for (const auto& [key, value] : metrics.items()) {
    if (!value.is_number() && !value.is_boolean()) continue;
    const char* unit = "";
    for (const auto& [suffix, name] : kUnits) {
      if (key.ends_with(suffix)) unit = name;
    }
    if (key.ends_with("area_pct") || key.ends_with("deviation_mean_pct")) unit = "%";
    if (key.ends_with("edges_pct")) unit = "% of the printing edges";
    if (key.starts_with("depth_error")) unit = "% of the depth the printed shrink gives";
    list.push_back(
        {key, value.is_boolean() ? (value.get<bool>() ? 1.0 : 0.0) : value.get<double>(), unit});
  }
  return list;
}

}  // namespace flatmorph
