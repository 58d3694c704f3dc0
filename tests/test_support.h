// Helpers shared by the tests: where data lives, scratch folders, running the CLI.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace flatmorph::testing {

// tests/data (small fixtures committed with the tests).
std::filesystem::path test_data_dir();
// ../shared (the paper meshes live in shared/meshes).
std::filesystem::path shared_dir();
// A fresh, empty folder under the build tree for this test (named after the running test).
std::filesystem::path scratch_dir();

// The bytes of a file ("" when it cannot be read).
std::string read_file(const std::filesystem::path& path);

struct CliResult {
  int exit_code;
  std::string out;
  std::string err;
};
// Runs build/flatmorph with the given arguments (no shell interpretation of the arguments).
CliResult run_cli(const std::vector<std::string>& args);

}  // namespace flatmorph::testing
