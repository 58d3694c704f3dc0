#include "progress_display.h"

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace flatmorph::cli {
namespace {

// Whether the terminal display left its line open (app-wide: there is one stdout).
bool line_open = false;

struct StageClock {
  std::string stage;
  std::chrono::steady_clock::time_point start;
};

std::string describe(const Progress& p, double elapsed) {
  std::string text = p.stage;
  if (p.step > 0) {
    text += p.total > 0 ? fmt::format(": {}/{}", p.step, p.total) : fmt::format(": {}", p.step);
  }
  if (std::isfinite(p.objective)) text += fmt::format(", objective {:.6g}", p.objective);
  if (!p.detail.empty()) {
    text += p.step > 0 ? ", " : ": ";
    text += p.detail;
  }
  text += fmt::format(" ({:.1f} s)", elapsed);
  return text;
}

std::string bar(const Progress& p) {
  if (p.total <= 0) return "";
  constexpr int kWidth = 20;
  const int filled = std::min(kWidth, kWidth * p.step / p.total);
  std::string text = "[";
  text.append(filled, '#');
  text.append(kWidth - filled, '.');
  text += "] ";
  return text;
}

}  // namespace

void finish_progress_line() {
  if (!line_open) return;
  fmt::print(stdout, "\n");
  line_open = false;
}

ProgressCallback make_progress_display(bool silent) {
  if (silent) return {};
  const bool terminal = ::isatty(STDOUT_FILENO) == 1;
  auto clock = std::make_shared<StageClock>();
  return [terminal, clock](const Progress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (p.stage != clock->stage) {
      finish_progress_line();
      clock->stage = p.stage;
      clock->start = now;
    }
    const double elapsed = std::chrono::duration<double>(now - clock->start).count();
    if (terminal) {
      // Redraw in place; \x1b[K clears what a longer previous line left.
      fmt::print(stdout, "\r{}{}\x1b[K", bar(p), describe(p, elapsed));
      line_open = true;
    } else {
      fmt::print(stdout, "{}\n", describe(p, elapsed));
    }
    std::fflush(stdout);
  };
}

}  // namespace flatmorph::cli
