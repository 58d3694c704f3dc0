#include "report/server.h"

#include <fmt/core.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "common/error.h"
#include "common/file_text.h"
#include "report/report.h"

// After Eigen: httplib.h brings <resolv.h>, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace flatmorph {

void serve_run_folder(const std::filesystem::path& run_dir, const ViewServerOptions& options,
                      const std::function<void(const std::string& url)>& on_listening,
                      const std::function<bool()>& stop) {
  read_run_folder(run_dir);  // a bad folder fails before the server starts
  if (options.port < 0 || options.port > 65535) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("--port {}: give a port from 1 to 65535 (0: any free port)", options.port));
  }
  httplib::Server server;
  server.Get("/", [&](const httplib::Request&, httplib::Response& res) {
    try {
      res.set_content(report_html(read_run_folder(run_dir)), "text/html; charset=utf-8");
    } catch (const std::exception& e) {
      res.status = 500;
      res.set_content(fmt::format("flatmorph view: {}\n", e.what()), "text/plain; charset=utf-8");
    }
  });
  server.Get("/report.html",
             [](const httplib::Request&, httplib::Response& res) { res.set_redirect("/"); });
  // Only these files, never a path from the request.
  for (const char* name : {"plate_theta1.png", "plate_theta2.png", "predicted.png", "layers.png",
                           "layers/overview.png"}) {
    const std::filesystem::path file = run_dir / name;
    server.Get(std::string("/") + name, [file](const httplib::Request&, httplib::Response& res) {
      try {
        res.set_content(read_file_text(file, "picture"), "image/png");
      } catch (const UserError&) {
        res.status = 404;
        res.set_content("not in the run folder (run flatmorph report DIR)\n", "text/plain");
      }
    });
  }

  int port = options.port;
  if (port == 0) {
    port = server.bind_to_any_port(options.host);
  } else if (!server.bind_to_port(options.host, port)) {
    port = -1;
  }
  if (port <= 0) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("cannot listen on {}:{} (in use?); choose another --port",
                                options.host, options.port));
  }
  std::atomic<bool> done = false;
  std::thread watcher;
  if (stop) {
    watcher = std::thread([&] {
      while (!done && !stop()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      server.stop();
    });
  }
  on_listening(fmt::format("http://{}:{}/", options.host, port));
  server.listen_after_bind();
  done = true;
  if (watcher.joinable()) watcher.join();
}

}  // namespace flatmorph
