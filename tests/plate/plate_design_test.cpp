// The plate file set (plate/plate_design.h): flat.ply + flat.stack.json read back bit for bit, the
// errors of a stack file that does not belong to its mesh, the fallback for an older flat.ply, and
// the acceptance check of issue 20: a plate designed with --layers 6 --material pla-generic is
// printed and simulated with them, without being told.
#include "plate/plate_design.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "common/error.h"
#include "mesh/io.h"
#include "plate/plate_fixtures.h"
#include "test_support.h"

namespace flatmorph::plate_design_test {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Two materials, per-face directions and thicknesses, a face left out of one layer.
PlateDesign two_material_design() {
  const testing::TestPlate p = testing::rectangle_plate(20, 10, 4, 2);
  const int nf = static_cast<int>(p.F.rows());
  PlateDesign d;
  d.plate = p.V;
  d.F = p.F;
  d.method = "test";
  Material pla, tpu;
  pla.name = "pla-test";
  tpu.name = "tpu-test";
  tpu.lambda1 = tpu.lambda2 = tpu.lambda3 = 1;
  tpu.delta_lambda1 = 0;
  tpu.young_modulus_along = tpu.young_modulus_across = 0.7;
  d.stack.materials = {pla, tpu};
  for (int k = 0; k < 3; ++k) {
    Layer l = uniform_layer(nf, k == 0 ? 1 : 0, d.stack.materials[k == 0 ? 1 : 0], 0.1);
    for (int f = 0; f < nf; ++f) l.theta(f) = 0.1 * f - 0.3 * k + 1.0 / 3.0;
    if (k == 2) {
      l.printed_thickness(3) = 0.12;
      l.material(5) = Layer::kNotCovered;
      l.lambda1(1) = 0.6;
      l.cover(2) = 1.0 / 3.0;
    }
    d.stack.layers.push_back(l);
  }
  d.design_fields.set_face("theta1", Eigen::VectorXd::LinSpaced(nf, -1, 1));
  d.design_fields.set_vertex("theta2", Eigen::VectorXd::LinSpaced(p.V.rows(), 0.1, 0.7));
  return d;
}

void expect_same_stack(const LayerStack& a, const LayerStack& b) {
  ASSERT_EQ(a.num_layers(), b.num_layers());
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t m = 0; m < a.materials.size(); ++m) {
    EXPECT_EQ(material_json(a.materials[m]), material_json(b.materials[m]));
  }
  for (int k = 0; k < a.num_layers(); ++k) {
    const Layer &x = a.layers[k], &y = b.layers[k];
    EXPECT_EQ(x.printed_thickness, y.printed_thickness) << k;  // bit for bit
    EXPECT_EQ(x.material, y.material) << k;
    EXPECT_EQ(x.theta, y.theta) << k;
    EXPECT_EQ(x.lambda1, y.lambda1) << k;
    EXPECT_EQ(x.delta_lambda1, y.delta_lambda1) << k;
    EXPECT_EQ(x.lambda2, y.lambda2) << k;
    EXPECT_EQ(x.lambda3, y.lambda3) << k;
    EXPECT_EQ(x.cover, y.cover) << k;
  }
}

