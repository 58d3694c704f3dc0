// The output folder a command writes into.
#pragma once

#include <filesystem>

namespace flatmorph::cli {

// Creates `dir` (and its parents) if needed; throws UserError (kFile) naming it when it cannot.
void create_output_folder(const std::filesystem::path& dir);

}  // namespace flatmorph::cli
