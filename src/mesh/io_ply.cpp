// Stanford PLY: a text header declaring elements and their properties, then the data in ASCII or
// binary (either byte order). Reference: http://paulbourke.net/dataformats/ply/
#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "common/atomic_file.h"
#include "mesh/io_internal.h"

namespace flatmorph {
namespace mesh_io {
namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool parse_type(std::string_view word, PlyType& type) {
  static constexpr struct {
    std::string_view name;
    PlyType type;
  } kNames[] = {
      {"char", PlyType::kInt8},       {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},     {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},   {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},     {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},   {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64},
  };
  for (const auto& entry : kNames) {
    if (entry.name == word) {
      type = entry.type;
      return true;
    }
  }
  return false;
}

std::size_t type_size(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 8;
}

bool is_integral(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // lists only
  PlyType value_type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
  long long line = 0;
};

enum class DataEncoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyHeader {
  DataEncoding encoding = DataEncoding::kAscii;
  std::vector<PlyElement> elements;
  LineScanner scanner;  // positioned at the first byte of data
};

std::string plural(const PlyElement& element) {
  if (element.name == "vertex") return "vertices";
  if (element.name == "face") return "faces";
  return fmt::format("`{}` elements", element.name);
}

PlyHeader parse_header(std::string_view bytes, const std::string& name) {
  PlyHeader header;
  header.scanner = LineScanner{bytes};
  LineScanner& scanner = header.scanner;
  std::string_view line;
  std::string_view token;
  {
    std::string_view rest;
    const bool ok = next_line(scanner, line) && (rest = line, next_token(rest, token)) &&
                    token == "ply" && !next_token(rest, token);
    if (!ok) {
      fail_at_line(name, 1,
                   "the file does not start with `ply`; it is not a PLY file, check its "
                   "format",
                   {});
    }
  }
  bool has_format = false;
  for (;;) {
    if (!next_line(scanner, line)) {
      fail(name, "the header has no `end_header` line; the file is truncated or not a PLY file",
           {});
    }
    const long long line_number = scanner.line_number;
    std::string_view rest = line;
    if (!next_token(rest, token)) continue;
    auto header_error = [&](const std::string& problem) {
      fail_at_line(name, line_number, problem + "; fix or re-export the mesh", {});
    };
    if (token == "end_header") break;
    if (token == "comment" || token == "obj_info") continue;
    if (token == "format") {
      if (has_format) header_error("a second `format` line");
      if (!next_token(rest, token)) header_error("`format` without an encoding");
      if (token == "ascii") {
        header.encoding = DataEncoding::kAscii;
      } else if (token == "binary_little_endian") {
        header.encoding = DataEncoding::kBinaryLittleEndian;
      } else if (token == "binary_big_endian") {
        header.encoding = DataEncoding::kBinaryBigEndian;
      } else {
        header_error(
            fmt::format("unknown encoding {}; expected ascii, binary_little_endian or "
                        "binary_big_endian",
                        quote(token)));
      }
      has_format = true;
    } else if (token == "element") {
      PlyElement element;
      element.line = line_number;
      std::string_view count;
      if (!next_token(rest, token) || !next_token(rest, count)) {
        header_error("an element line must read `element NAME COUNT`");
      }
      if (!parse_unsigned(count, element.count)) {
        header_error(fmt::format("{} is not a valid element count", quote(count)));
      }
      element.name = std::string(token);
      for (const PlyElement& other : header.elements) {
        if (other.name == element.name && (other.name == "vertex" || other.name == "face")) {
          header_error(fmt::format("a second `{}` element", other.name));
        }
      }
      header.elements.push_back(std::move(element));
    } else if (token == "property") {
      if (header.elements.empty()) header_error("a property before any element");
      PlyProperty property;
      if (!next_token(rest, token)) header_error("`property` without a type");
      std::string_view type_word = token;
      if (token == "list") {
        property.is_list = true;
        if (!next_token(rest, token) || !parse_type(token, property.count_type) ||
            !is_integral(property.count_type)) {
          header_error(
              "a list property must read `property list COUNT_TYPE VALUE_TYPE NAME` "
              "with an integer COUNT_TYPE");
        }
        if (!next_token(rest, type_word)) header_error("a list property without a value type");
      }
      if (!parse_type(type_word, property.value_type)) {
        header_error(
            fmt::format("unknown property type {}; expected char, uchar, short, ushort, "
                        "int, uint, float, double or int8 ... float64",
                        quote(type_word)));
      }
      if (!next_token(rest, token)) header_error("a property without a name");
      property.name = std::string(token);
      PlyElement& element = header.elements.back();
      for (const PlyProperty& other : element.properties) {
        if (other.name == property.name) {
          header_error(fmt::format("property `{}` appears twice in element `{}`", property.name,
                                   element.name));
        }
      }
      element.properties.push_back(std::move(property));
    } else {
      header_error(fmt::format("unexpected header line starting with {}", quote(token)));
    }
  }
  if (!has_format) {
    fail(name, "the header has no `format` line; fix or re-export the mesh", {});
  }
  return header;
}

// Where each property of an element goes: the roles below, or (>= 0) a named property.
constexpr int kSkip = -1;
constexpr int kX = -2;
constexpr int kY = -3;
constexpr int kZ = -4;
constexpr int kIndices = -5;

// Decoded data so far, and what to tell the user about it on error.
struct PlyData {
  long long declared_vertices = 0;
  std::vector<double> xyz;
  std::vector<std::vector<double>> vertex_values;  // one column per extra vertex property
  std::vector<int> triangles;
  std::vector<std::vector<double>> face_values;  // one value per triangle
  Progress progress() const {
    return {static_cast<long long>(xyz.size() / 3), static_cast<long long>(triangles.size() / 3)};
  }
};

struct ItemContext {
  const PlyElement* element = nullptr;
  unsigned long long index = 0;
  Progress progress;
};

[[noreturn]] void fail_truncated(const std::string& name, const ItemContext& item) {
  fail(name,
       fmt::format("the header announces {} {} but the data ends after {}; the file is truncated, "
                   "export it again",
                   item.element->count, plural(*item.element), item.index),
       item.progress);
}

template <class T>
T load(const char* p, bool swap) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, p, sizeof(T));
  if (swap) std::reverse(raw, raw + sizeof(T));
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

// Reads values from the binary data, in the file's byte order.
struct BinarySource {
  const std::string& name;
  std::string_view bytes;
  std::size_t position;
  bool swap;
  std::size_t value_offset = 0;  // of the value read last, for messages
  ItemContext item;