TEST(PlateDesignFile, ReadsBackBitForBit) {
  const fs::path dir = testing::scratch_dir();
  const PlateDesign d = two_material_design();
  write_plate_design(dir / "flat.ply", d);
  ASSERT_TRUE(fs::exists(dir / "flat.stack.json"));
  const PlateDesignFile back = read_plate_design(dir / "flat.ply", Material{}, 10);
  EXPECT_TRUE(back.from_stack_file);
  EXPECT_EQ(back.design.plate, d.plate);
  EXPECT_EQ(back.design.F, d.F);
  EXPECT_EQ(back.design.method, "test");
  expect_same_stack(back.design.stack, d.stack);
  ASSERT_NE(back.design.design_fields.find_face("theta1"), nullptr);
  EXPECT_EQ(*back.design.design_fields.find_face("theta1"), *d.design_fields.find_face("theta1"));
  EXPECT_EQ(*back.design.design_fields.find_vertex("theta2"),
            *d.design_fields.find_vertex("theta2"));
  // Only what varies over a layer's faces is a PLY property; the stack's own properties are not
  // design fields.
  const std::string stack = testing::read_file(dir / "flat.stack.json");
  EXPECT_NE(stack.find("\"layer_3_thickness\""), std::string::npos);
  EXPECT_NE(stack.find("\"layer_3_cover\""), std::string::npos);
  EXPECT_EQ(stack.find("\"layer_1_thickness\""), std::string::npos);
  EXPECT_EQ(back.design.design_fields.find_face("layer_1_theta"), nullptr);
  // Same design, same bytes.
  const std::string ply = testing::read_file(dir / "flat.ply");
  write_plate_design(dir / "flat.ply", back.design);
  EXPECT_EQ(testing::read_file(dir / "flat.ply"), ply);
  EXPECT_EQ(testing::read_file(dir / "flat.stack.json"), stack);
}

