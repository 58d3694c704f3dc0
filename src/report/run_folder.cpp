#include "report/run_folder.h"

#include <fmt/core.h>

#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {

RunFolder read_run_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: not a folder; give the output folder (-o DIR) of flatmorph "
                                "design",
                                dir.string()));
  }
  RunFolder run;
  run.dir = dir;
  run.name = dir.filename().string();
  if (run.name.empty()) run.name = dir.parent_path().filename().string();
  auto exists = [&](const char* name) {
    const bool found = std::filesystem::is_regular_file(dir / name, ec);
    if (!found) run.missing.emplace_back(name);
    return found;
  };
  // A plate without a stack file (an older run) is shown with the default stack: the report only
  // draws its plate and design fields.
  if (exists("flat.ply")) run.flat = read_plate_design(dir / "flat.ply", Material{}, 10).design;
  if (exists("target.ply")) run.target = read_mesh(dir / "target.ply");
  if (exists("simulated.ply")) run.simulated = read_mesh(dir / "simulated.ply");
  if (std::filesystem::is_regular_file(dir / "gcode_simulated.ply", ec)) {
    run.gcode_simulated = read_mesh(dir / "gcode_simulated.ply");
  }
  if (exists("design.json")) {
    run.design =
        nlohmann::ordered_json::parse(read_file_text(dir / "design.json", "file"), nullptr, false);
    if (run.design.is_discarded() || !run.design.is_object()) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: not a JSON object; run flatmorph design again to rewrite it",
                                  (dir / "design.json").string()));
    }
  }
  if (exists("toolpath.json")) run.print = read_toolpath_file(dir / "toolpath.json");
  // Only plain .svg names of this folder: a design.json edited to point elsewhere reads nothing.
  if (const auto it = run.design.is_object() ? run.design.find("drawings") : run.design.end();
      it != run.design.end() && it->is_array()) {
    for (const auto& entry : *it) {
      if (!entry.is_string()) continue;
      const std::string name = entry.get<std::string>();
      const std::filesystem::path path(name);
      if (path.filename() != path || path.extension() != ".svg") continue;
      if (!std::filesystem::is_regular_file(dir / path, ec)) {
        run.missing.push_back(name);
        continue;
      }
      run.drawings.emplace_back(name, read_file_text(dir / path, "drawing"));
    }
  }
  if (!run.design.is_object() && run.missing.size() == 5) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: no flat.ply, target.ply, simulated.ply, design.json or "
                                "toolpath.json here; give the output folder (-o DIR) of flatmorph "
                                "design",
                                dir.string()));
  }
  return run;
}

}  // namespace flatmorph
