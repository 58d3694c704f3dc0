#include "mesh/io.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "mesh/io_internal.h"
#include "test_support.h"

namespace flatmorph::io_test {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const fs::path& dir, const std::string& name, const std::string& bytes) {
  const fs::path path = dir / name;
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The error read_mesh throws; a test failure (and an empty error) when it throws nothing.
MeshReadError read_error(const fs::path& path) {
  try {
    read_mesh(path);
  } catch (const MeshReadError& e) {
    return e;
  }
  ADD_FAILURE() << "reading " << path << " should have failed";
  return MeshReadError(ErrorCategory::kResource, "", -1, -1);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Eigen::MatrixXi faces(std::initializer_list<std::array<int, 3>> rows) {
  Eigen::MatrixXi F(static_cast<Eigen::Index>(rows.size()), 3);
  int r = 0;
  for (const auto& row : rows) {
    F.row(r++) << row[0], row[1], row[2];
  }
  return F;
}

// Eigen's == assumes equal sizes; check them first.
template <class A, class B>
::testing::AssertionResult equal(const A& a, const B& b) {
  if (a.rows() == b.rows() && a.cols() == b.cols() && a == b) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "\n" << a << "\nis not\n" << b;
}

bool bitwise_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (std::bit_cast<std::uint64_t>(a.data()[i]) != std::bit_cast<std::uint64_t>(b.data()[i])) {
      return false;
    }
  }
  return true;
}

// Appends `value` as the PLY scalar type `type`, in either byte order.
void put(std::string& out, const std::string& type, double value, bool big_endian) {
  auto append = [&](auto v) {
    char raw[sizeof(v)];
    std::memcpy(raw, &v, sizeof(v));
    if (big_endian == (std::endian::native == std::endian::little)) {
      std::reverse(raw, raw + sizeof(v));
    }
    out.append(raw, sizeof(v));
  };
  if (type == "char" || type == "int8") {
    append(static_cast<std::int8_t>(value));
  } else if (type == "uchar" || type == "uint8") {
    append(static_cast<std::uint8_t>(value));
  } else if (type == "short" || type == "int16") {
    append(static_cast<std::int16_t>(value));
  } else if (type == "ushort" || type == "uint16") {
    append(static_cast<std::uint16_t>(value));
  } else if (type == "int" || type == "int32") {
    append(static_cast<std::int32_t>(value));
  } else if (type == "uint" || type == "uint32") {
    append(static_cast<std::uint32_t>(value));
  } else if (type == "float" || type == "float32") {
    append(static_cast<float>(value));
  } else if (type == "double" || type == "float64") {
    append(value);
  } else {
    ADD_FAILURE() << "unknown type " << type;
  }
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST(MeshIoObj, ReadsQuadsWithTextureNormalAndRelativeIndices) {
  const MeshFile file = read_mesh(testing::test_data_dir() / "mesh/quad.obj");
  ASSERT_EQ(file.mesh.num_vertices(), 7);
  EXPECT_TRUE(equal(file.mesh.V.row(5), Eigen::RowVector3d(2, 1, 0)));  // the line with tabs
  EXPECT_TRUE(equal(file.mesh.V.row(6), Eigen::RowVector3d(1.5, 2, 0)));
  // Quads are fanned from their first corner; -5 -2 -1 -4 after 6 vertices are 2 5 6 3.
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}, {2, 5, 6}})));
  EXPECT_TRUE(file.properties.vertex.empty());
  EXPECT_TRUE(file.properties.face.empty());
}

TEST(MeshIoObj, ToleratesCrLfTabsTrailingSpacesAndNoFinalNewline) {
  const auto dir = testing::scratch_dir();
  const auto path = write_file(dir, "crlf.OBJ",
                               "v 0 0 0\r\nv\t+1.5 0 0 \r\n\r\nv 0 1e1 -0.25\t\r\n# c\r\nf 1 2 3");
  const MeshFile file = read_mesh(path);
  ASSERT_EQ(file.mesh.num_vertices(), 3);
  EXPECT_TRUE(equal(file.mesh.V.row(1), Eigen::RowVector3d(1.5, 0, 0)));
  EXPECT_TRUE(equal(file.mesh.V.row(2), Eigen::RowVector3d(0, 10, -0.25)));
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}})));
}

