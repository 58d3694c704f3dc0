#include "common/file_text.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <string>

#include "common/error.h"
#include "test_support.h"

namespace flatmorph::file_text_test {
namespace {

UserError error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const UserError& e) {
    return e;
  }
  ADD_FAILURE() << "no UserError";
  return UserError(ErrorCategory::kResource, "");
}

// Every byte comes back as written: text, zero bytes, CR LF, a byte above 127; an empty file is
// an empty string.
TEST(FileText, ReadsEveryByteUnchanged) {
  const auto dir = testing::scratch_dir();
  const std::string bytes = std::string("line\r\n\0\xff end", 11);
  std::ofstream(dir / "a.bin", std::ios::binary) << bytes;
  EXPECT_EQ(read_file_text(dir / "a.bin", "file"), bytes);
  std::ofstream(dir / "empty.txt").close();
  EXPECT_EQ(read_file_text(dir / "empty.txt", "file"), "");
}

// One line naming the file and what it is, kFile, for a missing file and a folder.
TEST(FileText, MissingFilesAndFoldersAreFileErrorsNamingThem) {
  const auto dir = testing::scratch_dir();
  const UserError missing = error_of([&] { read_file_text(dir / "gone.json", "material file"); });
  EXPECT_EQ(missing.category(), ErrorCategory::kFile);
  EXPECT_EQ(std::string(missing.what()),
            (dir / "gone.json").string() +
                ": cannot open the material file: check the path and its permissions");
  const UserError folder = error_of([&] { read_file_text(dir, "drawing"); });
  EXPECT_EQ(folder.category(), ErrorCategory::kFile);
  EXPECT_EQ(std::string(folder.what()),
            dir.string() + ": is a folder, not a file: give the path of the drawing");
}

// The size check sees the file's size before anything is read, and its error is the caller's.
TEST(FileText, TheSizeCheckSeesTheSizeFirst) {
  const auto dir = testing::scratch_dir();
  std::ofstream(dir / "ten.txt") << "0123456789";
  std::uintmax_t seen = 0;
  EXPECT_EQ(read_file_text(dir / "ten.txt", "file", [&](std::uintmax_t size) { seen = size; }),
            "0123456789");
  EXPECT_EQ(seen, 10u);
  const UserError large = error_of([&] {
    read_file_text(dir / "ten.txt", "file", [](std::uintmax_t size) {
      if (size > 4) throw UserError(ErrorCategory::kResource, "too large");
    });
  });
  EXPECT_EQ(large.category(), ErrorCategory::kResource);
  EXPECT_EQ(std::string(large.what()), "too large");
}

}  // namespace
}  // namespace flatmorph::file_text_test
