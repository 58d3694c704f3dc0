// The sheet's two-material toolpath (notes §8), from the toolpath and, through the G-code writer,
// from the G-code as the tests' own reader replays it: faces of 20 x 20 mm joined by 10 mm wide
// actuators, case A, case B, both in one sheet, and turned so that the hinge runs at 30° to x.
#include "methods/origami/origami_toolpath.h"
#include "common/angles.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "gcode/gcode_check.h"
#include "gcode/gcode_replay.h"
#include "gcode/gcode_writer.h"
#include "material/material.h"

namespace flatmorph::origami_toolpath_test {
namespace {

constexpr double kActiveSpeed = 5000.0 / 60;  // mm/s, the paper's samples

Eigen::Matrix2d rotation(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

Eigen::MatrixX2d square(double x0, double x1, const Eigen::Matrix2d& turn) {
  Eigen::MatrixX2d p(4, 2);
  p << x0, 0, x1, 0, x1, 20, x0, 20;
  return (p * turn.transpose()).eval();
}

// Faces [0, 20] x [0, 20], [30, 50] x [0, 20], ... in a row along x, each joined to the next by a
// 10 mm actuator whose hinge runs along y; `case_a[i]` is the stacking of actuator i. The whole
// sheet turned by `angle` about the origin.
ActuatedSheet row_of_faces(const std::vector<bool>& case_a, double angle = 0) {
  const Eigen::Matrix2d turn = rotation(angle);
  ActuatedSheet sheet;
  sheet.name = "row";
  for (size_t f = 0; f <= case_a.size(); ++f)
    sheet.faces.push_back(square(30.0 * f, 30.0 * f + 20, turn));
  for (size_t i = 0; i < case_a.size(); ++i) {
    Actuator a;
    a.hinge.crease = static_cast<int>(i);
    a.hinge.fold_angle = case_a[i] ? -std::numbers::pi / 2 : std::numbers::pi / 2;
    a.hinge.width = 10;
    a.hinge.radius = 10 / (std::numbers::pi / 2);
    a.hinge.pla_on_bed = case_a[i];
    a.hinge.pla_speed = kActiveSpeed;
    a.parent_face = static_cast<int>(i);
    a.child_face = static_cast<int>(i) + 1;
    const double x = 30.0 * i + 20;
    // Corners 0, 1 on the parent's edge, 2, 3 on the child's, counter-clockwise.
    Eigen::MatrixX2d q(4, 2);
    q << x, 20, x, 0, x + 10, 0, x + 10, 20;
    a.quad = q * turn.transpose();
    a.across = turn * Eigen::Vector2d::UnitX();
    sheet.actuators.push_back(a);
  }
  return sheet;
}

// An actuator's area as the design puts it, in its own frame: s across the hinge from the
// parent's edge, t along it from the quad's corner 1; the quad is s in [0, 10], t in [0, 20].
struct Frame {
  Eigen::Vector2d origin, across, along;
  Eigen::Vector2d local(const Eigen::Vector2d& p) const {
    return {(p - origin).dot(across), (p - origin).dot(along)};
  }
};

Frame frame_of(const Actuator& a, const Eigen::Vector2d& plate_to_bed = Eigen::Vector2d::Zero()) {
  return {a.quad.row(1).transpose() + plate_to_bed, a.across,
          Eigen::Vector2d(-a.across.y(), a.across.x())};
}

// Whether the local point lies in the quad grown by the 1 mm margins, within `slack` mm.
bool in_grown(const Eigen::Vector2d& st, double slack) {
  return st.x() >= -1 - slack && st.x() <= 11 + slack && st.y() >= -slack && st.y() <= 20 + slack;
}

// The angle between a segment and a direction, as lines (0 to 90 degrees).
double line_angle(const Eigen::Vector2d& d, const Eigen::Vector2d& dir) {
  return std::acos(std::min(1.0, std::abs(d.normalized().dot(dir)))) / kDegree;
}

struct Bead {
  Eigen::Vector2d a, b;
  int tool = 0;
  int layer = 0;
};

std::vector<Bead> beads_of(const Toolpath& toolpath) {
  std::vector<Bead> beads;
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    for (const PathPolyline& path : toolpath.layers[k].paths) {
      for (size_t i = 0; i < path.segments.size(); ++i) {
        if (path.segments[i].travel) continue;
        beads.push_back({path.points.row(i).head<2>().transpose(),
                         path.points.row(i + 1).head<2>().transpose(), path.segments[i].tool,
                         static_cast<int>(k)});
      }
    }
  }
  return beads;
}

std::vector<Bead> beads_of(const testing::ReadGcode& read) {
  std::vector<Bead> beads;
  for (size_t k = 0; k < read.layers.size(); ++k) {
    for (const testing::ReadExtrusion& e : read.layers[k].extrusions) {
      if (e.type == "Skirt/Brim" || e.type == "Wipe tower") continue;
      beads.push_back({{e.x0, e.y0}, {e.x1, e.y1}, e.tool, static_cast<int>(k)});
    }
  }
  return beads;
}

// What notes §8 asks of every actuator, from the beads (wherever they come from): in its active
// layers, PLA beads reaching into its area run across the hinge within 2° and span the quad and
// both margins; in its constraint layers, no PLA reaches into the area, and TPU covers it along
// the hinge; TPU nowhere else. `slack`: the rounding of the coordinates read (mm).
void expect_actuators_as_designed(const std::vector<Bead>& beads, const ActuatedSheet& sheet,
                                  const Eigen::Vector2d& plate_to_bed, double slack) {
  const double w = 0.4;
  for (const Actuator& a : sheet.actuators) {
    SCOPED_TRACE("actuator of crease " + std::to_string(a.hinge.crease));
    const Frame frame = frame_of(a, plate_to_bed);
    for (int k = 0; k < 4; ++k) {
      SCOPED_TRACE("layer " + std::to_string(k + 1));
      const bool active = a.hinge.pla_on_bed ? k < 3 : k >= 1;
      double s_min = 1e9, s_max = -1e9;
      std::set<long> rows;  // the active lines' offsets along the hinge, in µm
      double tpu_length = 0;
      for (const Bead& bead : beads) {
        if (bead.layer != k) continue;
        const Eigen::Vector2d p = frame.local(bead.a), q = frame.local(bead.b);
        // Inside the area by more than the rounding: the bead's centre line enters it.
        const bool enters =
            in_grown(p, -slack) || in_grown(q, -slack) || in_grown((p + q) / 2, -slack);
        if (bead.tool == 0 && enters) {
          EXPECT_TRUE(active) << "PLA in the constraint layer at (" << p.transpose() << ")";
          EXPECT_LT(line_angle(q - p, Eigen::Vector2d::UnitX()), 2.0)
              << "PLA along (" << (q - p).transpose() << ") in the area";
          EXPECT_TRUE(in_grown(p, slack) && in_grown(q, slack))
              << p.transpose() << " " << q.transpose();
          s_min = std::min({s_min, p.x(), q.x()});
          s_max = std::max({s_max, p.x(), q.x()});
          rows.insert(std::lround((p.y() + q.y()) / 2 * 1000));
        }
        if (bead.tool == 1 && enters) {
          EXPECT_FALSE(active) << "TPU in an active layer";
          EXPECT_LT(line_angle(q - p, Eigen::Vector2d::UnitY()), 2.0);
          tpu_length += (q - p).norm();
        }
      }
      if (active) {
        // From half a bead inside the 1 mm margin in the parent to the same in the child.
        EXPECT_NEAR(s_min, -1 + w / 2, slack + 1e-6);
        EXPECT_NEAR(s_max, 11 - w / 2, slack + 1e-6);
        EXPECT_EQ(rows.size(), 50u);  // 20 mm of hinge in 0.4 mm beads
        EXPECT_NEAR(*rows.begin() / 1000.0, w / 2, slack + 1e-6);
        EXPECT_NEAR(*rows.rbegin() / 1000.0, 20 - w / 2, slack + 1e-6);
      } else {
        // 12 x 20 mm in 0.4 mm beads: 30 lines of 19.6 mm.
        EXPECT_NEAR(tpu_length, 30 * 19.6, 30 * 2 * slack + 1e-6);
      }
    }
  }
  // TPU lies in some actuator's area and nowhere else.
  for (const Bead& bead : beads) {
    if (bead.tool != 1) continue;
    bool inside = false;
    for (const Actuator& a : sheet.actuators) {
      const Frame frame = frame_of(a, plate_to_bed);
      inside =
          inside || (in_grown(frame.local(bead.a), slack) && in_grown(frame.local(bead.b), slack));
    }
    EXPECT_TRUE(inside) << bead.a.transpose() << " -> " << bead.b.transpose();
  }
}

// The tools in print order, one entry per run.
std::vector<int> tool_runs(const std::vector<Bead>& beads) {
  std::vector<int> runs;
  for (const Bead& bead : beads) {
    if (runs.empty() || runs.back() != bead.tool) runs.push_back(bead.tool);
  }
  return runs;
}

TEST(OrigamiToolpath, CaseAPrintsThreeActiveLayersThenTPU) {
  const ActuatedSheet sheet = row_of_faces({true});
  const Toolpath toolpath = origami_toolpath(sheet);
  ASSERT_EQ(toolpath.layers.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(toolpath.layers[k].z, 0.2 * (k + 1), 1e-12);
    EXPECT_EQ(toolpath.layers[k].height, 0.2);
  }
  const std::vector<Bead> beads = beads_of(toolpath);
  expect_actuators_as_designed(beads, sheet, Eigen::Vector2d::Zero(), 2e-3);
  // PLA in layers 1-3, then layer 4: PLA, then TPU; one change.
  EXPECT_EQ(tool_runs(beads), (std::vector<int>{0, 1}));
  for (const Bead& bead : beads) {
    if (bead.tool == 1) {
      EXPECT_EQ(bead.layer, 3);
    }
  }
}

TEST(OrigamiToolpath, CaseBPrintsTPUOnTheBedThenThreeActiveLayers) {
  const ActuatedSheet sheet = row_of_faces({false});
  const std::vector<Bead> beads = beads_of(origami_toolpath(sheet));
  expect_actuators_as_designed(beads, sheet, Eigen::Vector2d::Zero(), 2e-3);
  // Layer 1: TPU, then PLA; layers 2-4 PLA: one change.
  EXPECT_EQ(tool_runs(beads), (std::vector<int>{1, 0}));
  for (const Bead& bead : beads) {
    if (bead.tool == 1) {
      EXPECT_EQ(bead.layer, 0);
    }
  }
}

TEST(OrigamiToolpath, BothCasesInOneSheetChangeMaterialTwice) {
  const ActuatedSheet sheet = row_of_faces({true, false});
  const std::vector<Bead> beads = beads_of(origami_toolpath(sheet));
  expect_actuators_as_designed(beads, sheet, Eigen::Vector2d::Zero(), 2e-3);
  // Layer 1 TPU (case B), PLA; layers 2-3 PLA; layer 4 PLA, TPU (case A).
  EXPECT_EQ(tool_runs(beads), (std::vector<int>{1, 0, 1}));
  // Each layer starts with the material the layer below ended with.
  for (size_t i = 1; i < beads.size(); ++i) {
    if (beads[i].layer != beads[i - 1].layer) {
      EXPECT_EQ(beads[i].tool, beads[i - 1].tool);
    }
  }
}

TEST(OrigamiToolpath, FacesAreSolidAndStopWhereTheActuatorBegins) {
  const ActuatedSheet sheet = row_of_faces({true});
  const Toolpath toolpath = origami_toolpath(sheet);
  const Frame frame = frame_of(sheet.actuators[0]);
  for (int k = 0; k < 4; ++k) {
    // The face beads: PLA outside the actuator's area, and the nearest ones half a bead from it
    // on both sides (beads touch: no gap, no double extrusion).
    double parent_edge = -1e9, child_edge = 1e9;
    for (const Bead& bead : beads_of(toolpath)) {
      if (bead.layer != k || bead.tool != 0) continue;
      const Eigen::Vector2d p = frame.local(bead.a), q = frame.local(bead.b);
      if (in_grown(p, -1e-3) || in_grown(q, -1e-3)) continue;  // active lines
      for (const Eigen::Vector2d& x : {p, q}) {
        if (x.x() < 5) parent_edge = std::max(parent_edge, x.x());
        if (x.x() > 5) child_edge = std::min(child_edge, x.x());
      }
    }
    EXPECT_NEAR(parent_edge, -1 - 0.2, 1e-3);
    EXPECT_NEAR(child_edge, 11 + 0.2, 1e-3);
  }
  // The fill of a face, parent side: 19 x 20 mm, a loop half a bead in, then lines a bead in.
  // Lines along x in layer 1, along y in layer 2.
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d dir = k == 0 ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY();
    int along = 0, other = 0;
    for (const PathPolyline& path : toolpath.layers[static_cast<size_t>(k)].paths) {
      if (path.type != PathType::kSolidInfill || path.segments[0].tool != 0) continue;
      const Eigen::Vector2d d = (path.points.row(1) - path.points.row(0)).head<2>().transpose();
      const Eigen::Vector2d mid =
          (path.points.row(0) + path.points.row(1)).head<2>().transpose() / 2;
      if (in_grown(frame.local(mid), 0)) continue;
      (line_angle(d, dir) < 1e-6 ? along : other) += 1;
    }
    EXPECT_GT(along, 40);
    EXPECT_EQ(other, 0);
  }
  // The volume printed: every layer covers the faces and the actuator (50 x 20 mm), less the
  // round ends of the lines (a bead's length counts from centre to centre), never more.
  for (const ToolpathLayer& layer : toolpath.layers) {
    const double fill = extrusion_volume(layer) / (0.2 * 50 * 20);
    EXPECT_GT(fill, 0.97);
    EXPECT_LT(fill, 1);
  }
}

TEST(OrigamiToolpath, AHingeAt30DegreesTurnsItsLines) {
  // The hinge along y turned by -60 degrees runs at 30 degrees to x.
  const double angle = -60 * kDegree;
  const ActuatedSheet turned = row_of_faces({true}, angle);
  const Eigen::Vector2d hinge(-turned.actuators[0].across.y(), turned.actuators[0].across.x());
  EXPECT_NEAR(std::atan2(hinge.y(), hinge.x()) / kDegree, 30, 1e-9);
  const Toolpath toolpath = origami_toolpath(turned);
  expect_actuators_as_designed(beads_of(toolpath), turned, Eigen::Vector2d::Zero(), 2e-3);
  // The actuator's own lines are those of the unturned sheet, turned: the same length in each
  // layer (the faces' lines stay along x and y, so they differ).
  const Toolpath straight = origami_toolpath(row_of_faces({true}));
  for (int k = 0; k < 4; ++k) {
    auto actuator_length = [&](const Toolpath& t, const ActuatedSheet& s) {
      const Frame frame = frame_of(s.actuators[0]);
      double length = 0;
      for (const Bead& bead : beads_of(t)) {
        if (bead.layer == k && in_grown(frame.local((bead.a + bead.b) / 2), -1e-3)) {
          length += (bead.b - bead.a).norm();
        }
      }
      return length;
    };
    EXPECT_NEAR(actuator_length(toolpath, turned), actuator_length(straight, row_of_faces({true})),
                0.05);
  }
}

TEST(OrigamiToolpath, RefusesBadSettings) {
  const ActuatedSheet sheet = row_of_faces({true});
  OrigamiPrintSettings s;
  s.tpu_tool = s.pla_tool;
  EXPECT_THROW(origami_toolpath(sheet, s), std::invalid_argument);
  s = {};
  s.line_width = 0;
  EXPECT_THROW(origami_toolpath(sheet, s), std::invalid_argument);
  ActuatedSheet slow = sheet;
  slow.actuators[0].hinge.pla_speed = 0;
  EXPECT_THROW(origami_toolpath(slow), std::invalid_argument);
  EXPECT_THROW(origami_toolpath(ActuatedSheet{}), std::invalid_argument);
}

// PLA on T0 and TPU on T1, at temperatures the check can tell apart.
std::vector<Material> pla_tpu() {
  return {load_material("pla-generic"), load_material("tpu-generic")};
}

struct Printed {
  GcodeResult gcode;
  testing::ReadGcode read;
};

Printed print(const ActuatedSheet& sheet, const std::string& printer_name) {
  const PrinterProfile printer = load_printer(printer_name);
  Printed p;
  p.gcode = make_gcode(origami_toolpath(sheet), printer, pla_tpu());
  p.read = testing::read_gcode(p.gcode.text);
  EXPECT_TRUE(check_gcode(p.gcode.text, printer, pla_tpu()).empty());
  return p;
}

// Every bead is printed at its material's own temperature.
void expect_material_temperatures(const testing::ReadGcode& read, bool own_heaters) {
  const std::vector<Material> materials = pla_tpu();
  int beads = 0;
  for (const testing::ReadLayer& layer : read.layers) {
    for (const testing::ReadExtrusion& e : layer.extrusions) {
      const double target = own_heaters ? e.nozzle_target : e.heater_target;
      EXPECT_EQ(target, materials[static_cast<size_t>(e.tool)].nozzle_temperature)
          << "T" << e.tool << " at " << e.x0 << ", " << e.y0;
      ++beads;
    }
  }
  EXPECT_GT(beads, 500);
}

TEST(OrigamiToolpath, TwoToolGcodeReadsBackAsDesigned) {
  // Case A, case B, both: changes as notes §8 says, plus one at the start when the print begins
  // with TPU (the start G-code leaves T0 in use).
  const std::vector<std::pair<std::vector<bool>, size_t>> cases = {
      {{true}, 1}, {{false}, 2}, {{true, false}, 3}};
  for (const auto& [stacking, changes] : cases) {
    SCOPED_TRACE(stacking.size() == 2 ? "both" : stacking[0] ? "case A" : "case B");
    const ActuatedSheet sheet = row_of_faces(stacking, stacking.size() == 1 ? -60 * kDegree : 0);
    const Printed p = print(sheet, "prusa-xl-2t");
    expect_actuators_as_designed(beads_of(p.read), sheet, p.gcode.plate_to_bed, 3e-3);
    EXPECT_EQ(p.read.tool_changes.size(), changes);
    EXPECT_EQ(p.gcode.tool_changes, static_cast<int>(changes));
    expect_material_temperatures(p.read, true);
  }
}

TEST(OrigamiToolpath, OneNozzleGcodePausesForEachSwap) {
  const std::vector<std::pair<std::vector<bool>, size_t>> cases = {
      {{true}, 1}, {{false}, 2}, {{true, false}, 3}};
  for (const auto& [stacking, changes] : cases) {
    SCOPED_TRACE(stacking.size() == 2 ? "both" : stacking[0] ? "case A" : "case B");
    const ActuatedSheet sheet = row_of_faces(stacking);
    const Printed p = print(sheet, "prusa-mk4");
    expect_actuators_as_designed(beads_of(p.read), sheet, p.gcode.plate_to_bed, 3e-3);
    EXPECT_TRUE(p.read.tool_changes.empty());  // no T command on a one-tool printer
    ASSERT_EQ(p.read.filament_swaps.size(), changes);
    ASSERT_EQ(p.read.pauses.size(), changes);
    for (size_t i = 0; i < changes; ++i) {
      // Each swap pauses (M600) before anything more is printed.
      EXPECT_GT(p.read.pauses[i], p.read.filament_swaps[i].line);
      if (i + 1 < changes) {
        EXPECT_LT(p.read.pauses[i], p.read.filament_swaps[i + 1].line);
      }
      EXPECT_EQ(p.read.lines[static_cast<size_t>(p.read.pauses[i]) - 1].rfind("M600", 0), 0u);
    }
    expect_material_temperatures(p.read, false);
  }
}

TEST(OrigamiToolpath, OneFilePerMaterialForPrintersThatCannotPause) {
  // Case B on a printer without a filament swap: the TPU of layer 1 (F1), then all the PLA (F2).
  const PrinterProfile printer = load_printer("creality-ender3-v2");
  const std::vector<MaterialFile> files =
      make_material_files(origami_toolpath(row_of_faces({false})), printer, pla_tpu());
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].tool, 1);
  EXPECT_EQ(files[0].first_layer, 0u);
  EXPECT_EQ(files[0].last_layer, 0u);
  EXPECT_EQ(files[1].tool, 0);
  EXPECT_EQ(files[1].first_layer, 0u);
  EXPECT_EQ(files[1].last_layer, 3u);
  const std::vector<Material> materials = pla_tpu();
  for (const MaterialFile& file : files) {
    const Material& m = materials[static_cast<size_t>(file.tool)];
    EXPECT_TRUE(check_gcode(file.gcode.text, printer, {m}).empty()) << file.label;
    EXPECT_NE(file.gcode.text.find(fmt::format("M109 S{:g}", m.nozzle_temperature)),
              std::string::npos);
  }
}

