#include "numerics/linear_algebra_threads.h"

#include <dlfcn.h>
#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/stopwatch.h"
#include "numerics/sparse_cholesky.h"

namespace flatmorph {
namespace {

using SetNumThreads = void (*)(int);

// Looked up at run time: the BLAS is whichever the system's alternatives select, and only
// OpenBLAS has threads.
SetNumThreads openblas_set_num_threads() {
  return reinterpret_cast<SetNumThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
}

// The processor, its core count and whether the BLAS has threads: what the choice depends on.
std::string machine_key() {
  std::string model = "unknown processor";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) model = line.substr(line.find_first_not_of(' ', colon + 1));
      break;
    }
  }
  return fmt::format("{}, {} cores, {}", model, std::max(1u, std::thread::hardware_concurrency()),
                     openblas_set_num_threads() ? "OpenBLAS" : "a BLAS without threads");
}

// A plate-like Hessian: a triangulated n x n grid, 3 unknowns per vertex, each interior edge
// coupling the four vertices of its two triangles (the hinge stencil of the plate energy), made
// positive definite by the grid Laplacian and the identity. Lower triangle, as CHOLMOD reads it.
Eigen::SparseMatrix<double> plate_like_matrix(int n) {
  auto vertex = [n](int i, int j) { return i * n + j; };
  std::vector<Eigen::Triplet<double>> t;
  auto couple = [&t](const std::vector<int>& vs, const std::vector<double>& w) {
    for (size_t a = 0; a < vs.size(); ++a) {
      for (size_t b = 0; b < vs.size(); ++b) {
        for (int c = 0; c < 3; ++c) {
          const int row = 3 * vs[a] + c, col = 3 * vs[b] + c;
          if (row >= col) t.emplace_back(row, col, w[a] * w[b]);
        }
      }
    }
  };
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      // The quad's diagonal edge and, to its right and above, the edges to the next quads.
      couple({vertex(i, j), vertex(i + 1, j + 1), vertex(i + 1, j), vertex(i, j + 1)},
             {1, 1, -1, -1});
      if (j + 2 < n) {
        couple({vertex(i, j + 1), vertex(i + 1, j + 1), vertex(i, j), vertex(i + 1, j + 2)},
               {1, 1, -1, -1});
      }
      if (i + 2 < n) {
        couple({vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j), vertex(i + 2, j + 1)},
               {1, 1, -1, -1});
      }
    }
  }
  for (int k = 0; k < 3 * n * n; ++k) t.emplace_back(k, k, 1.0);
  Eigen::SparseMatrix<double> a(3 * n * n, 3 * n * n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

}  // namespace

ThreadsChoice fastest_thread_count(const std::vector<int>& candidates,
                                   const std::function<double(int)>& seconds) {
  ThreadsChoice choice;
  choice.source = "measured";
  double best = 0;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const double s = seconds(candidates[k]);
    choice.seconds.push_back(s);
    if (k == 0 || s < 0.9 * best) {
      best = s;
      choice.threads = candidates[k];
    }
  }
  return choice;
}

double time_factorization(int threads) {
  const Eigen::SparseMatrix<double> a = plate_like_matrix(90);
  set_linear_algebra_threads(threads);
  SparseCholesky solver;
  configure_sparse_cholesky(solver);
  analyze_pattern(solver, a);
  double best = 0;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = Clock::now();
    factorize(solver, a);
    const double s = seconds_since(t0);
    if (k == 0 || s < best) best = s;
  }
  return best;
}

std::filesystem::path threads_cache_path() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return std::filesystem::path(xdg) / "flatmorph" / "threads.json";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::filesystem::path(home) / ".cache" / "flatmorph" / "threads.json";
  }
  return {};
}

ThreadsChoice choose_linear_algebra_threads(std::optional<int> given,
                                            const std::filesystem::path& cache) {
  if (given) {
    if (*given < 1) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{} linear algebra threads: give 1 or more (or leave it out to "
                                  "use the number measured on this machine)",
                                  *given));
    }
    return {*given, "given", {}};
  }
  const std::string key = machine_key();
  if (!cache.empty()) {
    std::ifstream in(cache);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_object() && j.value("machine", "") == key && j.contains("threads") &&
        j["threads"].is_number_integer() && j["threads"].get<int>() >= 1) {
      return {j["threads"].get<int>(), "cached", {}};
    }
  }
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!openblas_set_num_threads() || cores == 1) return {1, "measured", {}};
  const ThreadsChoice choice = fastest_thread_count({1, cores}, time_factorization);
  if (!cache.empty()) {
    try {
      std::filesystem::create_directories(cache.parent_path());
      const nlohmann::json j = {
          {"machine", key}, {"threads", choice.threads}, {"seconds", choice.seconds}};
      write_file_atomically(cache, false, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
    } catch (const std::exception&) {
      // Not cached: measured again next time, nothing else changes.
    }
  }
  return choice;
}

ThreadsChoice configure_linear_algebra_threads(std::optional<int> given) {
  if (!given) {
    if (const char* env = std::getenv("FLATMORPH_THREADS"); env && *env) {
      char* end = nullptr;
      const long value = std::strtol(env, &end, 10);
      if (*end != '\0' || value < 1 || value > 1024) {
        throw UserError(ErrorCategory::kOption,
                        fmt::format("FLATMORPH_THREADS={}: give a whole number of threads, 1 or "
                                    "more, or unset it to use the number measured on this machine",
                                    env));
      }
      given = static_cast<int>(value);
    }
  }
  const ThreadsChoice choice = choose_linear_algebra_threads(given, threads_cache_path());
  set_linear_algebra_threads(choice.threads);
  return choice;
}

void set_linear_algebra_threads(int threads) {
  if (const SetNumThreads set = openblas_set_num_threads()) set(threads);
}

}  // namespace flatmorph
