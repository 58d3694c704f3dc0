#include "mesh/io.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "common/memory.h"
#include "mesh/io_internal.h"

namespace flatmorph {
namespace mesh_io {
namespace {

constexpr const char* kSupportedExtensions = ".obj, .ply, .stl, .off";

int clamp_to_int(long long n) { return static_cast<int>(std::min<long long>(n, INT_MAX)); }

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

[[noreturn]] void fail_file(const std::string& name, const std::string& problem) {
  throw MeshReadError(ErrorCategory::kFile, fmt::format("{}: {}", name, problem), 0, 0);
}

// The whole file in memory: every reader parses from a buffer, which keeps them linear and lets
// them check counts against the real size before allocating anything.
std::string read_whole_file(const std::filesystem::path& path, const std::string& name) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    fail_file(name, "no such file; check the path");
  }
  if (std::filesystem::is_directory(status)) {
    fail_file(name, "is a folder, not a mesh file; give the path of a mesh file");
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) {
    fail_file(name, fmt::format("cannot open the file ({}); check its permissions",
                                std::strerror(errno)));
  }
  std::string bytes;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) {
    // The file in memory, the arrays parsed from it and the welding/topology tables built next:
    // a few times the file's size. Refused up front rather than killed by the kernel half-way.
    require_memory(4 * static_cast<std::uint64_t>(size),
                   fmt::format("{}: reading this {:.0f} MB mesh", name, size / 1e6),
                   "use a smaller mesh (decimate it, e.g. with MeshLab's quadric edge collapse)");
    bytes.reserve(static_cast<std::size_t>(size));
  }
  char chunk[1 << 16];
  for (;;) {
    const std::size_t n = std::fread(chunk, 1, sizeof chunk, file.get());
    bytes.append(chunk, n);
    if (n < sizeof chunk) break;
  }
  if (std::ferror(file.get())) {
    fail_file(name, "reading the file failed; check that it is a readable regular file");
  }
  return bytes;
}

}  // namespace

MeshFile read_mesh_bytes(std::string_view bytes, const std::string& name, MeshFormat format) {
  if (bytes.empty()) fail(name, "the file is empty; export the mesh again", {});
  switch (format) {
    case MeshFormat::kObj:
      return read_obj(bytes, name);
    case MeshFormat::kPly:
      return read_ply(bytes, name);
    case MeshFormat::kStl:
      return read_stl(bytes, name);
    case MeshFormat::kOff:
      return read_off(bytes, name);
  }
  fail(name, "unknown mesh format", {});
}

void fail_at_line(const std::string& name, long long line, const std::string& problem,
                  Progress progress) {
  throw MeshReadError(ErrorCategory::kFormat, fmt::format("{}:{}: {}", name, line, problem),
                      clamp_to_int(progress.vertices), clamp_to_int(progress.faces));
}

void fail_at_byte(const std::string& name, std::size_t offset, const std::string& problem,
                  Progress progress) {
  throw MeshReadError(ErrorCategory::kFormat, fmt::format("{}: byte {}: {}", name, offset, problem),
                      clamp_to_int(progress.vertices), clamp_to_int(progress.faces));
}

void fail(const std::string& name, const std::string& problem, Progress progress) {
  throw MeshReadError(ErrorCategory::kFormat, fmt::format("{}: {}", name, problem),
                      clamp_to_int(progress.vertices), clamp_to_int(progress.faces));
}

