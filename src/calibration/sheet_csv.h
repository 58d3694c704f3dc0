// The CSV of the measurement sheets the calibration prints write and `calibrate fit` reads back
// (measurements.h, hinge_sheet.h): cells split on commas, trimmed, and read one by one with errors
// that name the file, the line and the column.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

std::string_view trim_cell(std::string_view s);
std::string lower_case(std::string_view s);
std::vector<std::string_view> split_cells(std::string_view line);

// A line of a sheet that says something: a "# key = value" comment (other comments and blank
// lines are left out) or a row, trimmed; `line` counts from 1.
struct SheetLine {
  int line = 0;
  bool comment = false;
  std::string key;         // a comment's
  std::string_view value;  // a comment's
  std::string_view text;   // the whole line, trimmed
};
std::vector<SheetLine> sheet_lines(std::string_view text);

// The column names of a sheet's header line (`raw`, lower-cased). Throws UserError(kFormat) naming
// `source`, the line and the first of `required` that is missing.
std::vector<std::string> sheet_columns(std::string_view raw, int line, const std::string& source,
                                       std::span<const char* const> required);

// One row of a sheet. Every error is a UserError(kFormat): "FILE: line L, column C (NAME): ...".
class SheetRow {
 public:
  // `names`: the columns, from the header line; a missing value suggests writing skip in
  // `skip_column` to leave the row's `id_column` out.
  SheetRow(const std::string& source, int line, const std::vector<std::string>& names,
           std::vector<std::string_view> cells, std::string_view id_column,
           std::string_view skip_column);

  std::string_view text(const std::string& column) const;
  bool empty(const std::string& column) const { return text(column).empty(); }
  [[noreturn]] void fail(const std::string& column, const std::string& problem) const;
  double number(const std::string& column) const;
  double positive(const std::string& column) const;  // > 0
  int whole(const std::string& column) const;        // a whole number of 1 or more
  size_t index(const std::string& column) const;     // 0-based; names.size() when absent

 private:
  const std::string& source_;
  int line_;
  const std::vector<std::string>& names_;
  std::vector<std::string_view> cells_;
  std::string_view id_column_, skip_column_;
};

}  // namespace flatmorph
