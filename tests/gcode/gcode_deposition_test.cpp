// The G-code reader of src/gcode/gcode_reader.h: small files written here, each with the beads it
// must give (twins in different E modes give the same beads, arcs give chords on their circle,
// retractions deposit nothing), flatmorph's own files read back to the toolpath they were written
// from on every shipped printer, and hostile files give one clear error with their line.
#include "gcode/gcode_reader.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode_fixtures.h"

namespace flatmorph::gcode_deposition_test {
namespace {

constexpr double kArea = std::numbers::pi * 1.75 * 1.75 / 4;  // mm², 1.75 mm filament

// Filament (mm) for a bead of length × width × height (mm).
double filament(double length, double width, double height) {
  return length * width * height / kArea;
}

GcodeDeposition read(const std::string& text, const GcodeReadOptions& options = {}) {
  return read_gcode_deposition(text, "test.gcode", options);
}

// One step of a small print: a travel or a bead to (x, y, z), or an E move alone (retraction).
struct Step {
  enum Kind { kTravel, kBead, kE } kind;
  double x = 0, y = 0, z = 0;
  double width = 0, height = 0;  // kBead
  double e = 0;                  // kE: mm of filament, negative to retract
};

// The steps in absolute E (M82, with a G92 E0 halfway), relative E (M83), relative E by G91 (with
// relative x, y, z), and G91 with M82 after it (relative x, y, z, absolute E).
enum class Mode { kM82, kM83, kG91, kG91M82 };

std::string write_steps(const std::vector<Step>& steps, Mode mode) {
  std::string out = "G21\nG90\n";
  const bool relative_xyz = mode == Mode::kG91 || mode == Mode::kG91M82;
  const bool relative_e = mode == Mode::kM83 || mode == Mode::kG91;
  if (mode == Mode::kM82) out += "M82\n";
  if (mode == Mode::kM83) out += "M83\n";
  if (relative_xyz) out += "G0 X0 Y0 Z0\nG91\n";
  if (mode == Mode::kG91M82) out += "M82\n";
  double x = 0, y = 0, z = 0, e = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (mode == Mode::kM82 && i == steps.size() / 2) {
      out += "G92 E0\n";
      e = 0;
    }
    double de = s.e;
    if (s.kind == Step::kBead) {
      de = filament(std::hypot(s.x - x, s.y - y, s.z - z), s.width, s.height);
    }
    e += de;
    const double ex = relative_e ? de : e;
    const double px = relative_xyz ? s.x - x : s.x, py = relative_xyz ? s.y - y : s.y,
                 pz = relative_xyz ? s.z - z : s.z;
    if (s.kind == Step::kTravel) {
      out += fmt::format("G0 X{:.6f} Y{:.6f} Z{:.6f} F6000\n", px, py, pz);
    } else if (s.kind == Step::kBead) {
      out += fmt::format("G1 X{:.6f} Y{:.6f} Z{:.6f} E{:.12f} F1800\n", px, py, pz, ex);
    } else {
      out += fmt::format("G1 E{:.12f} F2400\n", ex);
    }
    if (s.kind != Step::kE) x = s.x, y = s.y, z = s.z;
  }
  return out;
}

std::vector<Step> two_layer_steps() {
  return {
      {Step::kTravel, 10, 10, 0.2},           {Step::kBead, 30, 10, 0.2, 0.45, 0.2},
      {Step::kBead, 30, 25, 0.2, 0.5, 0.2},   {Step::kE, 0, 0, 0, 0, 0, -0.8},
      {Step::kTravel, 40, 40, 0.2},           {Step::kE, 0, 0, 0, 0, 0, 0.8},
      {Step::kBead, 60, 45, 0.2, 0.42, 0.2},  {Step::kTravel, 60, 45, 0.35},
      {Step::kBead, 40, 40, 0.35, 0.4, 0.15},
  };
}

TEST(GcodeDepositionModes, AbsoluteAndRelativeETwinsGiveTheSameBeads) {
  const std::vector<Step> steps = two_layer_steps();
  const GcodeDeposition reference = read(write_steps(steps, Mode::kM82));
  ASSERT_EQ(reference.beads.size(), 4u);
  EXPECT_EQ(reference.num_layers, 2);
  EXPECT_EQ(reference.retractions, 1);
  // The widths of the steps, from E alone (no annotation): the rectangle model.
  const double widths[] = {0.45, 0.5, 0.42, 0.4};
  const double heights[] = {0.2, 0.2, 0.2, 0.15};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(reference.beads[i].width, widths[i], 1e-9) << i;
    EXPECT_NEAR(reference.beads[i].height, heights[i], 1e-9) << i;
    EXPECT_EQ(reference.beads[i].feed_rate, 1800);
  }
  for (const Mode mode : {Mode::kM83, Mode::kG91, Mode::kG91M82}) {
    SCOPED_TRACE(static_cast<int>(mode));
    const GcodeDeposition twin = read(write_steps(steps, mode));
    ASSERT_EQ(twin.beads.size(), reference.beads.size());
    EXPECT_EQ(twin.layer_z, reference.layer_z);
    for (size_t i = 0; i < twin.beads.size(); ++i) {
      const DepositedBead& a = twin.beads[i];
      const DepositedBead& b = reference.beads[i];
      EXPECT_LT((a.start - b.start).norm(), 1e-9) << i;
      EXPECT_LT((a.end - b.end).norm(), 1e-9) << i;
      EXPECT_NEAR(a.width, b.width, 1e-9) << i;
      EXPECT_NEAR(a.height, b.height, 1e-9) << i;
      EXPECT_NEAR(a.filament_mm3, b.filament_mm3, 1e-9) << i;
      EXPECT_EQ(a.layer, b.layer) << i;
    }
  }
}

