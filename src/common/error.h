// Errors flatmorph reports to its user.
//
// A UserError is a problem with what the user gave us (a file, a mesh, an option value): the
// message names the input, the problem and what to do, and the CLI exits with status 2. Anything
// else that escapes is an internal failure (exit status 1): a library function whose caller broke
// its precondition (arrays of different sizes that other code produced) throws
// std::invalid_argument, never a UserError, so that a bug is not reported to the user as a bad
// option.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace flatmorph {

// The kind of mistake, so that tests and scripts can tell failures apart without parsing prose.
enum class ErrorCategory {
  kFile,        // cannot open, read or write a file
  kFormat,      // a file's content does not follow its format (truncated, corrupted, bad numbers)
  kGeometry,    // NaN/Inf/absurd coordinates, degenerate geometry
  kTopology,    // non-manifold, closed, holes, several components, orientation
  kOption,      // a command-line value out of range or inconsistent
  kProfile,     // a material or printer profile that is malformed or inconsistent
  kInfeasible,  // a request that cannot be met (plate larger than the bed, ...)
  kResource,    // the job needs more memory or time than the machine has
};

std::string_view to_string(ErrorCategory category);

// Text from a user's file quoted in a message: at most 32 characters, bytes other than printable
// ASCII as \xNN.
std::string printable(std::string_view text);

class UserError : public std::runtime_error {
 public:
  UserError(ErrorCategory category, const std::string& message)
      : std::runtime_error(message), category_(category) {}
  ErrorCategory category() const { return category_; }

 private:
  ErrorCategory category_;
};

// Throws UserError (kOption) with `message` unless `ok`: the check of one option's value.
void require_option(bool ok, const std::string& message);

}  // namespace flatmorph
