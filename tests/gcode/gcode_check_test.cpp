// The G-code safety check: each hand-made unsafe file of tests/data/gcode/unsafe/ is flagged for
// its own reason at its line (the file says which in "; expect: KIND LINE"), and nothing else;
// the G-code the writer produces passes (gcode_writer_test.cpp checks that on every printer).
#include "gcode/gcode_check.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode_fixtures.h"
#include "test_support.h"

namespace flatmorph::gcode_check_test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The value of a "; key: value" line of an unsafe file, or "".
std::string directive(const std::string& text, const std::string& key) {
  const std::string tag = "; " + key + ": ";
  const size_t at = text.find(tag);
  if (at == std::string::npos) return "";
  return text.substr(at + tag.size(), text.find('\n', at) - at - tag.size());
}

std::vector<fs::path> unsafe_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(testing::test_data_dir() / "gcode" / "unsafe")) {
    if (entry.path().extension() == ".gcode") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(GcodeCheck, FlagsEveryUnsafeFileForItsReason) {
  const std::vector<fs::path> files = unsafe_files();
  ASSERT_GE(files.size(), 10u);
  std::set<std::string> kinds_covered;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::string text = slurp(file);
    std::istringstream expect(directive(text, "expect"));
    std::string kind;
    int line = 0;
    ASSERT_TRUE(expect >> kind >> line) << "no \"; expect: KIND LINE\"";
    const std::string printer_name = directive(text, "printer");
    const PrinterProfile printer =
        load_printer(printer_name.empty() ? "generic-marlin" : printer_name);
    const std::vector<GcodeViolation> found =
        check_gcode(text, printer, {load_material("pla-paper")});
    ASSERT_FALSE(found.empty()) << "not flagged";
    std::set<std::string> kinds;
    for (const GcodeViolation& v : found) kinds.insert(std::string(to_string(v.kind)));
    EXPECT_EQ(kinds, std::set<std::string>{kind}) << found.front().reason;
    EXPECT_EQ(found.front().line, line) << found.front().reason;
    EXPECT_FALSE(found.front().reason.empty());
    kinds_covered.insert(kind);
  }
  EXPECT_GE(kinds_covered.size(), 14u);
}

// The unsafe files are the safe skeleton plus one mistake: without it they pass.
TEST(GcodeCheck, TheSkeletonOfTheUnsafeFilesIsSafe) {
  const std::string safe =
      "M140 S55\nM104 S190\nG28\nM190 S55\nM109 S190\nG90\nM83\nG92 E0\nG1 Z0.2 F600\n"
      "G1 X20 Y20 F3000\nG1 X60 Y20 E1.5 F1200\nG1 E-2 F2400\nG1 X100 Y50 F3000\nG1 E2 F2400\n"
      "G3 X100 Y90 I0 J20 E3 F1200\nG1 Z10 F600\nM104 S0\nM140 S0\nM84\n";
  EXPECT_TRUE(
      check_gcode(safe, load_printer("generic-marlin"), {load_material("pla-paper")}).empty());
}

TEST(GcodeCheck, ReadsTheUsualSpellings) {
  const PrinterProfile printer = load_printer("generic-marlin");
  const Material material = load_material("pla-paper");
  // Line numbers and checksums, compact words, lower case, comments in parentheses are no moves.
  const std::string text =
      "N1 M83*12\nN2 G1 X10 Y10 F3000*99\ng1 x300 (a comment)\nG1X300Y10\nM104 S190 T0\n"
      "M104 S0\nM140 S0\nM84\n";
  const std::vector<GcodeViolation> found = check_gcode(text, printer, {material});
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].line, 3);
  EXPECT_EQ(found[1].line, 4);
  EXPECT_EQ(found[0].kind, ViolationKind::kOutsideBed);
}

TEST(GcodeCheck, ReadsCommandNumbersWithLeadingZeros) {
  // Firmware reads "G01" as G1 and "G00" as G0, as the reader does.
  const std::string text =
      "M83\nM104 S190\nM109 S190\nG01 X500 Y10\nG00 X10 Y10 E1\nM104 S0\nM140 S0\nM84\n";
  const std::vector<GcodeViolation> found =
      check_gcode(text, load_printer("generic-marlin"), {load_material("pla-paper")});
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].kind, ViolationKind::kOutsideBed);
  EXPECT_EQ(found[0].line, 4);
  EXPECT_EQ(found[1].kind, ViolationKind::kExtrusionOnTravel);
  EXPECT_EQ(found[1].line, 5);
}

TEST(GcodeCheck, G90AndG91SetTheExtruderModeAsMarlinDoes) {
  // Marlin 2 (and the reader): G90/G91 set E too, until the next M82/M83. After "M83, G90" E is
  // absolute, so E0.1 after E0.4 pulls filament back while the head moves; after "M82, G91" it is
  // relative, and the same lines extrude.
  const auto check = [](const std::string& modes) {
    const std::string text = "M104 S190\nM109 S190\n" + modes +
                             "G92 E0\nG1 X10 Y10 F3000\nG1 X20 Y10 E0.4 F1200\n"
                             "G1 X30 Y10 E0.1\nM104 S0\nM140 S0\nM84\n";
    return check_gcode(text, load_printer("generic-marlin"), {load_material("pla-paper")});
  };
  const std::vector<GcodeViolation> absolute = check("M83\nG90\n");
  ASSERT_EQ(absolute.size(), 1u);
  EXPECT_EQ(absolute[0].line, 8);
  EXPECT_TRUE(check("M82\nG91\nG90\nM83\n").empty());
  const std::vector<GcodeViolation> relative = check("M82\nG91\n");
  // G91 makes X and Y relative too: the head ends at (60, 40), still on the bed.
  EXPECT_TRUE(relative.empty());
}

