#include "common/atomic_file.h"

#include <fmt/core.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <system_error>
#include <vector>

#include "common/error.h"

namespace flatmorph {
namespace {

namespace fs = std::filesystem;

// The temporaries in progress. Renames into place happen under the same mutex, so that after
// abandon_temporary_outputs() has taken it no temporary becomes an output.
struct Registry {
  std::mutex mutex;
  std::vector<fs::path> paths;
};

Registry& registry() {
  static Registry r;
  return r;
}

void add_temporary(const fs::path& tmp) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().paths.push_back(tmp);
}

void drop_temporary_locked(const fs::path& tmp) {
  auto& paths = registry().paths;
  for (auto it = paths.begin(); it != paths.end(); ++it) {
    if (*it == tmp) {
      paths.erase(it);
      return;
    }
  }
}

void remove_temporary(const fs::path& tmp) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  std::error_code ignored;
  fs::remove_all(tmp, ignored);
  drop_temporary_locked(tmp);
}

// A name beside `path` that no other run shares (the process id) and no other call of this run
// (a counter).
fs::path temporary_name(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path tmp = path;
  tmp += fmt::format(".{}-{}.tmp", static_cast<long>(::getpid()), counter++);
  return tmp;
}

}  // namespace

void write_file_atomically(const fs::path& path, bool binary,
                           const std::function<void(std::ostream&)>& write) {
  const fs::path tmp = temporary_name(path);
  add_temporary(tmp);
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
    std::lock_guard<std::mutex> lock(registry().mutex);
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: cannot replace the file: {}", path.string(), ec.message()));
    }
    drop_temporary_locked(tmp);
  } catch (...) {
    remove_temporary(tmp);
    throw;
  }
}

void write_folder_atomically(const fs::path& folder,
                             const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = temporary_name(folder);
  add_temporary(tmp);
  try {
    std::error_code ec;
    fs::create_directory(tmp, ec);
    if (ec) {
      throw UserError(ErrorCategory::kFile,
                      fmt::format("{}: cannot create the folder ({}); check that its parent exists "
                                  "and is writable",
                                  folder.string(), ec.message()));
    }
    write(tmp);
    std::lock_guard<std::mutex> lock(registry().mutex);
    // rename(2) cannot replace a non-empty folder: move the old one aside first.
    const fs::path old = temporary_name(folder);
    const bool had_old = fs::exists(folder, ec);
    if (had_old) {
      fs::rename(folder, old, ec);
      if (ec) {
        throw UserError(ErrorCategory::kFile, fmt::format("{}: cannot replace the folder: {}",
                                                          folder.string(), ec.message()));
      }
    }
    fs::rename(tmp, folder, ec);
    if (ec) {
      std::error_code ignored;
      if (had_old) fs::rename(old, folder, ignored);
      throw UserError(ErrorCategory::kFile, fmt::format("{}: cannot replace the folder: {}",
                                                        folder.string(), ec.message()));
    }
    drop_temporary_locked(tmp);
    if (had_old) fs::remove_all(old, ec);
  } catch (...) {
    remove_temporary(tmp);
    throw;
  }
}

void abandon_temporary_outputs() {
  registry().mutex.lock();  // never unlocked: the process is about to exit
  for (const fs::path& tmp : registry().paths) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
  }
  registry().paths.clear();
}

}  // namespace flatmorph