TEST(PlateDesignFile, AStackFileThatDoesNotMatchIsAClearError) {
  const fs::path dir = testing::scratch_dir();
  write_plate_design(dir / "flat.ply", two_material_design());
  const std::string stack = testing::read_file(dir / "flat.stack.json");
  const auto expect_error = [&](const std::string& text, const std::string& words) {
    write_text(dir / "flat.stack.json", text);
    try {
      read_plate_design(dir / "flat.ply", Material{}, 10);
      FAIL() << "expected an error mentioning " << words;
    } catch (const UserError& e) {
      // A bad material inside is the material reader's own error (kProfile), naming the file too.
      EXPECT_TRUE(e.category() == ErrorCategory::kFormat || e.category() == ErrorCategory::kProfile)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("flat.stack.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = stack;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  expect_error(replaced("\"faces\": 16", "\"faces\": 17"), "17 faces");
  expect_error(replaced("layer_3_thickness", "layer_9_thickness"), "layer_9_thickness");
  expect_error(replaced("\"lambda2\": 1.08", "\"lambda2\": -1.08"), "lambda2");
  expect_error(replaced("\"version\": 1", "\"version\": 7"), "version");
  expect_error("{ not json", "JSON");
  expect_error(replaced("\"material\": 1", "\"material\": 4"), "material");
}

TEST(PlateDesignFile, AnOlderFlatPlyIsReadWithTheGivenLayersAndMaterial) {
  const fs::path dir = testing::scratch_dir();
  const testing::TestPlate p = testing::rectangle_plate(20, 10, 4, 2);
  Mesh mesh{Eigen::MatrixXd::Zero(p.V.rows(), 3), p.F};
  mesh.V.leftCols(2) = p.V;
  MeshProperties properties;
  properties.set_face("theta1", Eigen::VectorXd::Constant(p.F.rows(), 0.4));
  write_ply(dir / "flat.ply", mesh, properties);
  Material m;
  m.name = "mine";
  m.layer_height = 0.1;
  const PlateDesignFile file = read_plate_design(dir / "flat.ply", m, 6);
  EXPECT_FALSE(file.from_stack_file);
  ASSERT_EQ(file.design.stack.num_layers(), 6);
  EXPECT_EQ(file.design.stack.materials[0].name, "mine");
  EXPECT_EQ(file.design.stack.layers[0].printed_thickness(0), 0.1);
  EXPECT_EQ(file.design.stack.layers[5].theta(0), 0.4);  // theta2 absent: 0
  properties = MeshProperties{};
  write_ply(dir / "flat.ply", mesh, properties);
  EXPECT_THROW(read_plate_design(dir / "flat.ply", m, 6), UserError);
}

// The fuzzer's seed (tests/data/stack) is a valid stack for its two-face plate, so that fuzzing
// starts inside the format.
TEST(PlateDesignFile, TheFuzzSeedIsAValidStack) {
  const fs::path dir = testing::scratch_dir();
  Mesh mesh;
  mesh.V.resize(4, 3);
  mesh.V << 0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0;
  mesh.F.resize(2, 3);
  mesh.F << 0, 1, 2, 0, 2, 3;
  MeshProperties properties;
  properties.set_face("layer_2_theta", Eigen::Vector2d(0.5, -0.25));
  write_ply(dir / "flat.ply", mesh, properties);
  fs::copy_file(testing::test_data_dir() / "stack" / "two_faces.stack.json",
                dir / "flat.stack.json");
  const PlateDesignFile file = read_plate_design(dir / "flat.ply", Material{}, 10);
  ASSERT_EQ(file.design.stack.num_layers(), 2);
  EXPECT_EQ(file.design.stack.materials[1].name, "tpu");
  EXPECT_EQ(file.design.stack.layers[1].theta(1), -0.25);
  // Written before layers had a cover: solid.
  EXPECT_EQ(file.design.stack.layers[1].cover, Eigen::Vector2d(1, 1));
}

// Issue 20's acceptance: the run's stack, not the defaults, decides what is printed and simulated.
TEST(PlateDesignCli, ToolpathsAndSimulateUseTheDesignedLayersAndMaterial) {
  const fs::path dir = testing::scratch_dir();
  const std::string run = (dir / "run").string();
  auto r = testing::run_cli({"design", "--example", "saddle", "--faces", "500", "--layers", "6",
                             "--material", "pla-generic", "--no-gcode", "-o", run});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing::run_cli({"toolpaths", run + "/flat.ply", "--printer", "generic-marlin", "-o",
                        (dir / "print").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 layers (0.48 mm printed) of pla-generic"), std::string::npos) << r.out;
  const std::string gcode = testing::read_file(dir / "print" / "plate.gcode");
  int layer_changes = 0;
  for (size_t at = 0; (at = gcode.find(";LAYER_CHANGE", at)) != std::string::npos; ++at) {
    ++layer_changes;
  }
  EXPECT_EQ(layer_changes, 6);
  EXPECT_NE(gcode.find("M109 S200"), std::string::npos);  // pla-generic's nozzle, not the paper's
  EXPECT_TRUE(fs::exists(dir / "print" / "layers" / "layer_006.svg"));
  EXPECT_FALSE(fs::exists(dir / "print" / "layers" / "layer_007.svg"));
  // `check` takes the run's materials from the stack file beside the G-code.
  fs::copy_file(run + "/flat.ply", dir / "print" / "flat.ply");
  fs::copy_file(run + "/flat.stack.json", dir / "print" / "flat.stack.json");
  r = testing::run_cli(
      {"check", (dir / "print" / "plate.gcode").string(), "--printer", "generic-marlin"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("with pla-generic (materials from"), std::string::npos) << r.out;
  // The prediction from the run's plate is the design's: same distances as design.json.
  r = testing::run_cli({"simulate", run + "/flat.ply", "--from", run + "/simulated.ply", "--target",
                        run + "/target.ply", "-o", (dir / "predicted.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 layers (0.48 mm printed) of pla-generic"), std::string::npos) << r.out;
  const std::string design = testing::read_file(run + "/design.json");
  const auto metric = [&](const std::string& key) {
    const size_t at = design.find("\"" + key + "\": ");
    return std::stod(design.substr(at + key.size() + 4));
  };
  const size_t at = r.out.find("distance to target: average ");
  ASSERT_NE(at, std::string::npos);
  const double avg = std::stod(r.out.substr(at + 28));
  EXPECT_NEAR(avg, metric("dist_to_optim_avg_pct"), 0.001);
  // The report says what the stack prints.
  r = testing::run_cli({"report", run});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::read_file(run + "/report.html").find("6 layers, 0.48 mm, of pla-generic"),
            std::string::npos);
  // Options the stack file decides are refused, not silently ignored.
  r = testing::run_cli(
      {"simulate", run + "/flat.ply", "--layers", "10", "-o", (dir / "x.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "x.ply"));
}

}  // namespace
}  // namespace flatmorph::plate_design_test
