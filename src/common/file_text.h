// Reading a whole file into memory, for the readers that parse from a buffer (JSON, CSV, SVG, DXF,
// PNG, G-code): one place that says, in one line naming the file, why it could not be read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace flatmorph {

// The bytes of the file at `path`, unchanged (text or binary). `what` names the file in messages
// ("material file", "height map PNG"). Throws UserError (kFile) naming the path, the problem and
// what to do for a folder, a file that cannot be opened (missing, no permission) and one that
// cannot be read. `check_size`, when given, gets the file's size in bytes before anything is read
// or allocated: a reader with a limit throws its own error there for a file too large for it.
std::string read_file_text(const std::filesystem::path& path, std::string_view what,
                           const std::function<void(std::uintmax_t bytes)>& check_size = {});

}  // namespace flatmorph