// Marlin 2: G90 after M83 makes E absolute again; M83 after it makes it relative.
TEST(GcodeDepositionModes, G90SetsTheEModeUntilTheNextM82OrM83) {
  const GcodeDeposition d = read(fmt::format(
      "M83\nG1 X0 Y0 Z0.2\nG1 X10 E{0:.8f}\nG90\nG1 X20 E{1:.8f}\nM83\nG1 X30 E{0:.8f}\n",
      filament(10, 0.4, 0.2), 2 * filament(10, 0.4, 0.2)));
  ASSERT_EQ(d.beads.size(), 3u);
  for (const DepositedBead& bead : d.beads) EXPECT_NEAR(bead.width, 0.4, 1e-7);
}

TEST(GcodeDepositionModes, AG0ThatExtrudesDepositsLikeAG1) {
  const GcodeDeposition d =
      read(fmt::format("M83\nG0 X0 Y0 Z0.2\nG0 X10 E{:.8f}\nG0 X20\n", filament(10, 0.4, 0.2)));
  ASSERT_EQ(d.beads.size(), 1u);
  EXPECT_NEAR(d.beads[0].width, 0.4, 1e-7);
  EXPECT_EQ(d.beads[0].line, 3);
}

// Chords of the arcs of a file, by the line of their G2/G3.
std::vector<DepositedBead> chords_of(const GcodeDeposition& d, int line) {
  std::vector<DepositedBead> out;
  for (const DepositedBead& bead : d.beads) {
    if (bead.line == line) out.push_back(bead);
  }
  return out;
}

TEST(GcodeDepositionArcs, ArcsGiveChordsOnTheirCircle) {
  const Eigen::Vector2d c(50, 50);
  const double r = 10, pi = std::numbers::pi;
  const double e = 2.0;  // mm of filament per arc (about 0.4 mm wide beads)
  const std::string text = fmt::format(
      "M83\n"
      "G0 X60 Y50 Z0.2\n"               // 2
      "G2 X50 Y40 I-10 J0 E{0}\n"       // 3: a quarter, clockwise, by its centre
      "G3 X60 Y50 R10 E{0}\n"           // 4: back, anticlockwise, by its radius
      "G2 X60 Y50 I-10 J0 E{0}\n"       // 5: a full circle
      "G3 X40 Y50 Z0.3 I-10 J0 E{0}\n"  // 6: half a turn, rising 0.1 mm (helical)
      "G2 X50 Y40 R-10 E{0}\n",         // 7: three quarters (negative R: the long way)
      e);
  const GcodeDeposition d = read(text);
  EXPECT_EQ(d.num_layers, 1);
  const double sweeps[] = {pi / 2, pi / 2, 2 * pi, pi, 1.5 * pi};
  for (int line = 3; line <= 7; ++line) {
    SCOPED_TRACE(line);
    const std::vector<DepositedBead> chords = chords_of(d, line);
    ASSERT_GE(chords.size(), 4u);
    double length = 0, volume = 0, turned = 0;
    for (size_t i = 0; i < chords.size(); ++i) {
      const DepositedBead& chord = chords[i];
      for (const Eigen::Vector3d& p : {chord.start, chord.end}) {
        EXPECT_NEAR((p.head<2>() - c).norm(), r, 1e-6);
      }
      if (i > 0) {
        EXPECT_EQ(chord.start, chords[i - 1].end);
      }
      const Eigen::Vector2d a = chord.start.head<2>() - c, b = chord.end.head<2>() - c;
      const double angle = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
      // G2 turns clockwise (negative angles), G3 anticlockwise.
      EXPECT_EQ(angle < 0, line == 3 || line == 5 || line == 7);
      // The sagitta: how far the arc strays from the chord.
      EXPECT_LE(r - ((a + b) / 2).norm(), 0.005 + 1e-12);
      length += (b - a).norm();
      volume += chord.filament_mm3;
      turned += std::abs(angle);
      if (line == 6) {
        // z rises with the angle turned: helical interpolation.
        EXPECT_NEAR(chord.end.z(), 0.2 + 0.1 * turned / pi, 1e-9);
      }
    }
    const double arc = r * sweeps[line - 3];
    EXPECT_NEAR(turned, sweeps[line - 3], 1e-9);
    // A chord of angle θ is shorter than its arc by about θ²/24 of it, and its sagitta r θ²/8 is
    // at most 0.005 mm.
    EXPECT_LE(length, arc);
    EXPECT_GE(length, arc * (1 - 0.005 / (3 * r) * 1.01));
    EXPECT_NEAR(volume, e * kArea, 1e-9);
  }
  // The quarter by its centre passes through x > 50, y < 50; the long arc by R < 0 through
  // x > 50 too (it turns clockwise from 180 degrees down to -90).
  for (const DepositedBead& chord : chords_of(d, 3)) {
    EXPECT_GE(chord.end.x(), 50 - 1e-9);
    EXPECT_LE(chord.end.y(), 50 + 1e-9);
  }
  double max_x = -1;
  for (const DepositedBead& chord : chords_of(d, 7)) max_x = std::max(max_x, chord.end.x());
  EXPECT_NEAR(max_x, 60, 0.01);
}

