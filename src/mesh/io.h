// Reading and writing triangle meshes: OBJ, PLY (ASCII, binary little/big endian), STL (ASCII and
// binary), OFF. Coordinates are stored as they are in the file (no unit conversion).
#pragma once

#include <filesystem>
#include <string>

#include "common/error.h"
#include "mesh/mesh.h"

namespace flatmorph {

// What a file held: the mesh and the named scalar properties it carried (PLY only).
struct MeshFile {
  Mesh mesh;
  MeshProperties properties;
};

// Thrown by read_mesh when a file is malformed. Carries what could be read before the problem, so
// that `flatmorph info` can still show it. Category is kFormat (or kFile when it cannot be opened).
class MeshReadError : public UserError {
 public:
  MeshReadError(ErrorCategory category, const std::string& message, int vertices_read,
                int faces_read)
      : UserError(category, message), vertices_read(vertices_read), faces_read(faces_read) {}
  int vertices_read;
  int faces_read;
};

// Reads OBJ, PLY, STL or OFF, chosen by extension (case-insensitive) and checked against the
// content.
// - OBJ: `v` and `f` lines; faces in v, v/vt, v//vn, v/vt/vn forms, negative (relative) indices,
//   polygons fan-triangulated; other statements ignored.
// - PLY: ascii, binary_little_endian, binary_big_endian; every scalar type; extra element and
//   property types tolerated and skipped; `vertex` scalar properties other than x, y, z and `face`
//   scalar properties other than the index list are returned as named properties (as doubles).
// - STL: ASCII and binary (told apart by content, not by the word "solid"); coincident corners are
//   welded exactly (bitwise-equal coordinates) so that the result is an indexed mesh.
// - OFF: with optional comments, polygons fan-triangulated.
// Throws MeshReadError naming the file, the line (or byte offset), and what is wrong: unknown
// extension, empty file, truncated data, a count in a header larger than the file can hold, a face
// index out of range, a non-number where a number belongs, a face with fewer than 3 vertices.
// NaN/Inf coordinates are read as they are; diagnose_mesh reports them.
MeshFile read_mesh(const std::filesystem::path& path);

enum class PlyEncoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

// Both writers refuse (std::invalid_argument) a mesh whose coordinates are not all finite: a NaN
// shape is a failed computation, never an output.

// Writes Wavefront OBJ (vertices and triangles; properties are not stored in OBJ).
// Numbers are written with enough digits to read back the same doubles.
void write_obj(const std::filesystem::path& path, const Mesh& mesh);

// Writes PLY with x, y, z as double and the named per-vertex / per-face properties as double
// properties (readable by MeshLab and Blender). The file is written to a temporary name and renamed
// when complete. Throws UserError(kFile) when it cannot be written, and std::invalid_argument when
// a property's size does not match the mesh.
void write_ply(const std::filesystem::path& path, const Mesh& mesh,
               const MeshProperties& properties = {},
               PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

// The bytes write_ply writes, for outputs that go into a folder written as one (a run folder).
std::string ply_bytes(const Mesh& mesh, const MeshProperties& properties = {},
                      PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

// Chooses the writer by extension (.obj or .ply); PLY is written binary little endian.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh,
                const MeshProperties& properties = {});

}  // namespace flatmorph
