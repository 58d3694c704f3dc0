#include "calibration/sheet_csv.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "common/error.h"

namespace flatmorph {

std::string_view trim_cell(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

std::string lower_case(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  size_t start = 0;
  for (size_t i = 0; i <= line.size(); ++i) {
    if (i == line.size() || line[i] == ',') {
      cells.push_back(trim_cell(line.substr(start, i - start)));
      start = i + 1;
    }
  }
  return cells;
}

SheetRow::SheetRow(const std::string& source, int line, const std::vector<std::string>& names,
                   std::vector<std::string_view> cells, std::string_view id_column,
                   std::string_view skip_column)
    : source_(source),
      line_(line),
      names_(names),
      cells_(std::move(cells)),
      id_column_(id_column),
      skip_column_(skip_column) {}

std::string_view SheetRow::text(const std::string& column) const {
  const size_t c = index(column);
  return c < cells_.size() ? cells_[c] : std::string_view();
}

void SheetRow::fail(const std::string& column, const std::string& problem) const {
  throw UserError(ErrorCategory::kFormat, fmt::format("{}: line {}, column {} ({}): {}", source_,
                                                      line_, index(column) + 1, column, problem));
}

double SheetRow::number(const std::string& column) const {
  const std::string_view t = text(column);
  if (t.empty()) {
    fail(column, fmt::format("the value is missing; measure it and fill it in (or write skip in "
                             "{} to leave {} {} out)",
                             skip_column_, id_column_, text(std::string(id_column_))));
  }
  double value = 0;
  const char* end = t.data() + t.size();
  const auto [ptr, ec] = std::from_chars(t.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
    fail(column, fmt::format("\"{}\" is not a number; write a plain number such as 79.5 (a "
                             "point, no units)",
                             t));
  }
  return value;
}

double SheetRow::positive(const std::string& column) const {
  const double value = number(column);
  if (!(value > 0)) fail(column, fmt::format("{} is not a positive size", value));
  return value;
}

int SheetRow::whole(const std::string& column) const {
  const double value = number(column);
  if (value != std::floor(value) || value < 1 || value > 1e6) {
    fail(column, fmt::format("{} is not a whole number of 1 or more", value));
  }
  return static_cast<int>(value);
}

size_t SheetRow::index(const std::string& column) const {
  return static_cast<size_t>(std::find(names_.begin(), names_.end(), column) - names_.begin());
}

std::vector<SheetLine> sheet_lines(std::string_view text) {
  std::vector<SheetLine> out;
  int line = 0;
  for (size_t pos = 0; pos < text.size();) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    const std::string_view raw = trim_cell(text.substr(pos, end - pos));
    pos = end + 1;
    ++line;
    if (raw.empty()) continue;
    SheetLine l;
    l.line = line;
    l.text = raw;
    if (raw.front() == '#') {
      const std::string_view body = trim_cell(raw.substr(1));
      const size_t eq = body.find(" = ");
      if (eq == std::string_view::npos) continue;
      l.comment = true;
      l.key = trim_cell(body.substr(0, eq));
      l.value = trim_cell(body.substr(eq + 3));
    }
    out.push_back(std::move(l));
  }
  return out;
}

std::vector<std::string> sheet_columns(std::string_view raw, int line, const std::string& source,
                                       std::span<const char* const> required) {
  std::vector<std::string> names;
  for (std::string_view cell : split_cells(raw)) names.push_back(lower_case(cell));
  for (const char* column : required) {
    if (std::find(names.begin(), names.end(), column) == names.end()) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: line {}: no column \"{}\"; the first line that is not a "
                                  "# comment must name the columns: {}",
                                  source, line, column, fmt::join(required, ",")));
    }
  }
  return names;
}

}  // namespace flatmorph