TEST(GcodeDepositionRetraction, RetractionWipeAndUnretractDepositNothing) {
  const double a = filament(10, 0.45, 0.2), b = filament(20, 0.4, 0.2);
  const std::string start = fmt::format("M83\nG0 X10 Y10 Z0.2\nG1 X20 Y10 E{:.6f}\n", a);
  const std::string bead_b = fmt::format("G1 X60 Y10 E{:.6f}\n", b);
  const GcodeDeposition reference = read(start + "G0 X40 Y10\n" + bead_b);
  ASSERT_EQ(reference.beads.size(), 2u);
  EXPECT_EQ(reference.retractions, 0);
  const std::vector<std::pair<std::string, std::string>> variants = {
      {"retract, wipe, lift, travel, unretract",
       "G1 E-0.8 F2400\nG1 X25 Y10 E-0.2\nG0 Z0.6\nG0 X40 Y10\nG0 Z0.2\nG1 E1.0\n" + bead_b},
      {"wipe first, then retract (one retraction), unretract with an extra prime",
       "G1 X25 Y10 E-0.2\nG1 E-0.8\nG0 X40 Y10\nG1 E1.3\n" + bead_b},
      {"the refill in the next bead's own E",
       fmt::format("G1 E-1\nG0 X40 Y10\nG1 X60 Y10 E{:.6f}\n", b + 1)},
      {"firmware retraction", "G10\nG0 X40 Y10\nG11\n" + bead_b},
  };
  for (const auto& [name, rest] : variants) {
    SCOPED_TRACE(name);
    const GcodeDeposition d = read(start + rest);
    ASSERT_EQ(d.beads.size(), 2u);
    EXPECT_EQ(d.retractions, 1);
    EXPECT_NEAR(d.beads[1].width, reference.beads[1].width, 1e-12);
    EXPECT_NEAR(d.beads[1].filament_mm3, reference.beads[1].filament_mm3, 1e-12);
    EXPECT_NEAR(d.beads[1].width, 0.4, 1e-5);
  }
  // The same in absolute E, whose retraction runs E back and whose G92 does not undo it.
  const GcodeDeposition absolute = read(fmt::format(
      "M82\nG92 E0\nG0 X10 Y10 Z0.2\nG1 X20 Y10 E{0:.6f}\nG1 E{1:.6f}\nG92 E0\nG0 X40 Y10\n"
      "G1 E0.8\nG1 X60 Y10 E{2:.6f}\n",
      a, a - 0.8, 0.8 + b));
  ASSERT_EQ(absolute.beads.size(), 2u);
  EXPECT_NEAR(absolute.beads[1].filament_mm3, reference.beads[1].filament_mm3, 1e-9);
}

TEST(GcodeDepositionAnnotations, WidthAndHeightOverrideTheModel) {
  const double e = filament(10, 0.4, 0.2);
  const GcodeDeposition d =
      read(fmt::format("M83\nG0 X0 Y0 Z0.2\nG1 X10 E{0:.8f}\n;TYPE:Perimeter\n;WIDTH:0.55\n"
                       ";HEIGHT:0.12\nG1 X20 E{0:.8f}\n;WIDTH:0.3\nG1 X30 E{0:.8f}\n"
                       "; FEATURE: Outer wall\n; LINE_WIDTH: 0.5\n; LAYER_HEIGHT: 0.16\n"
                       "G1 X40 E{0:.8f}\n",
                       e));
  ASSERT_EQ(d.beads.size(), 4u);
  EXPECT_NEAR(d.beads[0].width, 0.4, 1e-7);
  EXPECT_NEAR(d.beads[0].height, 0.2, 1e-12);
  EXPECT_EQ(d.beads[0].type, "");
  EXPECT_EQ(d.beads[1].width, 0.55);
  EXPECT_EQ(d.beads[1].height, 0.12);
  EXPECT_EQ(d.beads[1].type, "Perimeter");
  EXPECT_EQ(d.beads[2].width, 0.3);
  EXPECT_EQ(d.beads[2].height, 0.12);
  EXPECT_EQ(d.beads[3].width, 0.5);
  EXPECT_EQ(d.beads[3].height, 0.16);
  EXPECT_EQ(d.beads[3].type, "Outer wall");
  for (const DepositedBead& bead : d.beads) EXPECT_NEAR(bead.filament_mm3, e * kArea, 1e-7);
}

