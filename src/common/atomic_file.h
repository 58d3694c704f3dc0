// Writing output files so that a reader never sees half of one: the content goes to a temporary
// file beside the target, which is renamed over the target only once it is complete.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>

namespace flatmorph {

// Calls `write` with a stream on a temporary file in the target's folder, then renames it to `path`.
// If `write` throws, or the stream fails, the temporary file is removed and nothing appears at
// `path`; a write failure is reported as UserError(kFile) naming the path.
void write_file_atomically(const std::filesystem::path& path, bool binary,
                           const std::function<void(std::ostream&)>& write);

}  // namespace flatmorph
