#include "numerics/linear_algebra_threads.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "test_support.h"

namespace flatmorph::linear_algebra_threads_test {
namespace {

TEST(LinearAlgebraThreads, MoreThreadsMustBeClearlyFaster) {
  // 2 threads 5 % faster: not worth it; 4 threads 20 % faster than 1: taken.
  const ThreadsChoice a = fastest_thread_count({1, 2}, [](int t) { return t == 1 ? 1.0 : 0.95; });
  EXPECT_EQ(a.threads, 1);
  EXPECT_EQ(a.seconds, (std::vector<double>{1.0, 0.95}));
  const ThreadsChoice b = fastest_thread_count({1, 2, 4}, [](int t) { return 1.0 - 0.05 * t; });
  EXPECT_EQ(b.threads, 4);
  const ThreadsChoice c = fastest_thread_count({1, 2}, [](int t) { return t == 1 ? 0.5 : 0.8; });
  EXPECT_EQ(c.threads, 1);
  EXPECT_EQ(c.source, "measured");
}

TEST(LinearAlgebraThreads, GivenOverridesAndBadValuesAreOptionErrors) {
  const ThreadsChoice given = choose_linear_algebra_threads(3, {});
  EXPECT_EQ(given.threads, 3);
  EXPECT_EQ(given.source, "given");
  try {
    choose_linear_algebra_threads(0, {});
    FAIL() << "0 threads accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
  }
}

// The environment's FLATMORPH_THREADS stands in for a missing --threads; a given number wins.
TEST(LinearAlgebraThreads, EnvironmentGivesTheNumberUnlessTheOptionDoes) {
  setenv("FLATMORPH_THREADS", "1", 1);
  EXPECT_EQ(configure_linear_algebra_threads(std::nullopt).source, "given");
  EXPECT_EQ(configure_linear_algebra_threads(1).threads, 1);
  setenv("FLATMORPH_THREADS", "two", 1);
  EXPECT_THROW(configure_linear_algebra_threads(std::nullopt), UserError);
  EXPECT_EQ(configure_linear_algebra_threads(1).source, "given");
  unsetenv("FLATMORPH_THREADS");
}

// Measured once, then read back from the cache; a cache from another machine is measured again
// and replaced.
TEST(LinearAlgebraThreads, TheChoiceIsMeasuredOnceAndCachedPerMachine) {
  const std::filesystem::path dir = testing::scratch_dir();
  const std::filesystem::path cache = dir / "sub" / "threads.json";
  const ThreadsChoice first = choose_linear_algebra_threads(std::nullopt, cache);
  EXPECT_EQ(first.source, "measured");
  EXPECT_GE(first.threads, 1);
  ASSERT_TRUE(std::filesystem::exists(cache));
  const ThreadsChoice second = choose_linear_algebra_threads(std::nullopt, cache);
  EXPECT_EQ(second.source, "cached");
  EXPECT_EQ(second.threads, first.threads);
  {
    std::ofstream out(cache);
    out << R"({"machine": "another machine", "threads": 7})";
  }
  const ThreadsChoice third = choose_linear_algebra_threads(std::nullopt, cache);
  EXPECT_EQ(third.source, "measured");
  {
    std::ofstream out(cache);
    out << "not json";
  }
  EXPECT_EQ(choose_linear_algebra_threads(std::nullopt, cache).source, "measured");
}

TEST(LinearAlgebraThreads, SetsOpenBlasThreads) {
  using Get = int (*)();
  const auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  ASSERT_NE(get, nullptr) << "the BLAS loaded is not OpenBLAS (scripts/setup installs it)";
  const int before = get();
  set_linear_algebra_threads(1);
  EXPECT_EQ(get(), 1);
  set_linear_algebra_threads(before);
}

}  // namespace
}  // namespace flatmorph::linear_algebra_threads_test
