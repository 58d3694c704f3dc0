// `flatmorph view`: a local web server (127.0.0.1 only) that serves the report viewer of a run
// folder, read afresh on every page load, and the folder's pictures.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace flatmorph {

struct ViewServerOptions {
  std::string host = "127.0.0.1";
  int port = 8765;  // 0: any free port
};

// Serves until the process is stopped (or `stop` returns true, polled about ten times a second):
//   /            the viewer page of run_dir (as report.html would be now)
//   /NAME.png    plate_theta1.png, plate_theta2.png, predicted.png, layers.png, layers/overview.png
// Calls `on_listening` with the URL once the socket listens. Throws UserError(kFile) when the
// folder is not a run folder, UserError(kResource) when the port cannot be bound.
void serve_run_folder(const std::filesystem::path& run_dir, const ViewServerOptions& options,
                      const std::function<void(const std::string& url)>& on_listening,
                      const std::function<bool()>& stop = {});

}  // namespace flatmorph
