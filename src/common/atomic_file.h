// Writing output files so that a reader never sees half of one: the content goes to a temporary
// file beside the target, which is renamed over the target only once it is complete.
//
// The temporaries being written are kept in a registry, so that an interrupted run (SIGINT) can
// remove them: abandon_temporary_outputs() is what the CLI's signal handling (app/main.cpp) calls.
// This registry, guarded by a mutex, is the only global state of the library; it exists for signal
// handling alone.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>

namespace flatmorph {

// Calls `write` with a stream on a temporary file in the target's folder, then renames it to
// `path`. If `write` throws, or the stream fails, the temporary file is removed and nothing appears
// at `path`; a write failure is reported as UserError(kFile) naming the path.
void write_file_atomically(const std::filesystem::path& path, bool binary,
                           const std::function<void(std::ostream&)>& write);

// The same for a whole folder (e.g. the layer SVGs): `write` fills an empty temporary folder beside
// `folder` (its argument), which then replaces `folder` and everything an earlier run left in it.
// If `write` throws, the temporary folder is removed and `folder` is left as it was. Files written
// inside it need not be written atomically.
void write_folder_atomically(const std::filesystem::path& folder,
                             const std::function<void(const std::filesystem::path&)>& write);

// Removes every temporary file and folder being written right now and keeps any further one from
// being renamed into place: for a process about to exit on a signal. Call it from a normal thread
// (not from inside a signal handler: it takes a mutex and walks folders); it never returns the
// lock.
void abandon_temporary_outputs();

}  // namespace flatmorph
