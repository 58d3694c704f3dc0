#include "common/error.h"

#include <fmt/core.h>

namespace flatmorph {

std::string_view to_string(ErrorCategory category) {
  switch (category) {
    case ErrorCategory::kFile:
      return "file";
    case ErrorCategory::kFormat:
      return "format";
    case ErrorCategory::kGeometry:
      return "geometry";
    case ErrorCategory::kTopology:
      return "topology";
    case ErrorCategory::kOption:
      return "option";
    case ErrorCategory::kProfile:
      return "profile";
    case ErrorCategory::kInfeasible:
      return "infeasible";
    case ErrorCategory::kResource:
      return "resource";
  }
  return "unknown";
}

std::string printable(std::string_view text) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < 32; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("\\x{:02x}", c);
    }
  }
  return text.size() > 32 ? out + "..." : out;
}

void require_option(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

}  // namespace flatmorph