TEST(MeshIoObj, RoundTripKeepsEveryDoubleBitForBit) {
  Mesh mesh;
  mesh.V.resize(4, 3);
  mesh.V << 1.0 / 3.0, -0.0, 1e-310,                         //
      std::numeric_limits<double>::max(), 5e-324, -2.5e-17,  //
      std::numbers::pi * 1e10, 0.1, -7,                      //
      123456789.123456789, -1e300, 2.0 / 3.0;
  mesh.F = faces({{0, 1, 2}, {0, 2, 3}});
  const auto dir = testing::scratch_dir();
  write_obj(dir / "m.obj", mesh);
  const MeshFile back = read_mesh(dir / "m.obj");
  EXPECT_TRUE(bitwise_equal(back.mesh.V, mesh.V)) << back.mesh.V;
  EXPECT_TRUE(equal(back.mesh.F, mesh.F));
}

TEST(MeshIoObj, FaceReferringToMissingVertexNamesFileLineAndCounts) {
  const MeshReadError e = read_error(testing::test_data_dir() / "mesh/bad_index.obj");
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(),
                       "bad_index.obj:6: face refers to vertex 7 but the file defines 4 "
                       "vertices"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 4);
  EXPECT_EQ(e.faces_read, 1);
}

TEST(MeshIoObj, IndexZeroIsAnError) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e = read_error(write_file(dir, "zero.obj",
                                                "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                "f 1 2 3\nf 0 1 2\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(), "zero.obj:5:")) << e.what();
  EXPECT_TRUE(contains(e.what(), "index 0")) << e.what();
  EXPECT_EQ(e.vertices_read, 3);
  EXPECT_EQ(e.faces_read, 1);
}

TEST(MeshIoObj, RelativeIndexBeforeTheFirstVertexIsAnError) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e =
      read_error(write_file(dir, "rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"));
  EXPECT_TRUE(contains(e.what(), "rel.obj:4: face refers to vertex -4")) << e.what();
  EXPECT_EQ(e.vertices_read, 3);
}

TEST(MeshIoObj, FaceWithTwoVerticesIsAnError) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e =
      read_error(write_file(dir, "two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(), "two.obj:5: a face needs at least 3 vertices, this one has 2"))
      << e.what();
  EXPECT_EQ(e.faces_read, 1);
}

TEST(MeshIoObj, NonNumberCoordinateIsAnError) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e =
      read_error(write_file(dir, "nan.obj", "v 0 0 0\nv 1 0x1 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(), "nan.obj:2: `0x1` is not a number")) << e.what();
  EXPECT_EQ(e.vertices_read, 1);
  EXPECT_EQ(e.faces_read, 0);
}

TEST(MeshIoObj, TextWithoutVerticesOrFacesIsAnError) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e = read_error(write_file(dir, "notes.obj", "hello\nworld\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(), "notes.obj: the file has no vertex")) << e.what();
}

// ---------------------------------------------------------------------------------------------
// PLY

void expect_extra_ply(const MeshFile& file) {
  ASSERT_EQ(file.mesh.num_vertices(), 5);
  EXPECT_TRUE(equal(file.mesh.V.row(4), Eigen::RowVector3d(0.5, 2, 0)));
  // The quad is fanned; the material and edge elements in between are skipped.
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {3, 2, 4}})));
  ASSERT_EQ(file.properties.vertex.size(), 2u);
  EXPECT_EQ(file.properties.vertex[0].name, "red");
  EXPECT_TRUE(equal(file.properties.vertex[0].values, Eigen::Vector<double, 5>(255, 128, 0, 7, 1)));
  EXPECT_EQ(file.properties.vertex[1].name, "quality");
  EXPECT_TRUE(equal(file.properties.vertex[1].values,
                    Eigen::Vector<double, 5>(0.5, 1.5, 2.5, -3.25, 1e-3)));
  ASSERT_EQ(file.properties.face.size(), 2u);
  EXPECT_EQ(file.properties.face[0].name, "flags");
  EXPECT_TRUE(equal(file.properties.face[0].values, Eigen::Vector3d(-2, -2, 7)));
  EXPECT_EQ(file.properties.face[1].name, "thickness");
  EXPECT_TRUE(equal(file.properties.face[1].values, Eigen::Vector3d(0.25, 0.25, 0.75)));
}