bool next_line(LineScanner& scanner, std::string_view& line) {
  const std::string_view text = scanner.text;
  std::size_t start = scanner.position;
  if (start >= text.size()) return false;
  std::size_t end = start;
  while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
  line = text.substr(start, end - start);
  if (end < text.size()) {
    end += (text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') ? 2 : 1;
  }
  scanner.position = end;
  ++scanner.line_number;
  return true;
}

bool next_token(std::string_view& rest, std::string_view& token) {
  std::size_t i = 0;
  while (i < rest.size() && is_space(rest[i])) ++i;
  if (i == rest.size()) {
    rest = {};
    return false;
  }
  std::size_t j = i;
  while (j < rest.size() && !is_space(rest[j])) ++j;
  token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return true;
}

namespace {
// from_chars rejects a leading '+', which some writers emit; it must not hide a second sign.
bool strip_plus(std::string_view& token) {
  if (!token.empty() && token[0] == '+') {
    token.remove_prefix(1);
    if (token.empty() || token[0] == '-' || token[0] == '+') return false;
  }
  return !token.empty();
}
}  // namespace

bool parse_double(std::string_view token, double& value) {
  if (!strip_plus(token)) return false;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

bool parse_integer(std::string_view token, long long& value) {
  if (!strip_plus(token)) return false;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

bool parse_unsigned(std::string_view token, unsigned long long& value) {
  if (!strip_plus(token) || token[0] == '-') return false;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

std::string quote(std::string_view token) {
  constexpr std::size_t kMax = 32;
  std::string out = "`";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("\\x{:02x}", c);
    }
  }
  if (token.size() > kMax) out += "...";
  out += '`';
  return out;
}

Mesh make_mesh(const std::vector<double>& xyz, const std::vector<int>& triangles) {
  using RowMajorD = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMajorI = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  Mesh mesh;
  mesh.V = Eigen::Map<const RowMajorD>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  mesh.F = Eigen::Map<const RowMajorI>(triangles.data(),
                                       static_cast<Eigen::Index>(triangles.size() / 3), 3);
  return mesh;
}

void check_mesh_for_writing(const Mesh& mesh, const char* writer) {
  const bool empty_v = mesh.V.rows() == 0;
  const bool empty_f = mesh.F.rows() == 0;
  if (!empty_v && mesh.V.cols() != 3) {
    throw std::invalid_argument(
        fmt::format("{}: V must have 3 columns, it has {}", writer, mesh.V.cols()));
  }
  if (!empty_f && mesh.F.cols() != 3) {
    throw std::invalid_argument(
        fmt::format("{}: F must have 3 columns (triangles), it has {}", writer, mesh.F.cols()));
  }
  if (!empty_f && (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.V.rows())) {
    throw std::invalid_argument(
        fmt::format("{}: F refers to vertices outside 0..{}", writer, mesh.V.rows() - 1));
  }
  // A shape with NaN or infinite coordinates is a failed computation, never an output.
  if (!mesh.V.allFinite()) {
    throw std::invalid_argument(fmt::format(
        "{}: V holds NaN or infinite coordinates; such a shape is not written", writer));
  }
}

void append_double(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

}  // namespace mesh_io

MeshFile read_mesh(const std::filesystem::path& path) {
  using mesh_io::MeshFormat;
  const std::string name = path.string();
  const std::string ext = mesh_io::lower_extension(path);
  MeshFormat format;
  if (ext == ".obj") {
    format = MeshFormat::kObj;
  } else if (ext == ".ply") {
    format = MeshFormat::kPly;
  } else if (ext == ".stl") {
    format = MeshFormat::kStl;
  } else if (ext == ".off") {
    format = MeshFormat::kOff;
  } else {
    const std::string what = ext.empty() ? "the file name has no extension"
                                         : fmt::format("unknown mesh file extension \"{}\"", ext);
    mesh_io::fail_file(
        name, fmt::format("{}; the supported ones are {}", what, mesh_io::kSupportedExtensions));
  }
  const std::string bytes = mesh_io::read_whole_file(path, name);
  return mesh_io::read_mesh_bytes(bytes, name, format);
}

void write_mesh(const std::filesystem::path& path, const Mesh& mesh,
                const MeshProperties& properties) {
  const std::string ext = mesh_io::lower_extension(path);
  if (ext == ".obj") {
    write_obj(path, mesh);
  } else if (ext == ".ply") {
    write_ply(path, mesh, properties, PlyEncoding::kBinaryLittleEndian);
  } else {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: cannot write meshes with extension \"{}\"; use .obj or .ply",
                                path.string(), ext));
  }
}

}  // namespace flatmorph