TEST(OrigamiToolpath, CheckCatchesAFileAtTheWrongTemperature) {
  const ActuatedSheet sheet = row_of_faces({true});
  const std::vector<Material> materials = pla_tpu();
  auto kinds = [&](const std::string& text, const std::string& printer) {
    std::set<std::string> found;
    for (const GcodeViolation& v : check_gcode(text, load_printer(printer), materials)) {
      found.insert(std::string(to_string(v.kind)));
    }
    return found;
  };
  auto replace_all = [](std::string text, const std::string& from, const std::string& to) {
    for (size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
    return text;
  };
  // Two tools: T1 heated to PLA's temperature.
  const std::string xl = print(sheet, "prusa-xl-2t").gcode.text;
  ASSERT_NE(xl.find("M109 T1 S225"), std::string::npos);
  EXPECT_TRUE(kinds(replace_all(xl, "T1 S225", "T1 S200"), "prusa-xl-2t").count("cold-extrusion"));
  // One nozzle: the swap to TPU without its temperature (the nozzle stays at PLA's).
  const std::string mk4 = print(sheet, "prusa-mk4").gcode.text;
  const std::string wait = "M109 S225 ; wait: pla-generic unloads and tpu-generic purges at this\n";
  ASSERT_NE(mk4.find(wait), std::string::npos);
  const std::string no_wait = replace_all(mk4, wait, "");
  EXPECT_TRUE(kinds(no_wait, "prusa-mk4").count("swap-temperature"));
  EXPECT_TRUE(kinds(no_wait, "prusa-mk4").count("cold-extrusion"));
  // ... or set to PLA's after the swap.
  EXPECT_EQ(kinds(replace_all(mk4, "M109 S225", "M109 S200"), "prusa-mk4"),
            std::set<std::string>{"cold-extrusion"});
}

}  // namespace
}  // namespace flatmorph::origami_toolpath_test