TEST(MeshIoPly, ReadsAsciiWithExtraPropertiesAndElements) {
  expect_extra_ply(read_mesh(testing::test_data_dir() / "mesh/extra.ply"));
}

// The same content as extra.ply, binary big endian.
std::string extra_ply_big_endian() {
  std::string header = read_file(testing::test_data_dir() / "mesh/extra.ply");
  header = header.substr(0, header.find("end_header\n") + 11);
  header.replace(header.find("ascii"), 5, "binary_big_endian");
  std::string out = header;
  const double vertices[5][5] = {{0, 0, 0, 255, 0.5},
                                 {1, 0, 0, 128, 1.5},
                                 {1, 1, 0, 0, 2.5},
                                 {0, 1, 0, 7, -3.25},
                                 {0.5, 2, 0, 1, 1e-3}};
  for (const auto& v : vertices) {
    for (int k = 0; k < 3; ++k) put(out, "float", v[k], true);
    put(out, "uchar", v[3], true);
    put(out, "double", v[4], true);
  }
  // material: a list of 3 then of 0 ids, and a shininess.
  put(out, "uchar", 3, true);
  for (int id : {0, 1, 2}) put(out, "int", id, true);
  put(out, "float", 0.5, true);
  put(out, "uchar", 0, true);
  put(out, "float", 1, true);
  put(out, "uchar", 4, true);
  for (int i : {0, 1, 2, 3}) put(out, "int", i, true);
  put(out, "int16", -2, true);
  put(out, "float", 0.25, true);
  put(out, "uchar", 3, true);
  for (int i : {3, 2, 4}) put(out, "int", i, true);
  put(out, "int16", 7, true);
  put(out, "float", 0.75, true);
  put(out, "int", 0, true);
  put(out, "int", 4, true);
  return out;
}

TEST(MeshIoPly, ReadsBinaryBigEndianWithExtraPropertiesAndElements) {
  const auto dir = testing::scratch_dir();
  expect_extra_ply(read_mesh(write_file(dir, "extra_be.ply", extra_ply_big_endian())));
}

TEST(MeshIoPly, ReadsEveryScalarTypeAndAliasInEveryEncoding) {
  // Each type with a value at the edge of its range.
  const std::vector<std::pair<std::string, double>> props = {
      {"char", -128},        {"int8", 127},           {"uchar", 255},        {"uint8", 200},
      {"short", -32768},     {"int16", 32767},        {"ushort", 65535},     {"uint16", 1},
      {"int", -2147483648.}, {"int32", 2147483647},   {"uint", 4294967295.}, {"uint32", 3},
      {"float", 0.25},       {"float32", -0x1.8p100}, {"double", 0.1},       {"float64", 1e300}};
  const double xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (const std::string encoding : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(encoding);
    const bool big = encoding == "binary_big_endian";
    std::string out = "ply\r\nformat " + encoding + " 1.0\r\nelement vertex 3\r\n";
    for (const char* axis : {"x", "y", "z"}) out += std::string("property float64 ") + axis + "\n";
    for (const auto& [type, value] : props) out += "property " + type + " p_" + type + "\n";
    // The alternative index list name, with unusual count and index types.
    out += "element face 1\nproperty int8 tag\nproperty list ushort uint vertex_index\n";
    out += "end_header\n";
    for (const auto& v : xyz) {
      if (encoding == "ascii") {
        out += fmt::format("{} {} {}", v[0], v[1], v[2]);
        for (const auto& p : props) out += fmt::format(" {}", p.second);
        out += "\n";
      } else {
        for (double c : v) put(out, "double", c, big);
        for (const auto& [type, value] : props) put(out, type, value, big);
      }
    }
    if (encoding == "ascii") {
      out += "-5 3 2 0 1";  // no final newline
    } else {
      put(out, "int8", -5, big);
      put(out, "ushort", 3, big);
      for (int i : {2, 0, 1}) put(out, "uint", i, big);
    }
    const auto dir = testing::scratch_dir();
    const MeshFile file = read_mesh(write_file(dir, "types.ply", out));
    ASSERT_EQ(file.mesh.num_vertices(), 3);
    EXPECT_TRUE(equal(file.mesh.V.row(1), Eigen::RowVector3d(1, 0, 0)));
    EXPECT_TRUE(equal(file.mesh.F, faces({{2, 0, 1}})));
    ASSERT_EQ(file.properties.vertex.size(), props.size());
    for (std::size_t j = 0; j < props.size(); ++j) {
      EXPECT_EQ(file.properties.vertex[j].name, "p_" + props[j].first);
      EXPECT_TRUE(
          equal(file.properties.vertex[j].values, Eigen::Vector3d::Constant(props[j].second)))
          << props[j].first;
    }
    ASSERT_EQ(file.properties.face.size(), 1u);
    EXPECT_TRUE(equal(file.properties.face[0].values, Eigen::VectorXd::Constant(1, -5)));
  }
}