  std::size_t remaining() const { return bytes.size() - position; }
  // How many items of `element` the rest of the data can hold at most (lists taken as empty).
  unsigned long long capacity(const PlyElement& element) const {
    unsigned long long size = 0;
    for (const PlyProperty& p : element.properties) {
      size += type_size(p.is_list ? p.count_type : p.value_type);
    }
    return remaining() / size;
  }
  void begin_item(const ItemContext& context) { item = context; }
  double value(PlyType type) {
    const std::size_t size = type_size(type);
    if (remaining() < size) fail_truncated(name, item);
    const char* p = bytes.data() + position;
    value_offset = position;
    position += size;
    switch (type) {
      case PlyType::kInt8:
        return load<std::int8_t>(p, swap);
      case PlyType::kUint8:
        return load<std::uint8_t>(p, swap);
      case PlyType::kInt16:
        return load<std::int16_t>(p, swap);
      case PlyType::kUint16:
        return load<std::uint16_t>(p, swap);
      case PlyType::kInt32:
        return load<std::int32_t>(p, swap);
      case PlyType::kUint32:
        return load<std::uint32_t>(p, swap);
      case PlyType::kFloat32:
        return load<float>(p, swap);
      case PlyType::kFloat64:
        return load<double>(p, swap);
    }
    return 0.0;
  }
  void skip(PlyType type, unsigned long long count) {
    const std::size_t size = type_size(type);
    if (count > remaining() / size) fail_truncated(name, item);
    position += static_cast<std::size_t>(count * size);
  }
  void end_item() {}
  [[noreturn]] void fail_here(const std::string& problem, Progress progress) const {
    fail_at_byte(name, value_offset, problem, progress);
  }
};

// Reads values from ASCII data: one element per line, values separated by whitespace.
struct AsciiSource {
  const std::string& name;
  LineScanner scanner;
  std::string_view rest;
  ItemContext item;