TEST(GcodeCheck, UnknownCommandsAndMacrosAreFine) {
  const std::string text =
      "START_PRINT BED_TEMP=55 EXTRUDER_TEMP=190\nM862.3 P \"MK3S\"\nM117 Hello world\n"
      "TIMELAPSE_TAKE_FRAME\nM83\nG1 X10 Y10 F3000\nEND_PRINT\nTURN_OFF_HEATERS\nM84\n";
  EXPECT_TRUE(
      check_gcode(text, load_printer("generic-klipper"), {load_material("pla-paper")}).empty());
}

TEST(GcodeCheck, AbsoluteRetractionsWithinTheProfileAreFine) {
  // Absolute E: retract 2 mm (the profile's length), unretract, reset with G92 at a layer change.
  const std::string text =
      "M82\nG92 E0\nG1 X10 Y10 F3000\nG1 X50 Y10 E2 F1200\nG1 E0 F2400\nG1 X50 Y50 F3000\n"
      "G1 E2 F2400\nG1 X10 Y50 E4 F1200\nG92 E0\nG1 X10 Y10 E2 F1200\nM84\n";
  EXPECT_TRUE(
      check_gcode(text, load_printer("generic-marlin"), {load_material("pla-paper")}).empty());
}

TEST(GcodeCheck, ReportsEveryViolationWithItsLine) {
  const std::string text = "M83\nG1 X10 Y10\nG1 X500 Y10\nG1 X10 Y500\nM104 S300\n";
  const std::vector<GcodeViolation> found =
      check_gcode(text, load_printer("generic-marlin"), {load_material("pla-paper")});
  ASSERT_EQ(found.size(), 5u);
  EXPECT_EQ(found[0].line, 3);  // x
  EXPECT_EQ(found[1].line, 4);  // y
  EXPECT_EQ(found[2].line, 5);  // nozzle temperature
  EXPECT_EQ(found[3].kind, ViolationKind::kHeatersOnAtEnd);
  EXPECT_EQ(found[4].kind, ViolationKind::kMotorsOnAtEnd);
  EXPECT_EQ(found[4].line, 5);
  // At most max_violations.
  EXPECT_EQ(
      check_gcode(text, load_printer("generic-marlin"), {load_material("pla-paper")}, 2).size(),
      2u);
}

TEST(GcodeCheck, SurvivesGarbage) {
  // Random bytes and random G-code-like words: violations, never a crash or an exception.
  std::string text;
  uint32_t state = 12345;
  auto next = [&state] { return state = state * 1664525u + 1013904223u; };
  const char* words[] = {"G1", "G0", "G2", "G3", "M104", "M140", "G92", "G91",         "M83", "T",
                         "X",  "Y",  "E",  "I",  "J",    "S",    "-",   ".",           "9",   "1e9",
                         "(",  ")",  ";",  "*",  "N",    "\n",   " ",   "T99999999999"};
  for (int i = 0; i < 200000; ++i) {
    const uint32_t r = next();
    if (r % 7 == 0) {
      text += static_cast<char>(next() >> 24);
    } else {
      const std::string w = words[(r >> 8) % std::size(words)];
      text += w == "\\n" ? "\n" : w;
    }
  }
  const std::vector<GcodeViolation> found =
      check_gcode(text, load_printer("generic-delta"), {load_material("pla-paper")});
  EXPECT_FALSE(found.empty());
  EXPECT_LE(found.size(), 1000u);
}

TEST(GcodeCheck, PassesWhatTheWriterWritesForEveryMaterial) {
  for (const std::string& material_name : material_preset_names()) {
    for (const char* printer_name : {"prusa-mk4", "generic-delta"}) {
      const Material material = load_material(material_name);
      const PrinterProfile printer = load_printer(printer_name);
      GcodeOptions options;
      options.skirt_loops = 2;
      const GcodeResult result =
          make_gcode(testing::disk_toolpath(40, 4, {0, 0}), printer, {material}, options);
      EXPECT_TRUE(check_gcode(result.text, printer, {material}).empty())
          << material_name << " on " << printer_name;
    }
  }
}

TEST(GcodeCheck, TheWriterBlamesAnUnsafeProfile) {
  // A user profile whose purge line leaves the bed: the writer refuses, naming the profile line.
  PrinterProfile printer = load_printer("generic-marlin");
  printer.start_gcode += "G1 X300 Y10 F3000\n";
  try {
    make_gcode(testing::disk_toolpath(20, 2), printer, {load_material("pla-paper")});
    FAIL() << "an unsafe start G-code was written";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kProfile);
    EXPECT_NE(std::string(e.what()).find("start_gcode line 17"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("outside-bed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flatmorph::gcode_check_test
