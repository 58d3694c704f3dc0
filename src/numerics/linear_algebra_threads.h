// How many threads the sparse Cholesky factorizations give OpenBLAS for the dense blocks of
// CHOLMOD's supernodal factorization. The number is the process's setting (OpenBLAS keeps it per
// process), set once at the start of the programs (app/main.cpp, bench/main.cpp). CHOLMOD's own
// OpenMP regions always run on the calling thread (sparse_cholesky.h: Debian's CHOLMOD fixes their
// thread count when it is compiled, and they cost more than they save).
//
// More threads are not always faster: on a 2-core machine whose cores TBB already uses, one BLAS
// thread factorized the paper's hat Hessian in 134 ms and two in 139 ms (docs/design.md, "Speed").
// So the number is chosen by measuring on the machine it runs on, once: the result is kept in a
// small cache file, so that later runs (and their outputs) use the same number without measuring
// again.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace flatmorph {

struct ThreadsChoice {
  int threads = 1;
  // "measured", "cached" (read from the cache file) or "given" (an override).
  std::string source;
  std::vector<double> seconds;  // per candidate (measured only): the best of a few factorizations
};

// The candidate that takes the least time, where `seconds(threads)` times a factorization with
// that many threads; a candidate with more threads must be at least 10 % faster than the best with
// fewer to be chosen (threads that barely help still cost a busy machine). Candidates ascending.
ThreadsChoice fastest_thread_count(const std::vector<int>& candidates,
                                   const std::function<double(int)>& seconds);

// Seconds of the best of three factorizations of a plate-like Hessian (a 3-unknowns-per-vertex
// triangle grid of about 24k unknowns) with `threads` threads.
double time_factorization(int threads);

// Where the choice is kept: $XDG_CACHE_HOME/flatmorph/threads.json, else
// $HOME/.cache/flatmorph/threads.json; empty when neither variable is set.
std::filesystem::path threads_cache_path();

// The number of threads for this machine: `given` when set (an override: --threads, or
// FLATMORPH_THREADS; must be >= 1, else UserError kOption), else the cache file's when it was
// written on a machine with the same processor and core count, else measured (1 to the number of
// cores) and written to the cache (a cache that cannot be written is skipped silently: the choice
// is only remeasured next time).
ThreadsChoice choose_linear_algebra_threads(std::optional<int> given,
                                            const std::filesystem::path& cache);

// What the programs call once at their start: `given` (the --threads option) or else the
// environment's FLATMORPH_THREADS (a whole number >= 1, else UserError kOption), else the cached or
// measured number (choose_linear_algebra_threads with threads_cache_path()), set for the process.
ThreadsChoice configure_linear_algebra_threads(std::optional<int> given);

// Makes OpenBLAS, when it is the BLAS this process runs on, use `threads` threads (its threads
// wait for work by spinning: on a busy machine more than it has cores for stall every call).
void set_linear_algebra_threads(int threads);

}  // namespace flatmorph
