#include "common/error.h"

namespace flatmorph {

std::string_view to_string(ErrorCategory category) {
  switch (category) {
    case ErrorCategory::kFile: return "file";
    case ErrorCategory::kFormat: return "format";
    case ErrorCategory::kGeometry: return "geometry";
    case ErrorCategory::kTopology: return "topology";
    case ErrorCategory::kOption: return "option";
    case ErrorCategory::kProfile: return "profile";
    case ErrorCategory::kInfeasible: return "infeasible";
    case ErrorCategory::kResource: return "resource";
  }
  return "unknown";
}

}  // namespace flatmorph
