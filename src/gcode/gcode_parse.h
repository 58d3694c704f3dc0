// Internal to src/gcode/ (by convention, not included from elsewhere): the line-level G-code
// tokenizer shared by the safety check (gcode_check.cpp) and the reader (gcode_reader.cpp), so
// that both read a line the same way. Numbers go through std::from_chars: no locale, no
// allocation.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace flatmorph {

// One command: its name ("G1", "M104", "T0", "TURN_OFF_HEATERS") and its letter parameters. A
// letter given without a number (the flags of "M84 X Y" or "G28 W") has value NaN.
struct Command {
  std::string name;
  std::array<std::optional<double>, 26> params;
  std::optional<double> get(char letter) const { return params[letter - 'A']; }
  bool has(char letter) const { return params[letter - 'A'].has_value(); }
};

// `s` without leading blanks and trailing blanks and carriage returns.
std::string_view trim(std::string_view s);

// Removes a leading line number "N12" and a trailing "*checksum".
std::string_view strip_numbering(std::string_view line);

// Removes ";" and "(...)" comments and the line numbering; `buffer` holds the line when a
// parenthesised comment had to be cut out of it.
std::string_view strip(std::string_view text, std::string& buffer);

// Whether `name` is a classic command (a letter G, M or T and a digit), whose parameters are
// letters with numbers, rather than an extended one (Klipper macros) with KEY=VALUE words.
bool is_classic(std::string_view name);

// Splits "G1 X10 Y-2.5E0.3" into its command and parameters (a stripped line). Returns the
// malformed word, if any: a parameter that is not a finite number, or a character that is not a
// parameter letter.
std::optional<std::string> parse_command(std::string_view line, Command& cmd);

}  // namespace flatmorph
