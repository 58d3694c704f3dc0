#include "methods/origami/solid_estimate.h"

#include <fcntl.h>
#include <fmt/core.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <numbers>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "common/file_text.h"
#include "mesh/io.h"

extern char** environ;

namespace flatmorph {
namespace {

Eigen::Vector3d corner(const Polyhedron& solid, int v) { return solid.V.row(v).transpose(); }

// Runs `argv` with its output thrown away; false when it cannot start, fails or outlasts
// `timeout_s` (then it is killed).
bool run_quietly(const std::vector<std::string>& argv, double timeout_s, std::string& why) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    why = fmt::format("{} is not installed", argv[0]);
    return false;
  }
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
        timeout_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      why = fmt::format("{} took longer than {:.0f} s", argv[0], timeout_s);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    why = fmt::format("{} failed (exit status {})", argv[0],
                      WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return false;
  }
  return true;
}

// "1d 2h 3m 4s", any part left out.
double parse_duration(const std::string& text) {
  static const std::regex part(R"((\d+)\s*([dhms]))");
  double seconds = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), part); it != std::sregex_iterator();
       ++it) {
    const double value = std::stod((*it)[1]);
    switch ((*it)[2].str()[0]) {
      case 'd':
        seconds += 86400 * value;
        break;
      case 'h':
        seconds += 3600 * value;
        break;
      case 'm':
        seconds += 60 * value;
        break;
      default:
        seconds += value;
    }
  }
  return seconds;
}

}  // namespace

double polyhedron_volume(const Polyhedron& solid) {
  double six_volume = 0;
  for (const std::vector<int>& face : solid.faces) {
    const Eigen::Vector3d a = corner(solid, face[0]);
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      six_volume += a.dot(corner(solid, face[k]).cross(corner(solid, face[k + 1])));
    }
  }
  return six_volume / 6;
}

double polyhedron_area(const Polyhedron& solid) {
  double area = 0;
  for (const std::vector<int>& face : solid.faces) {
    Eigen::Vector3d twice = Eigen::Vector3d::Zero();  // Newell: exact for a planar polygon
    for (size_t k = 0; k < face.size(); ++k) {
      twice += corner(solid, face[k]).cross(corner(solid, face[(k + 1) % face.size()]));
    }
    area += 0.5 * twice.norm();
  }
  return area;
}

SolidPrintEstimate estimate_solid_print(const Polyhedron& solid, const Material& material,
                                        double filament_diameter,
                                        const SolidPrintSettings& settings) {
  SolidPrintEstimate out;
  out.volume = std::max(0.0, polyhedron_volume(solid));
  const double shells = std::min(out.volume, polyhedron_area(solid) * settings.shell_mm);
  out.printed = out.volume > 0 ? shells + settings.infill * (out.volume - shells)
                               : polyhedron_area(solid) * settings.shell_mm;
  const double filament_area = std::numbers::pi * filament_diameter * filament_diameter / 4;
  out.filament_mm = out.printed / filament_area;
  out.filament_g = out.printed * material.density / 1000;
  out.time_s = out.printed / (settings.line_width * settings.layer_height * settings.speed) *
               (1 + settings.overhead);
  out.source = fmt::format(
      "estimate: {:.1f} mm shells, {:.0f} % infill, {:.2f} x {:.2f} mm beads at {:.0f} mm/s, "
      "+{:.0f} % for travels, no supports",
      settings.shell_mm, 100 * settings.infill, settings.line_width, settings.layer_height,
      settings.speed, 100 * settings.overhead);
  return out;
}

std::optional<SolidPrintEstimate> read_slicer_estimate(const std::string& gcode) {
  static const std::regex time_line(R"(;\s*estimated printing time \(normal mode\)\s*=\s*(.+))");
  static const std::regex mm_line(R"(;\s*filament used \[mm\]\s*=\s*([0-9.eE+-]+))");
  static const std::regex g_line(R"(;\s*filament used \[g\]\s*=\s*([0-9.eE+-]+))");
  SolidPrintEstimate out;
  bool has_time = false;
  std::istringstream lines(gcode);
  std::smatch m;
  for (std::string line; std::getline(lines, line);) {
    if (std::regex_search(line, m, time_line)) {
      out.time_s = parse_duration(m[1]);
      has_time = true;
    } else if (std::regex_search(line, m, mm_line)) {
      out.filament_mm = std::stod(m[1]);
    } else if (std::regex_search(line, m, g_line)) {
      out.filament_g = std::stod(m[1]);
    }
  }
  if (!has_time) return std::nullopt;
  return out;
}

std::optional<SolidPrintEstimate> slicer_solid_print(const Polyhedron& solid,
                                                     double filament_diameter, double timeout_s,
                                                     std::string* why) {
  std::string reason;
  std::string folder = (std::filesystem::temp_directory_path() / "flatmorph-solid-XXXXXX").string();
  if (!mkdtemp(folder.data())) {
    if (why) *why = "no temporary folder";
    return std::nullopt;
  }
  const std::filesystem::path dir(folder);
  std::optional<SolidPrintEstimate> out;
  try {
    Mesh mesh;  // the faces as fans: a slicer reads triangles
    std::vector<Eigen::Vector3i> triangles;
    for (const std::vector<int>& face : solid.faces) {
      for (size_t k = 1; k + 1 < face.size(); ++k)
        triangles.emplace_back(face[0], face[k], face[k + 1]);
    }
    mesh.V = solid.V;
    mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
    for (size_t i = 0; i < triangles.size(); ++i)
      mesh.F.row(static_cast<Eigen::Index>(i)) = triangles[i];
    write_obj(dir / "solid.obj", mesh);
    if (run_quietly({"prusa-slicer", "--export-gcode", "--filament-diameter",
                     fmt::format("{}", filament_diameter), "--output",
                     (dir / "solid.gcode").string(), (dir / "solid.obj").string()},
                    timeout_s, reason)) {
      out = read_slicer_estimate(read_file_text(dir / "solid.gcode", "slicer's G-code"));
      if (out) {
        out->volume = polyhedron_volume(solid);
        out->printed =
            out->filament_mm * std::numbers::pi * filament_diameter * filament_diameter / 4;
        out->source = "PrusaSlicer, its default settings";
      } else {
        reason = "prusa-slicer wrote no time estimate";
      }
    }
  } catch (const std::exception& e) {
    reason = e.what();
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  if (!out && why) *why = reason;
  return out;
}

}  // namespace flatmorph
