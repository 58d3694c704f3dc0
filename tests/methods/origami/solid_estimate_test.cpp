// What printing the solid would cost (issue 27, item 7): its volume and area in closed form, the
// stated estimate, and a slicer's figures read from its G-code comments.
#include "methods/origami/solid_estimate.h"
#include "examples/origami_examples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace flatmorph::solid_estimate_test {
namespace {

TEST(SolidEstimate, ThePlatonicSolidsHaveTheirVolumeAndArea) {
  const double a = 20;
  EXPECT_NEAR(polyhedron_volume(polyhedron_example("cube", a)), a * a * a, 1e-9);
  EXPECT_NEAR(polyhedron_area(polyhedron_example("cube", a)), 6 * a * a, 1e-9);
  EXPECT_NEAR(polyhedron_volume(polyhedron_example("tetrahedron", a)),
              a * a * a / (6 * std::sqrt(2.0)), 1e-9);
  EXPECT_NEAR(polyhedron_area(polyhedron_example("tetrahedron", a)), std::sqrt(3.0) * a * a, 1e-9);
  EXPECT_NEAR(polyhedron_volume(polyhedron_example("dodecahedron", a)),
              (15 + 7 * std::sqrt(5.0)) / 4 * a * a * a, 1e-6);
  EXPECT_NEAR(polyhedron_volume(polyhedron_example("icosahedron", a)),
              5 * (3 + std::sqrt(5.0)) / 12 * a * a * a, 1e-6);
}

TEST(SolidEstimate, TheCubeIsItsShellsAndInfill) {
  Material pla;
  pla.density = 1.25;
  SolidPrintSettings s;
  const SolidPrintEstimate e = estimate_solid_print(polyhedron_example("cube", 20), pla, 1.75, s);
  const double printed = 2400 * 0.8 + 0.15 * (8000 - 2400 * 0.8);
  EXPECT_NEAR(e.printed, printed, 1e-9);
  EXPECT_NEAR(e.filament_g, printed * 1.25e-3, 1e-12);
  EXPECT_NEAR(e.filament_mm, printed / (M_PI * 1.75 * 1.75 / 4), 1e-9);
  EXPECT_NEAR(e.time_s, printed / (0.45 * 0.2 * 50) * 1.25, 1e-9);
}

TEST(SolidEstimate, ASlicersCommentsAreRead) {
  const auto e = read_slicer_estimate(
      "G1 X1\n; filament used [mm] = 1234.56\n; filament used [cm3] = 2.97\n"
      "; filament used [g] = 3.68\n; estimated printing time (normal mode) = 1h 2m 3s\n");
  ASSERT_TRUE(e);
  EXPECT_DOUBLE_EQ(e->time_s, 3723);
  EXPECT_DOUBLE_EQ(e->filament_mm, 1234.56);
  EXPECT_DOUBLE_EQ(e->filament_g, 3.68);
  EXPECT_FALSE(read_slicer_estimate("; filament used [mm] = 1\n"));
}

// A stand-in prusa-slicer on the PATH: what the real one would be asked, and its answer read.
TEST(SolidEstimate, TheSlicerIsRunOnTheSolidWhenInstalledAndMissedQuietlyWhenNot) {
  const std::filesystem::path bin =
      std::filesystem::temp_directory_path() / "flatmorph-fake-slicer";
  std::filesystem::create_directories(bin);
  {
    std::ofstream script(bin / "prusa-slicer");
    script << "#!/bin/sh\nwhile [ \"$1\" != --output ]; do shift; done\n"
              "grep -q '^f ' \"$3\" || exit 3\n"
              "printf '; filament used [mm] = 500\\n; estimated printing time (normal mode) = "
              "2m 5s\\n' > \"$2\"\n";
  }
  std::filesystem::permissions(bin / "prusa-slicer", std::filesystem::perms::owner_all);
  const std::string old_path = std::getenv("PATH");
  setenv("PATH", (bin.string() + ":" + old_path).c_str(), 1);
  std::string why;
  const auto e = slicer_solid_print(polyhedron_example("cube", 20), 1.75, 30, &why);
  setenv("PATH", "/nonexistent", 1);
  const auto none = slicer_solid_print(polyhedron_example("cube", 20), 1.75, 30, &why);
  setenv("PATH", old_path.c_str(), 1);
  std::filesystem::remove_all(bin);
  ASSERT_TRUE(e) << why;
  EXPECT_DOUBLE_EQ(e->time_s, 125);
  EXPECT_DOUBLE_EQ(e->filament_mm, 500);
  EXPECT_FALSE(none);
  EXPECT_NE(why.find("not installed"), std::string::npos) << why;
}

}  // namespace
}  // namespace flatmorph::solid_estimate_test