// A purge line at z 0.3 before the first layer, then two layers at 0.2 and 0.4 with a z-hop in
// the first; `layer_start(k, z)` writes the annotation of layer k.
std::string annotated_file(const std::function<std::string(int, double)>& layer_start) {
  const double e = filament(10, 0.4, 0.2), purge = filament(50, 0.8, 0.3);
  std::string out = fmt::format("M83\nG0 X0 Y5 Z0.3\nG1 X50 E{:.8f}\n", purge);
  out += layer_start(0, 0.2);
  out += fmt::format(
      "G0 X10 Y10 Z0.2\nG1 X20 E{0:.8f}\nG0 Z0.8\nG0 X40\nG0 Z0.2\nG1 X50 E{0:.8f}\n", e);
  out += layer_start(1, 0.4);
  out += fmt::format("G0 Z0.4\nG1 X40 E{0:.8f}\n", e);
  return out;
}

void expect_two_layers_and_a_purge(const GcodeDeposition& d) {
  ASSERT_EQ(d.beads.size(), 4u);
  EXPECT_EQ(d.num_layers, 2);
  ASSERT_EQ(d.layer_z.size(), 2u);
  EXPECT_NEAR(d.layer_z[0], 0.2, 1e-12);
  EXPECT_NEAR(d.layer_z[1], 0.4, 1e-12);
  const int layers[] = {0, 0, 0, 1};
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(d.beads[i].layer, layers[i]) << i;
  // The purge lies on the bed: as high as its z, 0.8 mm wide.
  EXPECT_NEAR(d.beads[0].height, 0.3, 1e-12);
  EXPECT_NEAR(d.beads[0].width, 0.8, 1e-6);
  for (size_t i = 1; i < 4; ++i) {
    EXPECT_NEAR(d.beads[i].height, 0.2, 1e-12) << i;
    EXPECT_NEAR(d.beads[i].width, 0.4, 1e-6) << i;
  }
}

TEST(GcodeDepositionLayers, ByLayerChangeAnnotations) {
  // PrusaSlicer, Orca and flatmorph.
  expect_two_layers_and_a_purge(read(annotated_file(
      [](int, double z) { return fmt::format(";LAYER_CHANGE\n;Z:{:.3f}\n;HEIGHT:0.2\n", z); })));
  // Without ;Z: or ;HEIGHT: (the layer's z is then its lowest extruding z).
  expect_two_layers_and_a_purge(
      read(annotated_file([](int, double) { return ";LAYER_CHANGE\n"; })));
  // Bambu Studio.
  expect_two_layers_and_a_purge(read(annotated_file([](int, double z) {
    return fmt::format("; CHANGE_LAYER\n; Z_HEIGHT: {:.3f}\n; LAYER_HEIGHT: 0.2\n", z);
  })));
}

TEST(GcodeDepositionLayers, ByCuraLayerAnnotations) {
  expect_two_layers_and_a_purge(read(";LAYER_COUNT:2\n" + annotated_file([](int k, double) {
                                       return fmt::format(";LAYER:{}\n;TYPE:WALL-OUTER\n", k);
                                     })));
}

// Without annotations: a new layer where the nozzle rises by a layer, not on a z-hop, and not along
// a path whose z rises slowly (a non-planar path).
TEST(GcodeDepositionLayers, ByZAlone) {
  std::string text = "M83\nG0 X0 Y0 Z0.2\n";
  const double e = filament(10, 0.4, 0.2);
  text += fmt::format("G1 X10 E{0:.8f}\nG1 X20 E{0:.8f}\n", e);  // layer 0 at 0.2
  text += fmt::format("G0 Z0.4\nG1 X10 E{0:.8f}\n", e);          // layer 1 at 0.4
  // A z-hop within it, then a path 0.05 mm higher: more than 0.02 mm but less than 40 % of the
  // layer's 0.2 mm above it.
  text += fmt::format("G0 Z1.0\nG0 X30\nG0 Z0.4\nG1 X40 E{0:.8f}\n", e);
  text += fmt::format("G0 X45 Z0.45\nG1 X50 E{0:.8f}\n", e / 2);
  // Layer 2 at 0.6, along a path rising to 0.75 in steps of 0.01 mm.
  text += "G0 Z0.6\n";
  for (int i = 1; i <= 15; ++i) {
    text += fmt::format("G1 X{} Z{:.3f} E{:.8f}\n", 50 - i, 0.6 + 0.01 * i, e / 10);
  }
  text += fmt::format("G0 Z0.95\nG1 X10 E{0:.8f}\n", e);  // layer 3 at 0.95
  const GcodeDeposition d = read(text);
  ASSERT_EQ(d.num_layers, 4);
  const double z[] = {0.2, 0.4, 0.6, 0.95};
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(d.layer_z[k], z[k], 1e-12) << k;
  ASSERT_EQ(d.beads.size(), 2u + 3u + 15u + 1u);
  for (size_t i = 0; i < d.beads.size(); ++i) {
    const int layer = i < 2 ? 0 : i < 5 ? 1 : i < 20 ? 2 : 3;
    EXPECT_EQ(d.beads[i].layer, layer) << i;
  }
  // Nominal heights: the bead's mean z above the layer below.
  EXPECT_NEAR(d.beads[0].height, 0.2, 1e-12);
  EXPECT_NEAR(d.beads[3].height, 0.2, 1e-12);
  EXPECT_NEAR(d.beads[4].height, 0.25, 1e-12);
  EXPECT_NEAR(d.beads[5].height, 0.6 + 0.005 - 0.4, 1e-12);
  EXPECT_NEAR(d.beads[19].height, 0.6 + 0.145 - 0.4, 1e-12);
  EXPECT_NEAR(d.beads[20].height, 0.35, 1e-12);
}