Mesh two_triangles() {
  Mesh mesh;
  mesh.V.resize(4, 3);
  mesh.V << 0.1, -0.0, 1e-310,                         //
      1.0 / 3.0, 2, 3,                                 //
      -4e10, 5.5, std::numeric_limits<double>::max(),  //
      7, 8, 9;
  mesh.F = faces({{0, 1, 2}, {2, 1, 3}});
  return mesh;
}

MeshProperties two_triangle_properties() {
  MeshProperties properties;
  properties.set_vertex("theta2", Eigen::Vector4d(0.1, -std::numbers::pi, 1e-300, 2.0 / 7.0));
  properties.set_vertex("deviation_mm", Eigen::Vector4d(1, 2, 3, 4));
  properties.set_face("theta1", Eigen::Vector2d(std::numbers::pi / 3, -0.0));
  return properties;
}

TEST(MeshIoPly, RoundTripInEveryEncodingIsBitExact) {
  const Mesh mesh = two_triangles();
  const MeshProperties properties = two_triangle_properties();
  const auto dir = testing::scratch_dir();
  for (const PlyEncoding encoding :
       {PlyEncoding::kAscii, PlyEncoding::kBinaryLittleEndian, PlyEncoding::kBinaryBigEndian}) {
    SCOPED_TRACE(static_cast<int>(encoding));
    write_ply(dir / "m.ply", mesh, properties, encoding);
    const MeshFile back = read_mesh(dir / "m.ply");
    EXPECT_TRUE(bitwise_equal(back.mesh.V, mesh.V)) << back.mesh.V;
    EXPECT_TRUE(equal(back.mesh.F, mesh.F));
    ASSERT_EQ(back.properties.vertex.size(), 2u);
    ASSERT_EQ(back.properties.face.size(), 1u);
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(back.properties.vertex[j].name, properties.vertex[j].name);
      EXPECT_TRUE(bitwise_equal(back.properties.vertex[j].values, properties.vertex[j].values));
    }
    EXPECT_EQ(back.properties.face[0].name, "theta1");
    EXPECT_TRUE(bitwise_equal(back.properties.face[0].values, properties.face[0].values));
  }
}

TEST(MeshIoPly, WritesAStandardDeterministicHeader) {
  const auto dir = testing::scratch_dir();
  write_ply(dir / "a.ply", two_triangles(), two_triangle_properties(),
            PlyEncoding::kBinaryLittleEndian);
  write_ply(dir / "b.ply", two_triangles(), two_triangle_properties(),
            PlyEncoding::kBinaryLittleEndian);
  const std::string a = read_file(dir / "a.ply");
  EXPECT_EQ(a, read_file(dir / "b.ply"));
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment flatmorph\nelement vertex 4\n"
      "property double x\nproperty double y\nproperty double z\nproperty double theta2\n"
      "property double deviation_mm\nelement face 2\nproperty list uchar int vertex_indices\n"
      "property double theta1\nend_header\n";
  EXPECT_EQ(a.substr(0, header.size()), header);
  // 4 vertices of 5 doubles, 2 faces of a count byte, 3 ints and a double.
  EXPECT_EQ(a.size(), header.size() + 4 * 5 * 8 + 2 * (1 + 12 + 8));
}