  std::size_t remaining() const { return scanner.text.size() - scanner.position; }
  // Every value takes at least one character and a separator (the very last one need not).
  unsigned long long capacity(const PlyElement& element) const {
    return (remaining() + 1) / (2 * element.properties.size());
  }
  void begin_item(const ItemContext& context) {
    item = context;
    std::string_view line;
    std::string_view token;
    do {
      if (!next_line(scanner, line)) fail_truncated(name, item);
      rest = line;
    } while (!next_token(rest, token));
    rest = line;
  }
  std::string_view token() {
    std::string_view token;
    if (!next_token(rest, token)) {
      fail_here(fmt::format("the line has fewer values than the header declares for one of the "
                            "{}; fix or re-export the mesh",
                            plural(*item.element)),
                item.progress);
    }
    return token;
  }
  double value(PlyType) {
    const std::string_view text = token();
    double value;
    if (!parse_double(text, value)) {
      fail_here(fmt::format("{} is not a number; fix or re-export the mesh", quote(text)),
                item.progress);
    }
    return value;
  }
  void skip(PlyType, unsigned long long count) {
    for (unsigned long long i = 0; i < count; ++i) token();
  }
  void end_item() {
    std::string_view extra;
    if (next_token(rest, extra)) {
      fail_here(fmt::format("the line has more values than the header declares for one of the "
                            "{} ({} is one too many); fix or re-export the mesh",
                            plural(*item.element), quote(extra)),
                item.progress);
    }
  }
  [[noreturn]] void fail_here(const std::string& problem, Progress progress) const {
    fail_at_line(name, scanner.line_number, problem, progress);
  }
};

// A list length or vertex index: a whole number in [0, limit).
template <class Source>
long long whole_number(Source& source, double value, double limit, const char* what) {
  if (!(value >= 0 && value < limit && value == std::floor(value))) {
    source.fail_here(fmt::format("{} is not a valid {}; fix or re-export the mesh", value, what),
                     source.item.progress);
  }
  return static_cast<long long>(value);
}

template <class Source>
void read_element(Source& source, const std::string& name, const PlyElement& element,
                  const std::vector<int>& slots, PlyData& data) {
  const bool is_vertex = element.name == "vertex";
  const bool is_face = element.name == "face";
  if (element.properties.empty() || element.count == 0) return;
  // Compare the count with what the rest of the file can hold before reserving anything, so that
  // a corrupted count is an error rather than an allocation of gigabytes.
  const unsigned long long fit = source.capacity(element);
  if (element.count > fit) {
    fail_at_line(name, element.line,
                 fmt::format("the header announces {} {} but the {} bytes of data left can hold "
                             "at most {}; the file is truncated or its header is wrong, export it "
                             "again",
                             element.count, plural(element), source.remaining(), fit),
                 data.progress());
  }
  const auto count = static_cast<std::size_t>(element.count);
  std::vector<double> scalars(element.properties.size());
  std::vector<int> polygon;
  std::size_t axis_property[3] = {0, 0, 0};
  if (is_vertex) {
    for (int k = 0; k < 3; ++k) {
      const int axis = k == 0 ? kX : k == 1 ? kY : kZ;
      axis_property[k] =
          static_cast<std::size_t>(std::find(slots.begin(), slots.end(), axis) - slots.begin());
    }
    data.xyz.reserve(3 * count);
    for (auto& column : data.vertex_values) column.reserve(count);
  } else if (is_face) {
    data.triangles.reserve(3 * count);
  }
  const double max_list_length = static_cast<double>(source.remaining()) + 1.0;
  for (std::size_t i = 0; i < count; ++i) {
    source.begin_item({&element, i, data.progress()});
    polygon.clear();
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (!property.is_list) {
        scalars[p] = source.value(property.value_type);
        continue;
      }
      const long long length =
          whole_number(source, source.value(property.count_type), max_list_length, "list length");
      if (slots[p] != kIndices) {
        source.skip(property.value_type, static_cast<unsigned long long>(length));
        continue;
      }
      for (long long k = 0; k < length; ++k) {
        const double index = source.value(property.value_type);
        if (!(index >= 0 && index < static_cast<double>(data.declared_vertices))) {
          source.fail_here(fmt::format("face refers to vertex {} but the file defines {} vertices "
                                       "(numbered from 0); fix or re-export the mesh",
                                       index, data.declared_vertices),
                           data.progress());
        }
        polygon.push_back(static_cast<int>(whole_number(
            source, index, static_cast<double>(data.declared_vertices), "vertex index")));
      }
    }
    source.end_item();
    if (is_vertex) {
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const int slot = slots[p];
        if (slot >= 0) {
          data.vertex_values[slot].push_back(scalars[p]);
        }
      }
      for (const std::size_t p : axis_property) data.xyz.push_back(scalars[p]);
    } else if (is_face) {
      if (polygon.size() < 3) {
        source.fail_here(fmt::format("a face needs at least 3 vertices, this one has {}; remove "
                                     "it or re-export the mesh",
                                     polygon.size()),
                         data.progress());
      }
      if (data.triangles.size() / 3 + polygon.size() - 2 > static_cast<std::size_t>(INT_MAX)) {
        source.fail_here("more faces than flatmorph can hold", data.progress());
      }
      // Fan triangulation; each triangle carries the polygon's values.
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        data.triangles.insert(data.triangles.end(), {polygon[0], polygon[k], polygon[k + 1]});
        for (std::size_t p = 0; p < element.properties.size(); ++p) {
          if (slots[p] >= 0) data.face_values[slots[p]].push_back(scalars[p]);
        }
      }
    }
  }
}