TEST(GcodeDepositionTools, TCommandsSelectTheToolAndM104TDoesNot) {
  const double e = filament(10, 0.4, 0.2);
  const GcodeDeposition d =
      read(fmt::format("M83\nT0\nG0 X0 Y0 Z0.2\nG1 X10 E{0:.8f}\n"
                       "G1 E-0.8\nT1\nM104 T0 S0\nG1 X20 E{0:.8f}\n"     // T1 has its own filament
                       "M104 T0 S200\nM109 T0 S200\nG1 X30 E{0:.8f}\n"   // still T1
                       "G1 E-0.5\nT255\nT0\nG1 E0.8\nG1 X40 E{0:.8f}\n"  // T0 refills its 0.8
                       "T1\nG1 E0.5\nG1 X50 E{0:.8f}\n",                 // T1 refills its 0.5
                       e));
  ASSERT_EQ(d.beads.size(), 5u);
  const int tools[] = {0, 1, 1, 0, 1};
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(d.beads[i].tool, tools[i]) << i;
    EXPECT_NEAR(d.beads[i].width, 0.4, 1e-6) << i;
  }
  EXPECT_EQ(d.tool_changes, 3);
  EXPECT_EQ(d.retractions, 2);
}

TEST(GcodeDepositionHeader, ReadsTheSlicersHeaders) {
  const double e = filament(10, 0.4, 0.2);
  const std::string moves =
      fmt::format("M83\nG0 X0 Y0 Z0.2\nG1 X10 E{0:.8f}\nT1\nG1 X20 E{0:.8f}\n", e);
  const GcodeDeposition prusa =
      read(moves +
           "; printer_model = MK4\n; printer_settings_id = Original Prusa MK4 Input Shaper\n"
           "; filament_settings_id = \"Prusament PLA\";\"Generic PETG\"\n"
           "; filament_diameter = 1.75,2.85\n");
  EXPECT_EQ(prusa.header.printer, "Original Prusa MK4 Input Shaper");
  EXPECT_EQ(prusa.header.tool_materials,
            (std::vector<std::string>{"Prusament PLA", "Generic PETG"}));
  ASSERT_TRUE(prusa.header.filament_diameter);
  EXPECT_EQ(*prusa.header.filament_diameter, 1.75);
  EXPECT_EQ(prusa.header.tool_filament_diameters, (std::vector<double>{1.75, 2.85}));
  EXPECT_FALSE(prusa.header.plate_to_bed);
  // Each tool's filament has its own section.
  ASSERT_EQ(prusa.beads.size(), 2u);
  EXPECT_NEAR(prusa.beads[0].filament_mm3, e * kArea, 1e-7);
  EXPECT_NEAR(prusa.beads[1].filament_mm3, e * std::numbers::pi * 2.85 * 2.85 / 4, 1e-7);
  // A diameter given by the caller wins over the header's.
  GcodeReadOptions given;
  given.filament_diameter = 2.85;
  given.filament_diameter_given = true;
  EXPECT_NEAR(read(moves + "; filament_diameter = 1.75\n", given).beads[0].filament_mm3,
              e * std::numbers::pi * 2.85 * 2.85 / 4, 1e-7);
  EXPECT_EQ(read(";TARGET_MACHINE.NAME:Creality Ender-3\n" + moves).header.printer,
            "Creality Ender-3");
  EXPECT_EQ(read(";MACHINE_NAME:Ultimaker S5\n" + moves).header.printer, "Ultimaker S5");
  // Nothing said: nothing known.
  const GcodeDeposition bare = read(moves);
  EXPECT_EQ(bare.header.printer, "");
  EXPECT_TRUE(bare.header.tool_materials.empty());
  EXPECT_FALSE(bare.header.filament_diameter);
}

// The extruding segments of a toolpath in print order (bed coordinates) with their layer.
struct Expected {
  Eigen::Vector3d a, b;
  SegmentStyle style;
  int layer;
};
std::vector<Expected> expected_beads(const Toolpath& toolpath,
                                     const Eigen::Vector2d& plate_to_bed) {
  std::vector<Expected> out;
  const Eigen::Vector3d offset(plate_to_bed.x(), plate_to_bed.y(), 0);
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    for (const PathPolyline& path : toolpath.layers[k].paths) {
      for (size_t i = 0; i < path.segments.size(); ++i) {
        if (path.segments[i].travel) continue;
        out.push_back({path.points.row(i).transpose() + offset,
                       path.points.row(i + 1).transpose() + offset, path.segments[i],
                       static_cast<int>(k)});
      }
    }
  }
  return out;
}

// The beads of the print: not the start G-code's purge (untyped) nor the primes of tool changes.
std::vector<DepositedBead> part_beads(const GcodeDeposition& d) {
  std::vector<DepositedBead> out;
  for (const DepositedBead& bead : d.beads) {
    if (!bead.type.empty() && bead.type != "Wipe tower") out.push_back(bead);
  }
  return out;
}

