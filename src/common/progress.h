// Progress of long stages (flattening, simulation, theta2 optimization, trajectories), reported
// by the library to whoever displays it (app/progress_display.h); the library never prints.
#pragma once

#include <functional>
#include <limits>
#include <string>

namespace flatmorph {

struct Progress {
  std::string stage;  // e.g. "flatten", "optimize theta2", "trajectories"
  int step = 0;       // iteration or item done, from 1; 0 announces the stage
  int total = 0;      // number of steps when known, else 0
  double objective = std::numeric_limits<double>::quiet_NaN();  // when the stage minimizes one
  std::string detail;  // one short phrase, e.g. "anisotropic local/global, 35 iterations"
};

// May be empty (no one listens). Called on the calling thread.
using ProgressCallback = std::function<void(const Progress&)>;

inline void report_progress(const ProgressCallback& callback, Progress progress) {
  if (callback) callback(progress);
}

}  // namespace flatmorph
