// Wall-clock timing of pipeline stages, in seconds (the t_*_s metrics and progress lines).
#pragma once

#include <chrono>

namespace flatmorph {

using Clock = std::chrono::steady_clock;

// Seconds elapsed since `start`.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace flatmorph