class FlatmorphGcode : public ::testing::TestWithParam<std::string> {};

// The G-code flatmorph writes, read back: every extruding segment of the toolpath, where it was,
// with its width, height, tool and layer, and the header's printer, materials and placement.
TEST_P(FlatmorphGcode, ReadsBackEverySegmentOfTheToolpath) {
  const PrinterProfile printer = load_printer(GetParam());
  Toolpath toolpath = testing::disk_toolpath(30, 6);
  std::vector<Material> materials = {load_material("pla-paper")};
  if (printer.extruder_count > 1) {
    // The odd layers and every third path of layer 2 with T1.
    materials.push_back(
        load_material(printer.tool_change.shared_nozzle ? "pla-generic" : "tpu-generic"));
    for (size_t k = 0; k < toolpath.layers.size(); ++k) {
      for (size_t p = 0; p < toolpath.layers[k].paths.size(); ++p) {
        for (SegmentStyle& s : toolpath.layers[k].paths[p].segments) {
          s.tool = k % 2 == 1 || (k == 2 && p % 3 == 1) ? 1 : 0;
        }
      }
    }
  }
  const GcodeResult result = make_gcode(toolpath, printer, materials);
  const GcodeDeposition d = read_gcode_deposition(result.text, GetParam() + ".gcode");

  EXPECT_EQ(d.header.printer, printer.name);
  ASSERT_EQ(d.header.tool_materials.size(), materials.size());
  for (size_t t = 0; t < materials.size(); ++t) {
    EXPECT_EQ(d.header.tool_materials[t], materials[t].name);
  }
  ASSERT_TRUE(d.header.filament_diameter);
  EXPECT_EQ(*d.header.filament_diameter, printer.filament_diameter);
  ASSERT_TRUE(d.header.plate_to_bed);
  EXPECT_LT((*d.header.plate_to_bed - result.plate_to_bed).norm(), 1e-3);
  EXPECT_EQ(d.tool_changes, result.tool_changes);

  ASSERT_EQ(d.num_layers, static_cast<int>(toolpath.layers.size()));
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    EXPECT_NEAR(d.layer_z[k], toolpath.layers[k].z, 5e-4) << k;
  }
  const std::vector<Expected> expected = expected_beads(toolpath, result.plate_to_bed);
  const std::vector<DepositedBead> beads = part_beads(d);
  ASSERT_EQ(beads.size(), expected.size());
  const double section =
      std::numbers::pi * printer.filament_diameter * printer.filament_diameter / 4;
  for (size_t i = 0; i < beads.size(); ++i) {
    const DepositedBead& got = beads[i];
    const Expected& want = expected[i];
    ASSERT_LT((got.start - want.a).norm(), 1e-3) << i;
    ASSERT_LT((got.end - want.b).norm(), 1e-3) << i;
    EXPECT_NEAR(got.width, want.style.width, 1e-3) << i;
    EXPECT_NEAR(got.height, want.style.layer_height, 1e-3) << i;
    EXPECT_EQ(got.tool, want.style.tool) << i;
    EXPECT_EQ(got.layer, want.layer) << i;
    // The filament of the segment, within the rounding of E to 10^-5 mm.
    const double volume = (want.b - want.a).norm() * want.style.width * want.style.layer_height;
    EXPECT_NEAR(got.filament_mm3, volume, 2e-5 * section) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(GcodeDepositionPresets, FlatmorphGcode,
                         ::testing::ValuesIn(printer_preset_names()), [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// The header gives each tool's shrink model, curves included, to the precision a simulation
// needs: the file alone says what its design assumed (a reader takes it over the preset's). A
// line that does not read leaves that tool's model unset, not wrong.
TEST(GcodeHeader, GivesEachToolsShrinkModelAndDropsALineThatDoesNotRead) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  Toolpath toolpath = testing::disk_toolpath(30, 4);
  for (ToolpathLayer& layer : toolpath.layers) {
    for (PathPolyline& path : layer.paths) {
      for (SegmentStyle& s : path.segments) s.tool = &layer == &toolpath.layers.back() ? 1 : 0;
    }
  }
  Material pla = load_material("pla-generic");
  pla.speed_curve = SpeedCurve{{0.948, -0.00132, 1.0 / 3e6}, 20, 120, 0.2, 0};
  pla.print_speed = 50;
  pla.lambda1 = 0.6 + 1.0 / 30;                           // not short: every digit must come back
  const Material geodesy = load_material("pla-geodesy");  // a thickness curve, no speed curve
  ASSERT_TRUE(geodesy.thickness_curve);
  const std::string text = make_gcode(toolpath, printer, {pla, geodesy}).text;
  const GcodeHeaderInfo header = read_gcode_header(text);
  ASSERT_EQ(header.tool_shrink.size(), 2u);
  for (size_t t = 0; t < 2; ++t) {
    const Material& m = t == 0 ? pla : geodesy;
    ASSERT_TRUE(header.tool_shrink[t]) << t;
    const HeaderShrinkModel& got = *header.tool_shrink[t];
    EXPECT_NEAR(got.lambda1, m.lambda1, 1e-11) << t;
    EXPECT_NEAR(got.lambda2, m.lambda2, 1e-11) << t;
    EXPECT_NEAR(got.lambda3, m.lambda3, 1e-11) << t;
    EXPECT_NEAR(got.delta_lambda1, m.delta_lambda1, 1e-11) << t;
    ASSERT_EQ(got.speed_curve.has_value(), m.speed_curve.has_value()) << t;
    ASSERT_EQ(got.thickness_curve.has_value(), m.thickness_curve.has_value()) << t;
  }
  const SpeedCurve& speed = *header.tool_shrink[0]->speed_curve;
  ASSERT_EQ(speed.lambda1_coefficients.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(speed.lambda1_coefficients[i], pla.speed_curve->lambda1_coefficients[i],
                1e-11 * std::abs(pla.speed_curve->lambda1_coefficients[i]));
  }
  EXPECT_EQ(speed.min_print_speed, 20);
  EXPECT_EQ(speed.max_print_speed, 120);
  EXPECT_EQ(speed.layer_height, 0.2);
  const ThicknessCurve& thickness = *header.tool_shrink[1]->thickness_curve;
  const ThicknessCurve& want = *geodesy.thickness_curve;
  ASSERT_EQ(thickness.lambda1_coefficients.size(), want.lambda1_coefficients.size());
  for (double h : {want.min_layer_height, 0.2, want.max_layer_height}) {
    double got_l = 0, want_l = 0;
    for (size_t i = want.lambda1_coefficients.size(); i-- > 0;) {
      got_l = got_l * h + thickness.lambda1_coefficients[i];
      want_l = want_l * h + want.lambda1_coefficients[i];
    }
    EXPECT_NEAR(got_l, want_l, 1e-10) << h;
  }

  // T0's speed curve line garbled: T0 has no model, T1 keeps its own.
  std::string garbled = text;
  const size_t at = garbled.find("; T0 speed_curve = lambda1 coefficients ");
  ASSERT_NE(at, std::string::npos);
  garbled.insert(at + std::string("; T0 speed_curve = lambda1 coefficients ").size(), "x");
  const GcodeHeaderInfo bad = read_gcode_header(garbled);
  ASSERT_EQ(bad.tool_shrink.size(), 2u);
  EXPECT_FALSE(bad.tool_shrink[0]);
  EXPECT_TRUE(bad.tool_shrink[1]);
}

// Without its annotations, flatmorph's G-code still reads: layers by z, heights from them, and
// each bead's cross-section (width × height) from E.
TEST(GcodeDepositionRoundTrip, FlatmorphGcodeWithoutAnnotations) {
  for (const std::string name : {"generic-marlin", "bambu-x1c"}) {
    SCOPED_TRACE(name);
    const PrinterProfile printer = load_printer(name);
    const Toolpath toolpath = testing::disk_toolpath(30, 6);
    const GcodeResult result = make_gcode(toolpath, printer, {load_material("pla-paper")});
    std::istringstream in(result.text);
    std::string stripped, line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] != ';') stripped += line + "\n";
    }
    const GcodeDeposition d = read_gcode_deposition(stripped, name);
    ASSERT_EQ(d.num_layers, static_cast<int>(toolpath.layers.size()));
    for (size_t k = 0; k < toolpath.layers.size(); ++k) {
      EXPECT_NEAR(d.layer_z[k], toolpath.layers[k].z, 5e-4) << k;
    }
    const std::vector<Expected> expected = expected_beads(toolpath, result.plate_to_bed);
    // The purge lines come first.
    ASSERT_GT(d.beads.size(), expected.size());
    const size_t purge = d.beads.size() - expected.size();
    for (size_t i = 0; i < expected.size(); ++i) {
      const DepositedBead& got = d.beads[purge + i];
      const Expected& want = expected[i];
      ASSERT_LT((got.end - want.b).norm(), 1e-3) << i;
      EXPECT_EQ(got.layer, want.layer) << i;
      EXPECT_NEAR(got.height, toolpath.layers[want.layer].height, 1e-3) << i;
      const double length = (want.b - want.a).norm();
      const double area = want.style.width * want.style.layer_height;
      // E and the positions are rounded: looser on short segments.
      EXPECT_NEAR(got.width * got.height, area, area * (2e-3 + 4e-3 / length)) << i;
    }
  }
}

