// The flatmorph subcommands. Each add_*_command registers its options on the app and returns the
// function that runs it; main() calls the one the user chose.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace flatmorph::cli {

using Run = std::function<int()>;

// Global options every command sees.
struct GlobalOptions {
  bool quiet = false;
};

}  // namespace flatmorph::cli
