// Pieces shared by the mesh readers and writers (io*.cpp): the per-format parsers over a file held
// in memory, error reporting, text scanning and number formatting. Not part of the public API; the
// tests and the fuzzing harness use read_mesh_bytes to parse bytes without touching the disk.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/io.h"

namespace flatmorph::mesh_io {

enum class MeshFormat { kObj, kPly, kStl, kOff };

// Parses a whole file held in memory. `name` is how messages refer to the file (the path as given).
MeshFile read_mesh_bytes(std::string_view bytes, const std::string& name, MeshFormat format);

MeshFile read_obj(std::string_view bytes, const std::string& name);
MeshFile read_ply(std::string_view bytes, const std::string& name);
MeshFile read_stl(std::string_view bytes, const std::string& name);
MeshFile read_off(std::string_view bytes, const std::string& name);

// What a reader has accepted so far, reported with the error.
struct Progress {
  long long vertices = 0;
  long long faces = 0;
};

// Throw MeshReadError(kFormat) as "<name>:<line>: <problem>", "<name>: byte <offset>: <problem>" or
// "<name>: <problem>". The problem text says what is wrong and what to do.
[[noreturn]] void fail_at_line(const std::string& name, long long line, const std::string& problem,
                               Progress progress);
[[noreturn]] void fail_at_byte(const std::string& name, std::size_t offset,
                               const std::string& problem, Progress progress);
[[noreturn]] void fail(const std::string& name, const std::string& problem, Progress progress);

// Lines of a text, ended by \n, \r\n or a lone \r (the last one may have no end).
struct LineScanner {
  std::string_view text;
  std::size_t position = 0;   // where the next line starts
  long long line_number = 0;  // of the line last returned, from 1
};
// Sets `line` to the next line without its end; false when the text is exhausted.
bool next_line(LineScanner& scanner, std::string_view& line);

// Splits the next token (separated by spaces, tabs, \r, \v, \f) off the front of `rest`; false when
// only whitespace is left.
bool next_token(std::string_view& rest, std::string_view& token);

// Whole-token conversions: false when the token is not entirely a number of that kind (or out of
// the type's range). A leading '+' is accepted; doubles also accept inf and nan.
bool parse_double(std::string_view token, double& value);
bool parse_integer(std::string_view token, long long& value);
bool parse_unsigned(std::string_view token, unsigned long long& value);

// A token quoted for a message: at most 32 characters, non-printable bytes shown as \xNN.
std::string quote(std::string_view token);

// Builds the mesh from flat arrays of 3 numbers per row.
Mesh make_mesh(const std::vector<double>& xyz, const std::vector<int>& triangles);

// Throws std::invalid_argument (naming `writer`) unless V is #V x 3, F is #F x 3 and every index in
// F names a vertex: a writer must not produce a file that no reader accepts.
void check_mesh_for_writing(const Mesh& mesh, const char* writer);

// Appends the shortest decimal text that reads back as exactly `value`.
void append_double(std::string& out, double value);

}  // namespace flatmorph::mesh_io