// Assigns each property its slot and checks that vertex and face carry what a mesh needs.
std::vector<int> element_slots(const std::string& name, const PlyElement& element,
                               MeshProperties& properties) {
  std::vector<int> slots(element.properties.size(), kSkip);
  const bool is_vertex = element.name == "vertex";
  const bool is_face = element.name == "face";
  if (!is_vertex && !is_face) return slots;
  auto& named = is_vertex ? properties.vertex : properties.face;
  bool has_indices = false;
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    if (property.is_list) {
      if (is_face && !has_indices &&
          (property.name == "vertex_indices" || property.name == "vertex_index")) {
        if (!is_integral(property.value_type)) {
          fail_at_line(name, element.line,
                       fmt::format("the face list `{}` holds floating-point values; vertex "
                                   "indices must be integers, fix or re-export the mesh",
                                   property.name),
                       {});
        }
        slots[p] = kIndices;
        has_indices = true;
      }
      continue;
    }
    if (is_vertex && property.name == "x") {
      slots[p] = kX;
    } else if (is_vertex && property.name == "y") {
      slots[p] = kY;
    } else if (is_vertex && property.name == "z") {
      slots[p] = kZ;
    } else {
      slots[p] = static_cast<int>(named.size());
      named.push_back({property.name, {}});
    }
  }
  if (is_vertex) {
    for (const int axis : {kX, kY, kZ}) {
      if (std::find(slots.begin(), slots.end(), axis) == slots.end()) {
        fail_at_line(name, element.line,
                     "the vertex element lacks one of the scalar properties x, y, z; fix or "
                     "re-export the mesh",
                     {});
      }
    }
  }
  if (is_face && !has_indices) {
    fail_at_line(name, element.line,
                 "the face element has no `vertex_indices` list; fix or re-export the mesh", {});
  }
  return slots;
}

Eigen::VectorXd to_vector(const std::vector<double>& values) {
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

}  // namespace

MeshFile read_ply(std::string_view bytes, const std::string& name) {
  PlyHeader header = parse_header(bytes, name);
  MeshFile result;
  PlyData data;
  std::vector<std::vector<int>> slots;
  const PlyElement* vertex = nullptr;
  for (const PlyElement& element : header.elements) {
    slots.push_back(element_slots(name, element, result.properties));
    if (element.name == "vertex") vertex = &element;
  }
  if (vertex == nullptr) {
    fail(name, "the header declares no `vertex` element; fix or re-export the mesh", {});
  }
  if (vertex->count > static_cast<unsigned long long>(INT_MAX)) {
    fail_at_line(name, vertex->line, "more vertices than flatmorph can hold", {});
  }
  data.declared_vertices = static_cast<long long>(vertex->count);
  data.vertex_values.resize(result.properties.vertex.size());
  data.face_values.resize(result.properties.face.size());

  if (header.encoding == DataEncoding::kAscii) {
    AsciiSource source{name, header.scanner, {}, {}};
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
      read_element(source, name, header.elements[e], slots[e], data);
    }
  } else {
    const bool file_is_little = header.encoding == DataEncoding::kBinaryLittleEndian;
    const bool host_is_little = std::endian::native == std::endian::little;
    BinarySource source{name, bytes, header.scanner.position, file_is_little != host_is_little,
                        0,    {}};
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
      read_element(source, name, header.elements[e], slots[e], data);
    }
  }

  result.mesh = make_mesh(data.xyz, data.triangles);
  for (std::size_t j = 0; j < data.vertex_values.size(); ++j) {
    result.properties.vertex[j].values = to_vector(data.vertex_values[j]);
  }
  for (std::size_t j = 0; j < data.face_values.size(); ++j) {
    result.properties.face[j].values = to_vector(data.face_values[j]);
  }
  return result;
}

