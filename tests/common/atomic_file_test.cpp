#include "common/atomic_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include "common/error.h"
#include "test_support.h"

namespace flatmorph::atomic_file_test {
namespace {

TEST(AtomicFile, WritesCompleteFile) {
  auto dir = testing::scratch_dir();
  write_file_atomically(dir / "a.txt", false, [](std::ostream& out) { out << "hello"; });
  std::ifstream in(dir / "a.txt");
  std::string s;
  in >> s;
  EXPECT_EQ(s, "hello");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}

TEST(AtomicFile, LeavesNothingWhenWriterThrows) {
  auto dir = testing::scratch_dir();
  EXPECT_THROW(write_file_atomically(dir / "a.txt", false,
                                     [](std::ostream& out) {
                                       out << "partial";
                                       throw std::runtime_error("boom");
                                     }),
               std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(AtomicFile, ReportsMissingFolderAsUserError) {
  auto dir = testing::scratch_dir();
  try {
    write_file_atomically(dir / "no" / "such" / "a.txt", false, [](std::ostream&) {});
    FAIL() << "expected a UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kFile);
    EXPECT_NE(std::string(e.what()).find("a.txt"), std::string::npos);
  }
}

}  // namespace
}  // namespace flatmorph::atomic_file_test
