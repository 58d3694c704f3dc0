#include "output_folder.h"

#include <fmt/core.h>

#include "common/error.h"

namespace flatmorph::cli {

void create_output_folder(const std::filesystem::path& dir) {
  if (dir.empty()) return;  // the current folder
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw UserError(ErrorCategory::kFile,
                    fmt::format("{}: cannot create the output folder ({}); choose another -o",
                                dir.string(), error.message()));
  }
}

}  // namespace flatmorph::cli