TEST(MeshIoPly, WriterRejectsPropertiesOfTheWrongSizeOrName) {
  const auto dir = testing::scratch_dir();
  MeshProperties wrong;
  wrong.set_vertex("theta2", Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(write_ply(dir / "a.ply", two_triangles(), wrong), std::invalid_argument);
  MeshProperties wrong_face;
  wrong_face.set_face("theta1", Eigen::Vector4d(1, 2, 3, 4));
  EXPECT_THROW(write_ply(dir / "a.ply", two_triangles(), wrong_face), std::invalid_argument);
  MeshProperties spaced;
  spaced.set_face("theta 1", Eigen::Vector2d(1, 2));
  EXPECT_THROW(write_ply(dir / "a.ply", two_triangles(), spaced), std::invalid_argument);
  MeshProperties clash;
  clash.set_vertex("x", Eigen::Vector4d(1, 2, 3, 4));
  EXPECT_THROW(write_ply(dir / "a.ply", two_triangles(), clash), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(MeshIoPly, AsciiDataShorterThanTheHeaderSays) {
  const auto dir = testing::scratch_dir();
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0.000 0.000 0.000\n1.000 0.000 0.000\n0.000 1.000 0.000\n";
  const MeshReadError e = read_error(write_file(dir, "short.ply", text));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(),
                       "short.ply: the header announces 4 vertices but the data ends "
                       "after 3; the file is truncated"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 3);
  EXPECT_EQ(e.faces_read, 0);
}

TEST(MeshIoPly, BinaryDataShorterThanTheHeaderSays) {
  Mesh mesh;
  mesh.V = Eigen::MatrixXd::Random(50, 3);
  mesh.F.resize(40, 3);
  for (int f = 0; f < 40; ++f) mesh.F.row(f) << f, f + 1, f + 2;
  const auto dir = testing::scratch_dir();
  write_ply(dir / "full.ply", mesh, {}, PlyEncoding::kBinaryBigEndian);
  const std::string full = read_file(dir / "full.ply");
  // Cut in the middle of face 30 (13 bytes per face).
  const std::string cut = full.substr(0, full.size() - 9 * 13 - 5);
  const MeshReadError e = read_error(write_file(dir, "cut.ply", cut));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(),
                       "cut.ply: the header announces 40 faces but the data ends after "
                       "30; the file is truncated"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 50);
  EXPECT_EQ(e.faces_read, 30);
}

TEST(MeshIoPly, HeaderClaimingTwoBillionVerticesIsRejectedWithoutAllocating) {
  const auto dir = testing::scratch_dir();
  for (const std::string encoding : {"ascii", "binary_little_endian"}) {
    const std::string text = "ply\nformat " + encoding +
                             " 1.0\nelement vertex 2000000000\nproperty float x\nproperty float "
                             "y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    const MeshReadError e = read_error(write_file(dir, "huge.ply", text));
    EXPECT_EQ(e.category(), ErrorCategory::kFormat);
    EXPECT_TRUE(contains(e.what(),
                         "huge.ply:3: the header announces 2000000000 vertices but the "
                         "18 bytes of data left can hold at most"))
        << e.what();
    EXPECT_EQ(e.vertices_read, 0);
  }
}

TEST(MeshIoPly, FaceIndexOutOfRangeNamesTheLine) {
  const auto dir = testing::scratch_dir();
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n";
  const MeshReadError e = read_error(write_file(dir, "idx.ply", text));
  EXPECT_TRUE(contains(e.what(),
                       "idx.ply:14: face refers to vertex 3 but the file defines 3 "
                       "vertices"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 3);
  EXPECT_EQ(e.faces_read, 1);
}

TEST(MeshIoPly, NonNumberAndMissingHeaderPartsAreErrors) {
  const auto dir = testing::scratch_dir();
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  MeshReadError e = read_error(write_file(dir, "nan.ply", head + "0 zero 0\n"));
  EXPECT_TRUE(contains(e.what(), "nan.ply:8: `zero` is not a number")) << e.what();
  e = read_error(write_file(dir, "noply.ply", "solid x\n"));
  EXPECT_TRUE(contains(e.what(), "noply.ply:1: the file does not start with `ply`")) << e.what();
  e = read_error(write_file(dir, "noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"));
  EXPECT_TRUE(contains(e.what(), "no `end_header`")) << e.what();
  e = read_error(write_file(dir, "noz.ply",
                            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                            "property float y\nend_header\n0 0\n"));
  EXPECT_TRUE(contains(e.what(), "noz.ply:3: the vertex element lacks")) << e.what();
  e = read_error(write_file(dir, "type.ply",
                            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n"));
  EXPECT_TRUE(contains(e.what(), "type.ply:4: unknown property type `float128`")) << e.what();
}

// ---------------------------------------------------------------------------------------------
// STL

// A binary STL of the tetrahedron in tetra_ascii.stl; the comment starts with "solid".
std::string tetra_binary_stl(std::uint32_t announced) {
  std::string out = "solid tetra, but binary";
  out.resize(80, ' ');
  put(out, "uint", announced, false);
  const float corners[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                                  {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                                  {{-0.f, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                  {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const auto& triangle : corners) {
    for (int k = 0; k < 3; ++k) put(out, "float", 0, false);  // normal
    for (const auto& corner : triangle) {
      for (float c : corner) put(out, "float", c, false);
    }
    out += std::string(2, '\0');
  }
  return out;
}

void expect_tetra(const MeshFile& file) {
  // 12 corners welded into 4 vertices, numbered as they first appear (-0 is 0).
  ASSERT_EQ(file.mesh.num_vertices(), 4);
  Eigen::MatrixXd V(4, 3);
  V << 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_TRUE(equal(file.mesh.V, V));
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {2, 1, 3}})));
}

TEST(MeshIoStl, AsciiCornersAreWelded) {
  expect_tetra(read_mesh(testing::test_data_dir() / "mesh/tetra_ascii.stl"));
}

TEST(MeshIoStl, BinaryWithSolidHeaderCornersAreWelded) {
  const auto dir = testing::scratch_dir();
  const std::string bytes = tetra_binary_stl(4);
  ASSERT_EQ(bytes.size(), 84u + 4 * 50);
  expect_tetra(read_mesh(write_file(dir, "tetra.stl", bytes)));
}

TEST(MeshIoStl, TruncatedBinaryIsAnError) {
  const auto dir = testing::scratch_dir();
  const std::string bytes = tetra_binary_stl(5);
  const MeshReadError e = read_error(write_file(dir, "part.stl", bytes));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(),
                       "part.stl: binary STL header announces 5 triangles (334 bytes) "
                       "but the file has 284 bytes; the file is truncated"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 0);
  EXPECT_EQ(e.faces_read, 0);
}

TEST(MeshIoStl, AsciiFacetCutShortIsAnError) {
  const std::string text = read_file(testing::test_data_dir() / "mesh/tetra_ascii.stl");
  const auto dir = testing::scratch_dir();
  const MeshReadError e = read_error(
      write_file(dir, "cut.stl", text.substr(0, text.find("endloop", text.find("normal -1")))));
  EXPECT_TRUE(contains(e.what(), "cut.stl: the file ends inside the facet that starts on line 16"))
      << e.what();
  EXPECT_EQ(e.faces_read, 2);
  EXPECT_EQ(e.vertices_read, 4);
}

// ---------------------------------------------------------------------------------------------
// OFF

TEST(MeshIoOff, ReadsCommentsBlankLinesAndAQuad) {
  const MeshFile file = read_mesh(testing::test_data_dir() / "mesh/quad.off");
  ASSERT_EQ(file.mesh.num_vertices(), 5);
  EXPECT_TRUE(equal(file.mesh.V.row(3), Eigen::RowVector3d(0, 1, 0)));
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}, {0, 2, 3}, {3, 2, 4}})));
}

