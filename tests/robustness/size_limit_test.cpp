// Issue 9, item 6: a job too large for the machine's memory is refused up front with the estimated
// need (category "resource"), never killed by the kernel; a million faces are handled.
// FLATMORPH_MEMORY_LIMIT_MB stands for a smaller machine (common/memory.h).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/memory.h"
#include "test_support.h"

namespace flatmorph::size_limit_test {
namespace {

namespace fs = std::filesystem;

// The CLI run as if the machine had `limit_mb` MB available.
testing::CliResult run_with_memory(const char* limit_mb, const std::vector<std::string>& args) {
  ::setenv("FLATMORPH_MEMORY_LIMIT_MB", limit_mb, 1);
  testing::CliResult r = testing::run_cli(args);
  ::unsetenv("FLATMORPH_MEMORY_LIMIT_MB");
  return r;
}

// An n x n grid of squares as binary PLY: 2 n^2 triangles.
void write_grid_ply(const fs::path& path, int n) {
  std::ofstream out(path, std::ios::binary);
  const int nv = (n + 1) * (n + 1);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << nv
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << 2 * n * n
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float p[3] = {static_cast<float>(i), static_cast<float>(j), 0.001f * (i % 7) * (j % 5)};
      out.write(reinterpret_cast<const char*>(p), sizeof p);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = i + (n + 1) * j, b = a + 1, c = a + n + 1, d = c + 1;
      const int tris[2][3] = {{a, b, d}, {a, d, c}};
      for (const auto& t : tris) {
        const unsigned char three = 3;
        out.write(reinterpret_cast<const char*>(&three), 1);
        out.write(reinterpret_cast<const char*>(t), sizeof t);
      }
    }
  }
}

TEST(SizeLimit, MemoryEnvironmentOverridesTheMeasurement) {
  ::setenv("FLATMORPH_MEMORY_LIMIT_MB", "100", 1);
  EXPECT_EQ(available_memory_bytes(), std::uint64_t{100} << 20);
  ::unsetenv("FLATMORPH_MEMORY_LIMIT_MB");
  EXPECT_GT(available_memory_bytes(), std::uint64_t{100} << 20) << "a test machine has more";
}

TEST(SizeLimit, AMillionFacesRequestIsRefusedUpFrontOnASmallMachine) {
  const fs::path dir = testing::scratch_dir();
  const auto r = run_with_memory("500", {"flatten", "--example", "saddle", "--width", "100",
                                         "--faces", "1000000", "-o", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("flatmorph: error [resource]: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("GB of memory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--faces"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(SizeLimit, APlateTooLargeToSimulateIsRefusedUpFront) {
  const fs::path dir = testing::scratch_dir();
  const fs::path plate =
      (fs::path(FLATMORPH_TEST_DATA_DIR) / ".." / "robustness" / "corpus" / "plate_grid.ply")
          .lexically_normal();
  // 8 faces need 128 KB by kDesignBytesPerFace: refused with 50 KB, simulated with 50 MB.
  const auto r =
      run_with_memory("0.05", {"simulate", plate.string(), "-o", (dir / "s.ply").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("flatmorph: error [resource]: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("plate_grid.ply"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir));
  const auto ok =
      run_with_memory("50", {"simulate", plate.string(), "-o", (dir / "s.ply").string()});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST(SizeLimit, AMillionFaceFileIsReadOrRefusedByItsSize) {
  const fs::path dir = testing::scratch_dir();
  const fs::path big = dir / "million.ply";
  write_grid_ply(big, 708);  // 1,002,528 faces, 19 MB
  const auto refused = run_with_memory("20", {"info", big.string()});
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_EQ(refused.err.rfind("flatmorph: error [resource]: ", 0), 0u) << refused.err;
  EXPECT_NE(refused.err.find("million.ply"), std::string::npos) << refused.err;

  const auto handled = testing::run_cli({"info", big.string()});
  EXPECT_EQ(handled.exit_code, 0) << handled.err;
  EXPECT_NE(handled.out.find("1002528"), std::string::npos) << handled.out;
}

}  // namespace
}  // namespace flatmorph::size_limit_test
