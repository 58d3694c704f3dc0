#include "common/atomic_file.h"

#include <fmt/core.h>
#include <unistd.h>

#include <system_error>

#include "common/error.h"

namespace flatmorph {

void write_file_atomically(const std::filesystem::path& path, bool binary,
                           const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  // The temporary name carries the process id so that two runs never share one.
  fs::path tmp = path;
  tmp += fmt::format(".{}.tmp", static_cast<long>(::getpid()));
  try {
    std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!out) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: cannot create the file; check that the folder exists and is "
                                  "writable",
                                  path.string()));
    }
    write(out);
    out.flush();
    if (!out) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: writing failed (disk full?)", path.string()));
    }
    out.close();
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: cannot replace the file: {}", path.string(), ec.message()));
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

}  // namespace flatmorph
