// Refusing up front a job that needs more memory than the machine has (issue 9, item 6), instead of
// being killed by the kernel half-way: readers check a file's size, the subdivision checks the face
// count it is asked for, before allocating.
#pragma once

#include <cstdint>
#include <string>

namespace flatmorph {

// Peak memory of a design run (flatten, simulate, theta2) per face of the subdivided target,
// measured: flatten ~1 KB, simulate ~12 KB per face at 4.6e4..1.9e5 faces (docs/robustness.md).
constexpr std::uint64_t kDesignBytesPerFace = 16 * 1024;

// Bytes this process may still allocate: the smaller of MemAvailable (/proc/meminfo) and the
// cgroup's memory.max minus its current use. The environment variable FLATMORPH_MEMORY_LIMIT_MB,
// when set, replaces the measurement (for tests, and for users who share a machine). Returns
// UINT64_MAX when nothing can be measured.
std::uint64_t available_memory_bytes();

// Throws UserError(kResource) "<what> needs about N GB of memory but only M GB are available;
// <advice>" when `bytes` exceeds available_memory_bytes().
void require_memory(std::uint64_t bytes, const std::string& what, const std::string& advice);

}  // namespace flatmorph
