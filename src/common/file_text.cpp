#include "common/file_text.h"

#include <fmt/core.h>

#include <fstream>
#include <system_error>

#include "common/error.h"

namespace flatmorph {

std::string read_file_text(const std::filesystem::path& path, std::string_view what,
                           const std::function<void(std::uintmax_t bytes)>& check_size) {
  const std::string name = path.string();
  std::error_code error;
  // A folder opens as a stream on Linux, with a nonsense size.
  if (std::filesystem::is_directory(path, error)) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: is a folder, not a file: give the path of the {}", name, what));
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: cannot open the {}: check the path and its permissions", name, what));
  }
  const auto cannot_read = [&] {
    return UserError(ErrorCategory::kFile,
                     fmt::format("{}: cannot read the {}: check that it is a readable regular file",
                                 name, what));
  };
  const std::streamoff size = in.tellg();
  if (size < 0) throw cannot_read();
  if (check_size) check_size(static_cast<std::uintmax_t>(size));
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) throw cannot_read();
  return bytes;
}

}  // namespace flatmorph
