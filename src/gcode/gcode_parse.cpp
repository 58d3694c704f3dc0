#include "gcode/gcode_parse.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace flatmorph {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::string_view strip_numbering(std::string_view line) {
  if (!line.empty() && (line[0] == 'N' || line[0] == 'n') && line.size() > 1 &&
      std::isdigit(static_cast<unsigned char>(line[1]))) {
    size_t i = 1;
    while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]))) ++i;
    line = trim(line.substr(i));
  }
  const size_t star = line.find('*');
  if (star != std::string_view::npos) line = trim(line.substr(0, star));
  return line;
}

std::string_view strip(std::string_view text, std::string& buffer) {
  text = text.substr(0, text.find(';'));
  if (text.find('(') != std::string_view::npos) {
    buffer.clear();
    int depth = 0;
    for (char c : text) {
      if (c == '(') ++depth;
      if (depth == 0) buffer += c;
      if (c == ')' && depth > 0) --depth;
    }
    text = buffer;
  }
  return strip_numbering(trim(text));
}

bool is_classic(std::string_view name) {
  return name.size() >= 2 && (name[0] == 'G' || name[0] == 'M' || name[0] == 'T') &&
         std::isdigit(static_cast<unsigned char>(name[1]));
}

std::optional<std::string> parse_command(std::string_view line, Command& cmd) {
  size_t i = 0;
  while (i < line.size() && line[i] != ' ' && line[i] != '\t' &&
         !(i > 0 && std::isalpha(static_cast<unsigned char>(line[i])) &&
           std::isdigit(static_cast<unsigned char>(line[1])))) {
    ++i;
  }
  cmd.name.assign(line.substr(0, i));
  std::transform(cmd.name.begin(), cmd.name.end(), cmd.name.begin(), ::toupper);
  if (!is_classic(cmd.name)) return std::nullopt;  // extended commands carry KEY=VALUE words
  // Firmware reads the number: "G01" is G1 and "M083" M83. Leading zeros go (a digit stays), so
  // every rule that names a command sees one spelling.
  size_t first = 1;
  while (first + 1 < cmd.name.size() && cmd.name[first] == '0' &&
         std::isdigit(static_cast<unsigned char>(cmd.name[first + 1]))) {
    ++first;
  }
  cmd.name.erase(1, first - 1);
  while (i < line.size()) {
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(line[i])));
    if (c == ' ' || c == '\t') {
      ++i;
      continue;
    }
    if (c < 'A' || c > 'Z') {
      return std::string(1, line[i]);
    }
    size_t j = i + 1;
    while (j < line.size() && (std::isdigit(static_cast<unsigned char>(line[j])) ||
                               line[j] == '.' || line[j] == '-' || line[j] == '+')) {
      ++j;
    }
    const std::string_view number = line.substr(i + 1, j - i - 1);
    if (number.empty()) {
      cmd.params[c - 'A'] = std::nan("");
    } else {
      double value = 0;
      const char* first = number.data();
      if (*first == '+') ++first;
      const auto [end, ec] = std::from_chars(first, number.data() + number.size(), value);
      if (ec != std::errc() || end != number.data() + number.size() || !std::isfinite(value)) {
        return std::string(line.substr(i, j - i));
      }
      cmd.params[c - 'A'] = value;
    }
    i = j;
  }
  return std::nullopt;
}

}  // namespace flatmorph
