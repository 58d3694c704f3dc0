#include "common/memory.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include "common/error.h"

namespace flatmorph {
namespace {

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

// The first number of a one-line file such as /sys/fs/cgroup/memory.max ("max" gives kUnknown).
std::uint64_t read_number(const char* path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word)) return kUnknown;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(word.c_str(), &end, 10);
  return end != word.c_str() && *end == '\0' ? value : kUnknown;
}

std::uint64_t mem_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit) {
    if (key == "MemAvailable:") return kib * 1024;
  }
  return kUnknown;
}

std::string gigabytes(std::uint64_t bytes) {
  return fmt::format("{:.1f} GB", static_cast<double>(bytes) / 1e9);
}

}  // namespace

std::uint64_t available_memory_bytes() {
  if (const char* limit = std::getenv("FLATMORPH_MEMORY_LIMIT_MB")) {
    char* end = nullptr;
    const double mb = std::strtod(limit, &end);
    if (end != limit && *end == '\0' && mb >= 0) return static_cast<std::uint64_t>(mb * 1048576.0);
  }
  std::uint64_t available = mem_available();
  const std::uint64_t cgroup_max = read_number("/sys/fs/cgroup/memory.max");
  const std::uint64_t cgroup_used = read_number("/sys/fs/cgroup/memory.current");
  if (cgroup_max != kUnknown && cgroup_used != kUnknown) {
    available = std::min(available, cgroup_max > cgroup_used ? cgroup_max - cgroup_used : 0);
  }
  return available;
}

void require_memory(std::uint64_t bytes, const std::string& what, const std::string& advice) {
  const std::uint64_t available = available_memory_bytes();
  if (bytes <= available) return;
  throw UserError(ErrorCategory::kResource,
                  fmt::format("{} needs about {} of memory but only {} are available; {}", what,
                              gigabytes(bytes), gigabytes(available), advice));
}

}  // namespace flatmorph