TEST(MeshIoOff, ColourHeaderWithExtraValuesAndCountsOnTheHeaderLine) {
  const auto dir = testing::scratch_dir();
  const MeshFile file = read_mesh(
      write_file(dir, "c.off",
                 "COFF 3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2"));
  EXPECT_EQ(file.mesh.num_vertices(), 3);
  EXPECT_TRUE(equal(file.mesh.F, faces({{0, 1, 2}})));
  const MeshFile noff = read_mesh(
      write_file(dir, "n.off", "NOFF\n3 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 2 1 0\n"));
  EXPECT_TRUE(equal(noff.mesh.F, faces({{2, 1, 0}})));
}

TEST(MeshIoOff, HeaderClaimingTwoBillionVerticesIsRejected) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e = read_error(
      write_file(dir, "huge.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_TRUE(contains(e.what(), "huge.off:2: the header announces 2000000000 vertices"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 0);
}

TEST(MeshIoOff, FaceErrorsNameTheLine) {
  const auto dir = testing::scratch_dir();
  const std::string head = "OFF\n3 2 0\n0.00 0.00 0.00\n1.00 0.00 0.00\n0.00 1.00 0.00\n3 0 1 2\n";
  MeshReadError e = read_error(write_file(dir, "two.off", head + "2 0 1\n"));
  EXPECT_TRUE(contains(e.what(), "two.off:7: a face needs at least 3 vertices, this one has 2"))
      << e.what();
  EXPECT_EQ(e.vertices_read, 3);
  EXPECT_EQ(e.faces_read, 1);
  e = read_error(write_file(dir, "idx.off", head + "3 0 1 3\n"));
  EXPECT_TRUE(contains(e.what(), "idx.off:7: face refers to vertex 3 but the file defines 3"))
      << e.what();
  e = read_error(write_file(dir, "cut.off", head));
  EXPECT_TRUE(contains(e.what(), "cut.off: the header announces 2 faces but the data ends after 1"))
      << e.what();
}

// ---------------------------------------------------------------------------------------------
// Errors common to every format

TEST(MeshIoErrors, EmptyFileInEveryFormat) {
  const auto dir = testing::scratch_dir();
  for (const std::string ext : {"obj", "ply", "stl", "off"}) {
    const MeshReadError e = read_error(write_file(dir, "empty." + ext, ""));
    EXPECT_EQ(e.category(), ErrorCategory::kFormat);
    EXPECT_TRUE(contains(e.what(), "empty." + ext + ": the file is empty")) << e.what();
    EXPECT_EQ(e.vertices_read, 0);
  }
}

TEST(MeshIoErrors, UnknownExtensionListsTheSupportedOnes) {
  const auto dir = testing::scratch_dir();
  const MeshReadError e = read_error(write_file(dir, "mesh.xyz", "v 0 0 0\n"));
  EXPECT_EQ(e.category(), ErrorCategory::kFile);
  EXPECT_TRUE(contains(e.what(), "mesh.xyz: unknown mesh file extension \".xyz\"")) << e.what();
  EXPECT_TRUE(contains(e.what(), ".obj, .ply, .stl, .off")) << e.what();
  EXPECT_THROW(write_mesh(dir / "out.stl", two_triangles()), UserError);
}

TEST(MeshIoErrors, MissingFileAndFolder) {
  const auto dir = testing::scratch_dir();
  MeshReadError e = read_error(dir / "missing.obj");
  EXPECT_EQ(e.category(), ErrorCategory::kFile);
  EXPECT_TRUE(contains(e.what(), "missing.obj: no such file")) << e.what();
  fs::create_directory(dir / "folder.ply");
  e = read_error(dir / "folder.ply");
  EXPECT_EQ(e.category(), ErrorCategory::kFile);
  EXPECT_TRUE(contains(e.what(), "folder.ply: is a folder")) << e.what();
}

TEST(MeshIoErrors, WritersRefuseAShapeThatIsNotFinite) {
  const auto dir = testing::scratch_dir();
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    Mesh mesh = two_triangles();
    mesh.V(2, 1) = bad;
    EXPECT_THROW(write_mesh(dir / "a.ply", mesh), std::invalid_argument);
    EXPECT_THROW(write_mesh(dir / "a.obj", mesh), std::invalid_argument);
    EXPECT_THROW(ply_bytes(mesh), std::invalid_argument);
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(MeshIoErrors, WriteMeshChoosesTheWriterByExtension) {
  const auto dir = testing::scratch_dir();
  write_mesh(dir / "a.OBJ", two_triangles(), two_triangle_properties());
  write_mesh(dir / "a.ply", two_triangles(), two_triangle_properties());
  EXPECT_EQ(read_file(dir / "a.OBJ").substr(0, 13), "# flatmorph\nv");
  EXPECT_EQ(read_file(dir / "a.ply").substr(0, 36), "ply\nformat binary_little_endian 1.0\n");
  EXPECT_EQ(read_mesh(dir / "a.ply").properties.vertex.size(), 2u);
}

// ---------------------------------------------------------------------------------------------
// The paper's meshes

TEST(MeshIoSharedMeshes, HatHasTheExpectedCounts) {
  const MeshFile file = read_mesh(testing::shared_dir() / "meshes/hat.obj");
  EXPECT_EQ(file.mesh.num_vertices(), 1409);
  EXPECT_EQ(file.mesh.num_faces(), 2752);
  // The first line of hat.obj.
  EXPECT_TRUE(equal(file.mesh.V.row(0), Eigen::RowVector3d(0.096018, 6.665190, 0.044045)));
}

TEST(MeshIoSharedMeshes, EveryPaperMeshHasItsLineCounts) {
  const std::vector<std::tuple<std::string, int, int>> expected = {
      {"beetle", 1131, 2112},   {"face", 529, 999},
      {"hat", 1409, 2752},      {"hemisphere-big", 562, 1072},
      {"hemisphere", 432, 812}, {"saddle", 1089, 2048},
      {"top", 517, 896}};
  for (const auto& [name, nv, nf] : expected) {
    const MeshFile file = read_mesh(testing::shared_dir() / "meshes" / (name + ".obj"));
    EXPECT_EQ(file.mesh.num_vertices(), nv) << name;
    EXPECT_EQ(file.mesh.num_faces(), nf) << name;
    EXPECT_GE(file.mesh.F.minCoeff(), 0) << name;
    EXPECT_LT(file.mesh.F.maxCoeff(), nv) << name;
  }
}

// ---------------------------------------------------------------------------------------------
// Robustness: every prefix and many corruptions of valid files either read into a consistent mesh
// or give a MeshReadError (run under the sanitizers to catch memory errors too).

void expect_consistent_or_error(std::string_view bytes, mesh_io::MeshFormat format) {
  try {
    const MeshFile file = mesh_io::read_mesh_bytes(bytes, "fuzz", format);
    ASSERT_EQ(file.mesh.V.cols(), 3);
    ASSERT_EQ(file.mesh.F.cols(), 3);
    if (file.mesh.num_faces() > 0) {
      ASSERT_GE(file.mesh.F.minCoeff(), 0);
      ASSERT_LT(file.mesh.F.maxCoeff(), file.mesh.num_vertices());
    }
    for (const auto& p : file.properties.vertex) ASSERT_EQ(p.values.size(), file.mesh.V.rows());
    for (const auto& p : file.properties.face) ASSERT_EQ(p.values.size(), file.mesh.F.rows());
  } catch (const MeshReadError& e) {
    ASSERT_EQ(e.category(), ErrorCategory::kFormat);
    ASSERT_TRUE(contains(e.what(), "fuzz")) << e.what();
  }
}

TEST(MeshIoRobustness, TruncationsAndCorruptionsGiveAMeshOrAMeshReadError) {
  using mesh_io::MeshFormat;
  const auto dir = testing::scratch_dir();
  write_ply(dir / "le.ply", two_triangles(), two_triangle_properties(),
            PlyEncoding::kBinaryLittleEndian);
  const std::vector<std::pair<std::string, MeshFormat>> inputs = {
      {read_file(testing::test_data_dir() / "mesh/quad.obj"), MeshFormat::kObj},
      {read_file(testing::test_data_dir() / "mesh/extra.ply"), MeshFormat::kPly},
      {extra_ply_big_endian(), MeshFormat::kPly},
      {read_file(dir / "le.ply"), MeshFormat::kPly},
      {read_file(testing::test_data_dir() / "mesh/tetra_ascii.stl"), MeshFormat::kStl},
      {tetra_binary_stl(4), MeshFormat::kStl},
      {read_file(testing::test_data_dir() / "mesh/quad.off"), MeshFormat::kOff}};
  const unsigned char replacements[] = {0, '\n', ' ', '9', '-', 0xff, '/', '#'};
  for (const auto& [bytes, format] : inputs) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      expect_consistent_or_error(std::string_view(bytes).substr(0, n), format);
      std::string corrupted = bytes;
      for (const unsigned char r : replacements) {
        corrupted[n] = static_cast<char>(r);
        expect_consistent_or_error(corrupted, format);
      }
    }
  }
}

}  // namespace
}  // namespace flatmorph::io_test