// A file cut in the middle of a line reads up to where it stops.
TEST(GcodeDepositionHostile, ATruncatedFileReadsWhatIsThere) {
  const double e = filament(10, 0.4, 0.2);
  const std::string text = fmt::format("M83\nG0 X0 Y0 Z0.2\nG1 X10 E{0:.8f}\nG1 X20 E{0:.8f}\n", e);
  EXPECT_EQ(read(text + "G1 X30 E").beads.size(), 2u);      // a parameter without its value
  EXPECT_EQ(read(text + "G1 X30 E0.1.").beads.size(), 2u);  // a broken number
  EXPECT_EQ(read(text + "G1 X30 E0.2").beads.size(), 3u);   // a complete last line
}

struct Hostile {
  std::string name;
  std::string text;
  int line;
  ErrorCategory category;
  std::string says;
};

TEST(GcodeDepositionHostile, EveryProblemGivesOneLineWithItsLineNumber) {
  const std::string ok =
      fmt::format("M83\nG0 X0 Y0 Z0.2\nG1 X10 E{:.8f}\n", filament(10, 0.4, 0.2));
  std::string huge_number = "G1 X1";
  huge_number.append(400, '0');
  const std::vector<Hostile> cases = {
      {"no extrusion", "G28\nG1 X10 Y10 Z0.2 F3000\nG1 E5\nG1 X20 Y20\n", 4, ErrorCategory::kFormat,
       "deposits nothing: no G1"},
      {"empty", "", 1, ErrorCategory::kFormat, "deposits nothing"},
      {"NaN", ok + "G1 Xnan Y0 E1\n", 4, ErrorCategory::kFormat, "X has no value"},
      {"infinity", ok + "G1 X10 Yinf E1\n", 4, ErrorCategory::kFormat, "Y has no value"},
      {"out of range", ok + huge_number + "\n", 4, ErrorCategory::kFormat, "not a parameter"},
      {"too far", ok + "G1 X1000000000 E1\n", 4, ErrorCategory::kFormat, "beyond"},
      {"inches", "G21\nG20\n" + ok, 2, ErrorCategory::kFormat, "inches (G20)"},
      {"XZ arcs", ok + "G18\nG2 X10 Z5 I5 E1\n", 5, ErrorCategory::kFormat, "XZ plane"},
      {"a full circle by R", ok + "G2 X10 Y0 R5 E1\n", 4, ErrorCategory::kFormat, "I and J"},
      {"an arc without centre", ok + "G2 X20 Y0 E1\n", 4, ErrorCategory::kFormat, "I, J"},
      {"at the bed", "M83\nG1 X0 Y0 Z0\nG1 X10 E0.3\n", 3, ErrorCategory::kFormat, "z = 0.000"},
      {"below the bed", "M83\nG1 X0 Y0 Z-0.2\nG1 X10 E0.3\n", 3, ErrorCategory::kFormat,
       "below the bed"},
      {"absolute E in relative mode", ok + "G1 X20 E0.66\nG1 X30 E0.99\nG1 X40 E55.2\n", 6,
       ErrorCategory::kFormat, "the E mode (M82"},
      {"a bad width", ok + ";WIDTH:abc\n", 4, ErrorCategory::kFormat, "bead width"},
      {"a bad height", ok + ";HEIGHT:-0.2\n", 4, ErrorCategory::kFormat, "bead height"},
      {"a bad diameter", "; filament_diameter = 0\n" + ok, 1, ErrorCategory::kFormat,
       "filament_diameter"},
      {"G92 without a value", ok + "G92 E\n", 4, ErrorCategory::kFormat, "E has no value"},
      {"a broken number", ok + "G1 X10.5.2 E1\n", 4, ErrorCategory::kFormat, "X10.5.2"},
  };
  for (const Hostile& c : cases) {
    SCOPED_TRACE(c.name);
    try {
      read(c.text);
      ADD_FAILURE() << "no error";
    } catch (const UserError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.category(), c.category) << message;
      EXPECT_EQ(message.rfind(fmt::format("test.gcode:{}: ", c.line), 0), 0u) << message;
      EXPECT_NE(message.find(c.says), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

TEST(GcodeDepositionHostile, LimitsOfLinesAndBeads) {
  std::string text = "M83\nG0 X0 Y0 Z0.2\n";
  for (int i = 1; i <= 100; ++i) text += fmt::format("G1 X{} E0.03\n", i);
  GcodeReadOptions options;
  options.max_lines = 50;
  try {
    read(text, options);
    ADD_FAILURE() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kResource);
    EXPECT_EQ(std::string(e.what()).rfind("test.gcode:51: more than 50 lines", 0), 0u) << e.what();
  }
  options = {};
  options.max_beads = 10;
  try {
    read(text, options);
    ADD_FAILURE() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kResource);
    EXPECT_EQ(std::string(e.what()).rfind("test.gcode:13: more than 10 beads", 0), 0u) << e.what();
  }
  // An arc of more chords than the beads left.
  options.max_beads = 100;
  EXPECT_THROW(read("M83\nG0 X0 Y0 Z0.2\nG2 X0 Y0 I500 J0 E20\n", options), UserError);
  options = {};
  options.filament_diameter = 0;
  try {
    read(text, options);
    ADD_FAILURE() << "no error";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
  }
}

// Marlin's default is absolute E: a file that never says M82 or M83 reads as absolute.
TEST(GcodeDepositionHostile, EBeforeAnyModeIsAbsolute) {
  const double e = filament(10, 0.4, 0.2);
  const GcodeDeposition d =
      read(fmt::format("G0 X0 Y0 Z0.2\nG1 X10 E{:.8f}\nG1 X20 E{:.8f}\n", e, 2 * e));
  ASSERT_EQ(d.beads.size(), 2u);
  EXPECT_NEAR(d.beads[1].width, 0.4, 1e-6);
}

}  // namespace
}  // namespace flatmorph::gcode_deposition_test