namespace {

void check_properties(const std::vector<ScalarProperty>& list, Eigen::Index expected,
                      const char* kind, std::initializer_list<std::string_view> reserved) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ScalarProperty& property = list[i];
    if (property.values.size() != expected) {
      throw std::invalid_argument(
          fmt::format("write_ply: {} property \"{}\" has {} values but "
                      "the mesh has {} {}",
                      kind, property.name, property.values.size(), expected,
                      kind == std::string_view("vertex") ? "vertices" : "faces"));
    }
    const bool bad_name = property.name.empty() ||
                          std::any_of(property.name.begin(), property.name.end(), [](char c) {
                            return static_cast<unsigned char>(c) <= ' ' || c == 0x7f;
                          });
    if (bad_name) {
      throw std::invalid_argument(
          fmt::format("write_ply: {} property name \"{}\" must be non-empty without spaces", kind,
                      property.name));
    }
    const bool clash = std::find(reserved.begin(), reserved.end(), property.name) != reserved.end();
    const bool repeated = std::any_of(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(i),
                                      [&](const auto& p) { return p.name == property.name; });
    if (clash || repeated) {
      throw std::invalid_argument(fmt::format(
          "write_ply: {} property name \"{}\" is used twice or clashes with the geometry", kind,
          property.name));
    }
  }
}

template <class T>
void append_binary(std::string& out, T value, bool swap) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (swap) std::reverse(raw, raw + sizeof(T));
  out.append(raw, sizeof(T));
}

}  // namespace
}  // namespace mesh_io

std::string ply_bytes(const Mesh& mesh, const MeshProperties& properties, PlyEncoding encoding) {
  using mesh_io::append_binary;
  using mesh_io::append_double;
  mesh_io::check_mesh_for_writing(mesh, "write_ply");
  const Eigen::Index nv = mesh.V.rows();
  const Eigen::Index nf = mesh.F.rows();
  mesh_io::check_properties(properties.vertex, nv, "vertex", {"x", "y", "z"});
  mesh_io::check_properties(properties.face, nf, "face", {"vertex_indices", "vertex_index"});

  const char* format = encoding == PlyEncoding::kAscii                ? "ascii"
                       : encoding == PlyEncoding::kBinaryLittleEndian ? "binary_little_endian"
                                                                      : "binary_big_endian";
  std::string out =
      fmt::format("ply\nformat {} 1.0\ncomment flatmorph\nelement vertex {}\n", format, nv);
  out += "property double x\nproperty double y\nproperty double z\n";
  for (const ScalarProperty& p : properties.vertex) out += "property double " + p.name + "\n";
  out += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", nf);
  for (const ScalarProperty& p : properties.face) out += "property double " + p.name + "\n";
  out += "end_header\n";

  const std::size_t vertex_values = 3 + properties.vertex.size();
  const std::size_t face_values = properties.face.size();
  if (encoding == PlyEncoding::kAscii) {
    out.reserve(out.size() + static_cast<std::size_t>(nv) * vertex_values * 20 +
                static_cast<std::size_t>(nf) * (24 + 20 * face_values));
    for (Eigen::Index i = 0; i < nv; ++i) {
      for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ' ';
        append_double(out, mesh.V(i, k));
      }
      for (const ScalarProperty& p : properties.vertex) {
        out += ' ';
        append_double(out, p.values[i]);
      }
      out += '\n';
    }
    for (Eigen::Index f = 0; f < nf; ++f) {
      fmt::format_to(std::back_inserter(out), "3 {} {} {}", mesh.F(f, 0), mesh.F(f, 1),
                     mesh.F(f, 2));
      for (const ScalarProperty& p : properties.face) {
        out += ' ';
        append_double(out, p.values[f]);
      }
      out += '\n';
    }
  } else {
    const bool file_is_little = encoding == PlyEncoding::kBinaryLittleEndian;
    const bool swap = file_is_little != (std::endian::native == std::endian::little);
    out.reserve(out.size() + static_cast<std::size_t>(nv) * vertex_values * 8 +
                static_cast<std::size_t>(nf) * (13 + 8 * face_values));
    for (Eigen::Index i = 0; i < nv; ++i) {
      for (int k = 0; k < 3; ++k) append_binary(out, mesh.V(i, k), swap);
      for (const ScalarProperty& p : properties.vertex) append_binary(out, p.values[i], swap);
    }
    for (Eigen::Index f = 0; f < nf; ++f) {
      out += static_cast<char>(3);
      for (int k = 0; k < 3; ++k) append_binary(out, static_cast<std::int32_t>(mesh.F(f, k)), swap);
      for (const ScalarProperty& p : properties.face) append_binary(out, p.values[f], swap);
    }
  }
  return out;
}

void write_ply(const std::filesystem::path& path, const Mesh& mesh,
               const MeshProperties& properties, PlyEncoding encoding) {
  const std::string out = ply_bytes(mesh, properties, encoding);
  write_file_atomically(path, true, [&](std::ostream& stream) {
    stream.write(out.data(), static_cast<std::streamsize>(out.size()));
  });
}

}  // namespace flatmorph
