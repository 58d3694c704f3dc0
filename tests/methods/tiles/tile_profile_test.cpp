// Geodesy tile profiles (CHI 2019 §7): the shrink per ring against the closed forms of the
// implementation note (§3: cone, spherical cap, paraboloid, the printable-height bound), its
// invariances (reparametrisation, scale), the library's rescaling, the clamp and its one-line
// warning, the forward model's round trip, CSV refusals, and the polygon mapping.
#include "methods/tiles/tile_profile.h"
#include "common/angles.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/error.h"

namespace flatmorph::tile_profile_test {
namespace {

constexpr double kLeast = 0.0793;  // Geodesy Fig. 2a, PLA
constexpr double kMost = 0.3727;

// The bead centrelines of a disc of flat radius R printed with pitch w (note §4.2, A8).
Eigen::VectorXd ring_radii(double flat_radius, double pitch) {
  const int n = static_cast<int>(std::floor(flat_radius / pitch));
  Eigen::VectorXd r(n);
  for (int m = 0; m < n; ++m) r(m) = flat_radius - (m + 0.5) * pitch;
  return r;
}

// The UserError of `f` (category, message); a failed expectation when it does not throw one.
template <typename F>
UserError refusal(F f) {
  try {
    f();
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    return e;
  }
  ADD_FAILURE() << "accepted";
  return UserError(ErrorCategory::kFile, "");
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A spherical cap of sphere radius a and rim polar angle θ as CSV, points at θ·f(i/n).
template <typename F>
std::string cap_csv(double a, double theta, int n, F f) {
  std::string csv = "# a cap\nr_mm,z_mm\n";
  for (int i = 0; i <= n; ++i) {
    const double phi = theta * f(static_cast<double>(i) / n);
    csv += fmt::format("{:.17g},{:.17g}\n", a * std::sin(phi), a * std::cos(phi));
  }
  return csv;
}

TEST(TileProfile, ConeShrinksUniformlyByOneMinusCosSlope) {
  // Note §3.2: every ring of a cone of slope α shrinks 1 − cos α.
  const double R = 20, H = 8, alpha = std::asin(H / R);
  const TileProfile cone = tile_profile("cone", R, H);
  const Eigen::VectorXd r = ring_radii(R, 0.4);
  const RingShrinkage rings = tile_ring_shrinkage(cone, r, 0.0, 0.99);
  for (Eigen::Index k = 0; k < r.size(); ++k) {
    EXPECT_NEAR(rings.wanted(k), 1 - std::cos(alpha), 1e-6) << "ring at " << r(k);
  }
  EXPECT_NEAR(ring_shrinkage(cone, 0), 1 - std::cos(alpha), 1e-12) << "the limit at the apex";

  // The same cone as a height field z = H(1 − ρ/b) with many collinear points.
  std::string csv;
  const double b = R * std::cos(alpha);
  for (int i = 0; i <= 37; ++i)
    csv += fmt::format("{:.17g},{:.17g}\n", b * i / 37, H * (1 - i / 37.0));
  const TileProfile from_csv = read_profile_csv(csv, "cone.csv");
  EXPECT_NEAR(profile_length(from_csv), R, 1e-9);
  for (double s : {0.05, 1.3, 7.77, 19.8}) {
    EXPECT_NEAR(ring_shrinkage(from_csv, s), 1 - std::cos(alpha), 1e-6) << s;
  }
}

TEST(TileProfile, SphericalCapMatchesClosedForm) {
  // Note §3.3: Sh(s) = 1 − sin(s/a)/(s/a), rising outward from 0 (A1).
  const double R = 15, H = 6;
  const TileProfile cap = tile_profile("spherical-cap", R, H);
  const double b = cap.meridian(cap.meridian.rows() - 1, 0);
  const double a = (b * b + H * H) / (2 * H);
  EXPECT_NEAR(a * std::atan2(b, a - H), R, 1e-6) << "the meridian is the cap's arc";
  double previous = -1;
  for (double s = 0.1; s <= R; s += 0.35) {
    const double sh = ring_shrinkage(cap, s);
    EXPECT_NEAR(sh, 1 - std::sin(s / a) / (s / a), 1e-5) << "s = " << s;
    EXPECT_GT(sh, previous);
    previous = sh;
  }
  EXPECT_NEAR(ring_shrinkage(cap, 0), 0, 1e-6) << "a smooth summit does not shrink";

  // The hemisphere: flat radius πa/2, rim shrink 1 − 2/π.
  const TileProfile hemisphere = tile_profile("spherical-cap", kPi * 10 / 2, 10);
  EXPECT_NEAR(hemisphere.meridian(hemisphere.meridian.rows() - 1, 0), 10, 1e-5);
  EXPECT_NEAR(ring_shrinkage(hemisphere, kPi * 10 / 2), 1 - 2 / kPi, 1e-6);
}

TEST(TileProfile, ParaboloidMatchesClosedForm) {
  // Note §3.4: z = H(1 − r²/b²), c = 2H/b², Sh = g(c r) at the flat radius s(r).
  const double R = 18, H = 9;
  const TileProfile parabola = tile_profile("paraboloid", R, H);
  const double b = parabola.meridian(parabola.meridian.rows() - 1, 0);
  const double c = 2 * H / (b * b);
  for (double r = 0.3; r < b; r += 0.7) {
    const double s = 0.5 * (r * std::sqrt(1 + c * c * r * r) + std::asinh(c * r) / c);
    const double x = c * r;
    const double g = 1 - 2 * x / (x * std::sqrt(1 + x * x) + std::asinh(x));
    EXPECT_NEAR(ring_shrinkage(parabola, s), g, 1e-5) << "r = " << r;
  }
  EXPECT_NEAR(0.5 * (b * std::sqrt(1 + c * c * b * b) + std::asinh(c * b) / c), R, 1e-5)
      << "the meridian is the parabola's arc";
}

TEST(TileProfile, ShrinkDoesNotDependOnHowTheProfileIsSampled) {
  // Note A3: the same curve with points bunched at the apex (u → u³) gives the same Sh.
  const TileProfile even = read_profile_csv(cap_csv(10, 1.2, 400, [](double u) { return u; }), "a");
  const TileProfile bunched =
      read_profile_csv(cap_csv(10, 1.2, 400, [](double u) { return u * u * u; }), "b");
  EXPECT_GT(even.meridian(1, 0) - bunched.meridian(1, 0), 1e-3) << "really sampled apart";
  const double R = profile_length(even);
  EXPECT_NEAR(profile_length(bunched), R, 1e-4);
  for (double s = 0.2; s < R - 1e-3; s += 0.5) {
    EXPECT_NEAR(ring_shrinkage(even, s), ring_shrinkage(bunched, s), 1e-4) << "s = " << s;
    EXPECT_NEAR(ring_shrinkage(even, s), 1 - std::sin(s / 10) / (s / 10), 1e-5) << "s = " << s;
  }
}

TEST(TileProfile, ShrinkIsScaleInvariant) {
  // Note A11: scaling the tile and the profile together leaves Sh(k/N) unchanged.
  const int n = 25;
  for (const char* name : {"gaussian", "transition"}) {
    const TileProfile small = tile_profile(name, 12, 5);
    const TileProfile large = tile_profile(name, 36, 15);
    for (int k = 1; k <= n; ++k) {
      EXPECT_NEAR(ring_shrinkage(small, 12.0 * k / n), ring_shrinkage(large, 36.0 * k / n), 1e-12)
          << name << " k = " << k;
    }
  }
  const TileProfile cap = read_profile_csv(cap_csv(10, 1.0, 50, [](double u) { return u; }), "c");
  const TileProfile scaled = scale_profile_to_length(cap, 3 * profile_length(cap));
  for (double s : {0.3, 2.0, 9.5}) {
    EXPECT_NEAR(ring_shrinkage(cap, s), ring_shrinkage(scaled, 3 * s), 1e-12);
  }
}

TEST(TileProfile, LibraryHitsTheFlatRadiusAndHeight) {
  // Note A11: a library entry is a shape, rescaled to meridian length R and height H.
  const double R = 17.5, H = 6.3;
  for (const std::string& name : tile_profile_names()) {
    const TileProfile p = tile_profile(name, R, H);
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(check_tile_profile(p, name));
    EXPECT_NEAR(profile_length(p), R, 1e-6 * R);
    if (name != "subtle-cone" && name != "dramatic-cone") {
      EXPECT_NEAR(profile_height(p), H, 1e-6 * H);
    }
    EXPECT_EQ(p.meridian(0, 0), 0);
    EXPECT_DOUBLE_EQ(p.meridian(0, 1), p.meridian.col(1).maxCoeff()) << "the apex is on top";
    EXPECT_NEAR(p.meridian(p.meridian.rows() - 1, 1), 0, 1e-9) << "the rim at z = 0";
  }
  // Shapes by their shrink (notes A4, A5, §3.5): a horn's Sh falls outward; the transition's
  // has a minimum inside; a Gaussian's rises from 0 and peaks near 1.5σ.
  const Eigen::VectorXd r = ring_radii(R, 0.4).reverse();
  const Eigen::VectorXd horn = tile_ring_shrinkage(tile_profile("concave", R, H), r, 0, 0.9).wanted;
  for (Eigen::Index k = 1; k < r.size(); ++k) EXPECT_LT(horn(k), horn(k - 1)) << r(k);
  const Eigen::VectorXd onion =
      tile_ring_shrinkage(tile_profile("transition", R, H), r, 0, 0.9).wanted;
  Eigen::Index low = 0;
  onion.minCoeff(&low);
  EXPECT_GT(low, r.size() / 5);
  EXPECT_LT(low, r.size() - r.size() / 5);
  const TileProfile gauss = tile_profile("gaussian", R, H);
  const Eigen::VectorXd bump = tile_ring_shrinkage(gauss, r, 0, 0.9).wanted;
  Eigen::Index peak = 0;
  bump.maxCoeff(&peak);
  const double sigma = gauss.meridian(gauss.meridian.rows() - 1, 0) / 3;
  const double peak_rho = profile_point_at_length(gauss, r(peak))(0);
  EXPECT_GT(peak_rho, 1.4 * sigma);
  EXPECT_LT(peak_rho, 1.7 * sigma);
}

TEST(TileProfile, SubtleAndDramaticConesHaveThePapersSlopes) {
  // Note §3.2: the cones printed at the least and the most shrink.
  const struct {
    const char* name;
    double shrink, slope_degrees, height_ratio;
  } cones[] = {{"subtle-cone", 0.0793, 22.97, 0.3903}, {"dramatic-cone", 0.3727, 51.15, 0.7788}};
  for (const auto& c : cones) {
    const TileProfile p = tile_profile(c.name, 20, 1);  // the height is ignored
    const double slope = std::atan2(p.meridian(0, 1) - p.meridian(1, 1), p.meridian(1, 0));
    EXPECT_NEAR(slope * 180 / kPi, c.slope_degrees, 0.005) << c.name;
    EXPECT_NEAR(profile_height(p) / 20, c.height_ratio, 5e-5) << c.name;
    for (double s : {0.2, 5.0, 19.9}) EXPECT_NEAR(ring_shrinkage(p, s), c.shrink, 1e-9) << c.name;
  }
}

TEST(TileProfile, NoPrintableProfileRisesAboveTheDramaticCone) {
  // Note §3.6: rings all within [least, most] bound the height by R √(1 − (1 − most)²).
  const double R = 15, bound = R * std::sqrt(1 - (1 - kMost) * (1 - kMost));
  const Eigen::VectorXd r = ring_radii(R, 0.4);
  int printable = 0;
  for (const std::string& name : tile_profile_names()) {
    for (double h = 0.1; h < 0.99; h += 0.1) {
      TileProfile p;
      try {
        p = tile_profile(name, R, h * R);
      } catch (const UserError&) {
        continue;  // a cap cannot rise that far
      }
      const RingShrinkage rings = tile_ring_shrinkage(p, r, kLeast, kMost);
      if ((rings.clamped.array() != 0).any()) continue;
      ++printable;
      EXPECT_LE(profile_height(p), bound + 1e-9) << name << " H/R = " << h;
    }
  }
  EXPECT_GE(printable, 5) << "the bound was tested on printable profiles";
  const TileProfile dramatic = tile_profile("dramatic-cone", R, 0);
  EXPECT_NEAR(profile_height(dramatic), bound, 1e-9);
  EXPECT_EQ((tile_ring_shrinkage(dramatic, r, kLeast, kMost).clamped.array() != 0).count(), 0);
  const TileProfile steeper = tile_profile("cone", R, bound * 1.001);
  EXPECT_EQ((tile_ring_shrinkage(steeper, r, kLeast, kMost).clamped.array() > 0).count(), r.size());
}

TEST(TileProfile, ForwardModelRoundTripsAHemisphere) {
  // Note §3.1/A8: inverse then forward, a = 10 mm, w = 0.4 mm, within 0.01 mm.
  const double a = 10, R = kPi * a / 2;
  const TileProfile hemisphere = tile_profile("spherical-cap", R, a);
  const Eigen::VectorXd r = ring_radii(R, 0.4);
  const RingShrinkage rings = tile_ring_shrinkage(hemisphere, r, 0, 0.9);
  const ForwardProfile forward = profile_from_shrinkage(r, rings.wanted);
  EXPECT_EQ(forward.horizontal_steps, 0);
  for (Eigen::Index k = 0; k < r.size(); ++k) {
    const Eigen::Vector2d target = profile_point_at_length(hemisphere, r(k));
    EXPECT_NEAR(forward.points(k, 0), target(0), 1e-9) << r(k);
    EXPECT_NEAR(forward.points(k, 1), target(1) - a, 0.01) << r(k);
  }
}

TEST(TileProfile, ForwardModelFlagsAShrinkThatWouldStretchTheMeridian) {
  // Note §3.1: r·Sh decreasing (here 0.5 at 1 mm, 0.1 at 2 mm) asks |Δρ| > Δr.
  Eigen::VectorXd r(3), sh(3);
  r << 2, 1, 3;
  sh << 0.1, 0.5, 0.1;
  const ForwardProfile forward = profile_from_shrinkage(r, sh);
  EXPECT_EQ(forward.horizontal_steps, 1);
  EXPECT_NEAR(forward.stretch, 0.3, 1e-12);
  EXPECT_NEAR(forward.points(1, 1), -std::sqrt(1 - 0.25), 1e-12) << "input order kept";
  EXPECT_EQ(forward.points(0, 1), forward.points(1, 1)) << "the bad step is horizontal";
  EXPECT_NEAR(forward.points(0, 0), 1.8, 1e-12) << "the ring keeps its printed radius";
  EXPECT_NEAR(forward.points(2, 1), forward.points(0, 1) - std::sqrt(1 - 0.9 * 0.9), 1e-12);
}

TEST(TileProfile, ClampingACapsTopMakesItTallerAndSaysWhere) {
  // Note §3.3: the top 40° of a sphere needs less than 7.93 %; clamped, the hemisphere
  // (a = 10 mm) rises 0.39 mm more with a 23° tip.
  const double R = kPi * 10 / 2;
  const TileProfile hemisphere = tile_profile("spherical-cap", R, 10);
  const RingShrinkage rings = tile_ring_shrinkage(hemisphere, ring_radii(R, 0.4), kLeast, kMost);
  for (Eigen::Index k = 0; k < rings.flat_radius.size(); ++k) {
    EXPECT_EQ(rings.clamped(k), rings.flat_radius(k) < 10 * 0.6982 ? -1 : 0)
        << rings.flat_radius(k);
    EXPECT_EQ(rings.printed(k), std::max(rings.wanted(k), kLeast));
  }
  const PrintabilityReport report = printability(hemisphere, rings, false);
  EXPECT_TRUE(report.any_clamped);
  EXPECT_NEAR(report.target_height_mm, 10, 1e-6);
  EXPECT_NEAR(report.clamped_height_mm - report.target_height_mm, 0.39, 0.01);
  EXPECT_EQ(report.horizontal_steps, 0);
  EXPECT_EQ(report.warning,
            "profile spherical-cap: rings at flat radius 0.3-6.7 mm need 0.02-7.33 % shrink, "
            "below the least 7.93 % the material gives, printed at 7.93 %; the tile rises 10.39 mm "
            "instead of 10.00 mm (a pointed apex)");

  const UserError strict = refusal([&] { printability(hemisphere, rings, true); });
  EXPECT_EQ(strict.category(), ErrorCategory::kInfeasible);
  EXPECT_TRUE(contains(strict.what(), "--strict")) << strict.what();
  EXPECT_TRUE(contains(strict.what(), "flat radius 0.3-6.7 mm")) << strict.what();
  EXPECT_TRUE(contains(strict.what(), "make the apex a point sloping at least 23.0°"))
      << strict.what();

  // A printable profile passes without a word, strict or not.
  const TileProfile cone = tile_profile("cone", 15, 9);
  const RingShrinkage fine = tile_ring_shrinkage(cone, ring_radii(15, 0.4), kLeast, kMost);
  const PrintabilityReport ok = printability(cone, fine, true);
  EXPECT_FALSE(ok.any_clamped);
  EXPECT_EQ(ok.warning, "");
  EXPECT_NEAR(ok.clamped_height_mm, 9, 1e-9);
}

TEST(TileProfile, WarningGroupsRangesOnBothSides) {
  // A cap a little taller than a hemisphere: a flat top and a rim beyond 37.27 % (note §3.3).
  const double a = 10, theta = 1.7;
  const TileProfile cap = tile_profile("spherical-cap", a * theta, a * (1 - std::cos(theta)));
  const RingShrinkage rings = tile_ring_shrinkage(cap, ring_radii(a * theta, 0.4), kLeast, kMost);
  const PrintabilityReport report = printability(cap, rings, false);
  EXPECT_TRUE(contains(report.warning,
                       "below the least 7.93 % the material gives, printed at "
                       "7.93 %; rings at flat radius 16.0-16.8 mm need"))
      << report.warning;
  EXPECT_TRUE(contains(report.warning,
                       "above the most 37.27 % the material gives, printed at "
                       "37.27 %; the tile rises"))
      << report.warning;
}

TEST(TileProfile, RefusesAProfileWithNoPrintableRing) {
  const Eigen::VectorXd r = ring_radii(15, 0.4);
  const TileProfile steep = tile_profile("cone", 15, 15 * std::sin(60 * kPi / 180));
  const UserError too_steep =
      refusal([&] { printability(steep, tile_ring_shrinkage(steep, r, kLeast, kMost), false); });
  EXPECT_EQ(too_steep.category(), ErrorCategory::kInfeasible);
  EXPECT_TRUE(contains(too_steep.what(), "no ring is printable")) << too_steep.what();
  EXPECT_TRUE(contains(too_steep.what(), "need 50.00 % shrink, above the most 37.27 %"))
      << too_steep.what();
  EXPECT_TRUE(contains(too_steep.what(), "lower the height or widen the tile")) << too_steep.what();

  const TileProfile flat = tile_profile("cone", 15, 2);
  const UserError too_flat =
      refusal([&] { printability(flat, tile_ring_shrinkage(flat, r, kLeast, kMost), false); });
  EXPECT_TRUE(contains(too_flat.what(), "raise the height")) << too_flat.what();
}

TEST(TileProfile, LibraryRefusesWhatCannotBeBuilt) {
  EXPECT_TRUE(contains(refusal([] { tile_profile("dome", 10, 3); }).what(),
                       "choose one of spherical-cap, cone, paraboloid"));
  const UserError too_high = refusal([] { tile_profile("paraboloid", 10, 10); });
  EXPECT_EQ(too_high.category(), ErrorCategory::kOption);
  EXPECT_TRUE(contains(too_high.what(), "lower the height below 10 mm or widen"))
      << too_high.what();
  EXPECT_TRUE(contains(refusal([] { tile_profile("cone", 10, -1); }).what(), "not a positive"));
  EXPECT_TRUE(contains(refusal([] { tile_profile("cone", NAN, 3); }).what(), "flat radius"));
  // (1 − cos θ)/θ peaks at 0.7246: no cap of flat radius 10 mm rises 8 mm.
  const UserError cap = refusal([] { tile_profile("spherical-cap", 10, 8); });
  EXPECT_TRUE(contains(cap.what(), "rises at most 7.246 mm")) << cap.what();
  EXPECT_NO_THROW(tile_profile("spherical-cap", 10, 7.2));
}

TEST(TileProfile, ReadsCsvWithHeaderAndComments) {
  const TileProfile p =
      read_profile_csv("# my dome\r\nr,z\r\n\r\n0, 5 # apex\r\n3,4\r\n+4,0\r\n", "dome.csv");
  EXPECT_EQ(p.name, "dome.csv");
  ASSERT_EQ(p.meridian.rows(), 3);
  EXPECT_EQ(p.meridian(2, 0), 4);
  EXPECT_NEAR(profile_length(p), std::sqrt(10.0) + std::sqrt(17.0), 1e-12);
  EXPECT_EQ(profile_point_at_length(p, std::sqrt(10.0) / 2), Eigen::Vector2d(1.5, 4.5));
  EXPECT_EQ(read_profile_csv("1e-12,1\n1,0", "tiny.csv").meridian(0, 0), 0) << "on the axis";
}

TEST(TileProfile, RefusesBadCsvWithTheLine) {
  struct Case {
    const char* text;
    const char* expected;
  } cases[] = {
      {"r,z\n0,1\nnan,0\n", "p.csv:3: r = nan is not a finite number"},
      {"# one\n0,5\n", "p.csv:2: only one point"},
      {"0,5\n1,4\n1,4\n", "p.csv:3: the point (1, 4) repeats line 2"},
      {"r,z\n2.5,5\n3,0\n", "p.csv:2: the profile starts at r = 2.5 mm, off the axis"},
      {"0,5\n-1,4\n", "p.csv:2: r = -1 mm is negative"},
      {"0,5\n1,four\n", "p.csv:2: z = \"four\" is not a number"},
      {"0,5\n1,4,3\n", "p.csv:2: 3 cells where a point has two"},
      {"# nothing\n", "p.csv:1: no points"},
      {"0,5\n1,inf\n", "p.csv:2: z = inf is not a finite number"},
  };
  for (const Case& c : cases) {
    const UserError e = refusal([&] { read_profile_csv(c.text, "p.csv"); });
    EXPECT_EQ(e.category(), ErrorCategory::kFormat) << c.text;
    EXPECT_EQ(std::string(e.what()).rfind(c.expected, 0), 0u) << e.what();
  }
  std::string many = "0,0\n";
  for (int i = 1; i <= 100000; ++i) many += fmt::format("{},0\n", i * 1e-3);
  EXPECT_TRUE(contains(refusal([&] { read_profile_csv(many, "p.csv"); }).what(),
                       "p.csv:100001: more than 100000 points"));
}

TEST(TileProfile, ChecksProfilesAndRingsAgainstItsLength) {
  TileProfile p{"mine", Eigen::MatrixX2d(3, 2)};
  p.meridian << 0, 2, 1, 1, NAN, 0;
  EXPECT_TRUE(contains(refusal([&] { check_tile_profile(p, "mine"); }).what(), "mine: point 3"));
  p.meridian << 0.5, 2, 1, 1, 2, 0;
  EXPECT_TRUE(contains(refusal([&] { check_tile_profile(p, "mine"); }).what(), "off the axis"));
  p.meridian << 0, 2, 1, 1, 1, 1;
  EXPECT_TRUE(contains(refusal([&] { check_tile_profile(p, "mine"); }).what(), "repeats"));
  const TileProfile cone = tile_profile("cone", 10, 5);
  Eigen::VectorXd r(2);
  r << 5, 10.5;
  const UserError shorter = refusal([&] { tile_ring_shrinkage(cone, r, kLeast, kMost); });
  EXPECT_EQ(shorter.category(), ErrorCategory::kGeometry);
  EXPECT_TRUE(contains(shorter.what(), "profile cone is 10.000 mm long")) << shorter.what();
  EXPECT_THROW(ring_shrinkage(cone, -1), std::invalid_argument);
}

TEST(TileProfile, PolygonMappingReproducesTheCircle) {
  // Note A10: a circular "polygon" (N' = N) gets the circle's own shrink, both mappings.
  const double R = 15, w = 0.4;
  const TileProfile p = tile_profile("transition", R, 7);
  const RingShrinkage circle = tile_ring_shrinkage(p, ring_radii(R, w), kLeast, kMost);
  const Eigen::Index n = circle.printed.size();
  for (Eigen::Index m = 0; m < n; ++m) {
    EXPECT_NEAR(polygon_ring_shrinkage(circle, R, (m + 0.5) * w / R), circle.printed(m), 1e-12);
  }
  const double between = polygon_ring_shrinkage(circle, R, (0.5 + 0.25) * w / R);
  EXPECT_NEAR(between, 0.75 * circle.printed(0) + 0.25 * circle.printed(1), 1e-12);
  EXPECT_EQ(polygon_ring_shrinkage(circle, R, 1.0), circle.printed(n - 1)) << "deepest point";

  // Paper mode: innermost first.
  const Eigen::VectorXd same = paper_polygon_shrinkage(circle, static_cast<int>(n));
  EXPECT_EQ(same, circle.printed.reverse().eval());
  const Eigen::VectorXd finer = paper_polygon_shrinkage(circle, static_cast<int>(2 * n));
  EXPECT_EQ(finer(0), circle.printed(n - 1)) << "Floor(N/2N) = 0, clamped to ring 1";
  EXPECT_EQ(finer(2), circle.printed(n - 1));
  EXPECT_EQ(finer(3), circle.printed(n - 2));
  EXPECT_EQ(finer(2 * n - 1), circle.printed(0));
}

}  // namespace
}  // namespace flatmorph::tile_profile_test
