// `flatmorph info` and `flatmorph example` as a user runs them: exit codes, one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "test_support.h"

namespace flatmorph::cli_info_test {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A 3x3-vertex grid square (8 triangles) as OBJ lines, vertex indices from 1.
std::string grid_obj() {
  std::string s;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) s += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  }
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const int a = 1 + i + 3 * j, b = a + 1, c = a + 3, d = c + 1;
      s += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + "\n";
      s += "f " + std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(c) + "\n";
    }
  }
  return s;
}

void expect_one_line_error(const testing::CliResult& r, const std::string& must_contain) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(must_contain), std::string::npos) << r.err;
}

TEST(CliInfo, PaperHatIsAValidDisk) {
  const auto r = run_cli({"info", (testing::shared_dir() / "meshes" / "hat.obj").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vertices:             1409"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("faces:                2752"), std::string::npos);
  EXPECT_NE(r.out.find("boundary loops:       1"), std::string::npos);
  EXPECT_NE(r.out.find("valid:                yes"), std::string::npos);
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST(CliInfo, JsonOutputOfAnExample) {
  const auto r = run_cli({"info", "--example", "saddle", "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"valid\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"euler_characteristic\": 1"), std::string::npos);
}

TEST(CliInfo, ClosedMeshIsRejected) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "tetra.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  const auto r = run_cli({"info", (dir / "tetra.obj").string()});
  expect_one_line_error(r, "closed");
  EXPECT_NE(r.out.find("faces:                4"), std::string::npos) << r.out;
}

TEST(CliInfo, TwoHolesAreRejected) {
  const fs::path dir = testing::scratch_dir();
  std::string s;
  // A 7x4-vertex grid with two interior cells removed.
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 7; ++i) s += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 6; ++i) {
      if (j == 1 && (i == 1 || i == 4)) continue;
      const int a = 1 + i + 7 * j, b = a + 1, c = a + 7, d = c + 1;
      s += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + "\n";
      s += "f " + std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(c) + "\n";
    }
  }
  write_text(dir / "holes.obj", s);
  const auto r = run_cli({"info", (dir / "holes.obj").string()});
  expect_one_line_error(r, "hole");
  EXPECT_NE(r.out.find("boundary loops:       3"), std::string::npos) << r.out;
}

TEST(CliInfo, NonManifoldEdgeIsRejected) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "fin.obj", grid_obj() + "v 1 1 1\nf 5 6 10\n");  // a third face on edge (5,6)
  const auto r = run_cli({"info", (dir / "fin.obj").string()});
  expect_one_line_error(r, "non-manifold");
}

TEST(CliInfo, NanCoordinateIsRejected) {
  const fs::path dir = testing::scratch_dir();
  std::string s = grid_obj();
  s.replace(s.find("v 1 1 0"), 7, "v 1 nan 0");
  write_text(dir / "nan.obj", s);
  const auto r = run_cli({"info", (dir / "nan.obj").string()});
  expect_one_line_error(r, "nan.obj");
  EXPECT_NE(r.err.find("NaN"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("vertices:             9"), std::string::npos) << r.out;
}

TEST(CliInfo, FaceIndexingMissingVertexIsRejected) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "missing.obj", grid_obj() + "f 1 2 42\n");
  const auto r = run_cli({"info", (dir / "missing.obj").string()});
  expect_one_line_error(r, "42");
  EXPECT_NE(r.out.find("read before the error"), std::string::npos) << r.out;
}

TEST(CliInfo, TruncatedBinaryStlIsRejected) {
  const fs::path dir = testing::scratch_dir();
  std::string stl(80, ' ');
  const uint32_t count = 10;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  stl.append(50 * 3, '\0');  // 3 of the 10 announced triangles
  write_text(dir / "cut.stl", stl);
  const auto r = run_cli({"info", (dir / "cut.stl").string()});
  expect_one_line_error(r, "truncated");
}

TEST(CliInfo, PlyShorterThanHeaderIsRejected) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "short.ply",
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n");
  const auto r = run_cli({"info", (dir / "short.ply").string()});
  expect_one_line_error(r, "short.ply");
  EXPECT_NE(r.out.find("4 vertices, 1 faces"), std::string::npos) << r.out;
}

TEST(CliInfo, EmptyFileIsRejected) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "empty.obj", "");
  const auto r = run_cli({"info", (dir / "empty.obj").string()});
  expect_one_line_error(r, "empty");
}

TEST(CliInfo, MissingArgumentsAndUnknownExample) {
  expect_one_line_error(run_cli({"info"}), "no target surface");
  expect_one_line_error(run_cli({"info", "--example", "teapot"}), "dome");
}

TEST(CliExample, WritesEveryExampleAsAValidMesh) {
  const fs::path dir = testing::scratch_dir();
  for (const std::string name : {"dome", "saddle", "paraboloid", "bump"}) {
    const fs::path out = dir / (name + ".ply");
    const auto w = run_cli({"example", name, "-o", out.string()});
    ASSERT_EQ(w.exit_code, 0) << w.err;
    const auto r = run_cli({"info", out.string()});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
  }
}

TEST(CliGeneral, VersionHelpAndBadCommand) {
  const auto v = run_cli({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("flatmorph 0."), std::string::npos);
  const auto h = run_cli({"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("info"), std::string::npos);
  const auto bad = run_cli({"frobnicate"});
  EXPECT_EQ(bad.exit_code, 2);
}

}  // namespace
}  // namespace flatmorph::cli_info_test
