// The height-map PNG reader: 8 and 16 bits kept exactly, colour as Rec. 709 luminance, and every
// bad file a UserError naming it.
#include "methods/heightfield/gray_image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "methods/heightfield/height_field.h"
#include "methods/heightfield/png_fixtures.h"
#include "raster/raster.h"
#include "test_support.h"

namespace flatmorph::gray_image_test {
namespace {

using testing::encode_test_png;
using testing::PngColor;

// The UserError `read` throws (a failed expectation when it throws none).
template <typename Read>
UserError error_of(Read read) {
  try {
    read();
  } catch (const UserError& e) {
    return e;
  }
  ADD_FAILURE() << "no UserError";
  return UserError(ErrorCategory::kFile, "");
}

TEST(GrayImage, EightBitGrayReadsEverySample) {
  const std::vector<uint16_t> samples = {0, 1, 2, 3, 127, 128, 200, 254, 255, 17, 34, 51};
  const GrayImage image =
      read_gray_png_bytes(encode_test_png(4, 3, 8, PngColor::kGray, samples), "gray8.png");
  EXPECT_EQ(image.width, 4);
  EXPECT_EQ(image.height, 3);
  EXPECT_EQ(image.bits, 8);
  EXPECT_EQ(image.max_value(), 255);
  EXPECT_EQ(image.samples, samples);
  EXPECT_EQ(image.at(1, 2), 17);  // x = 1 in the third row
}

TEST(GrayImage, SixteenBitGrayKeepsAllSixteenBits) {
  // Values an 8-bit reduction would merge (1 and 2, 40000 and 40001) or change.
  const std::vector<uint16_t> samples = {0, 1, 2, 257, 40000, 40001, 65534, 65535};
  const GrayImage image =
      read_gray_png_bytes(encode_test_png(2, 4, 16, PngColor::kGray, samples), "gray16.png");
  EXPECT_EQ(image.bits, 16);
  EXPECT_EQ(image.max_value(), 65535);
  EXPECT_EQ(image.samples, samples);
}

TEST(GrayImage, ColourBecomesRec709Luminance) {
  // Written by the project's own RGB encoder: red, green, blue, gray 77, white.
  Canvas canvas(5, 1);
  const std::vector<Rgb> colours = {
      {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {77, 77, 77}, {255, 255, 255}};
  for (int x = 0; x < 5; ++x) {
    for (int c = 0; c < 3; ++c) canvas.rgb[3 * x + c] = colours[x][c];
  }
  const std::vector<unsigned char> png = encode_png(canvas);
  const GrayImage image = read_gray_png_bytes(std::string(png.begin(), png.end()), "colour.png");
  EXPECT_EQ(image.bits, 8);
  // round(0.2126 * 255) = 54, round(0.7152 * 255) = 182, round(0.0722 * 255) = 18.
  EXPECT_EQ(image.samples, (std::vector<uint16_t>{54, 182, 18, 77, 255}));
}

TEST(GrayImage, SixteenBitRgbaUsesLuminanceAndIgnoresAlpha) {
  const std::vector<uint16_t> samples = {40000, 40000, 40000, 0,  // gray, transparent
                                         65535, 0,     0,     65535};
  const GrayImage image =
      read_gray_png_bytes(encode_test_png(2, 1, 16, PngColor::kRgba, samples), "rgba16.png");
  EXPECT_EQ(image.bits, 16);
  EXPECT_EQ(image.samples, (std::vector<uint16_t>{40000, 13933}));  // 0.2126 * 65535 = 13932.7
}

TEST(GrayImage, GrayAlphaIgnoresAlpha) {
  const GrayImage image = read_gray_png_bytes(
      encode_test_png(2, 1, 8, PngColor::kGrayAlpha, {10, 255, 20, 0}), "ga.png");
  EXPECT_EQ(image.samples, (std::vector<uint16_t>{10, 20}));
}

TEST(GrayImage, PaletteBecomesLuminance) {
  // tests/data/image/palette4.png: 4 x 2 pixels, palette black, red, green, blue, pixel (x, y)
  // showing entry (x + y) % 4.
  const GrayImage image = read_gray_png(testing::test_data_dir() / "image" / "palette4.png");
  EXPECT_EQ(image.bits, 8);
  EXPECT_EQ(image.samples, (std::vector<uint16_t>{0, 54, 182, 18, 54, 182, 18, 0}));
}

TEST(GrayImage, EveryFixtureLayoutGivesTheSameHill) {
  // The fuzz seeds of tests/data/image: one 9 x 7 hill as gray, gray + alpha, RGB (8 bits) and
  // gray, RGBA (16 bits).
  const auto dir = testing::test_data_dir() / "image";
  const GrayImage gray8 = read_gray_png(dir / "hill_gray8.png");
  const GrayImage gray16 = read_gray_png(dir / "hill_gray16.png");
  ASSERT_EQ(gray8.width, 9);
  ASSERT_EQ(gray8.height, 7);
  EXPECT_EQ(gray8.at(4, 3), 255);
  EXPECT_EQ(gray8.at(0, 3), 0);
  EXPECT_EQ(gray16.at(4, 3), 65535);
  EXPECT_EQ(gray16.bits, 16);
  for (const char* name : {"hill_gray_alpha8.png", "hill_rgb8.png"}) {
    EXPECT_EQ(read_gray_png(dir / name).samples, gray8.samples) << name;
  }
  EXPECT_EQ(read_gray_png(dir / "hill_rgba16.png").samples, gray16.samples);
}

TEST(GrayImage, FuzzInputsStayFixed) {
  // What fuzz_height_image found (fuzz/README.md): a result or a UserError, as in the target.
  for (const auto& entry :
       std::filesystem::directory_iterator(testing::test_data_dir() / "image")) {
    if (entry.path().filename().string().rfind("fuzz_", 0) != 0) continue;
    SCOPED_TRACE(entry.path().string());
    try {
      height_field_from_image(read_gray_png(entry.path()), 160.0, 120.0, 35.0, 5.0, "fuzz");
    } catch (const UserError&) {
    }
  }
}

TEST(GrayImage, ReadsAFile) {
  const auto path = testing::scratch_dir() / "map.png";
  std::ofstream(path, std::ios::binary) << encode_test_png(2, 2, 8, PngColor::kGray, {1, 2, 3, 4});
  EXPECT_EQ(read_gray_png(path).samples, (std::vector<uint16_t>{1, 2, 3, 4}));
}

TEST(GrayImage, TruncatedFileIsAFormatErrorNamingTheFile) {
  const std::string png =
      encode_test_png(16, 16, 8, PngColor::kGray, std::vector<uint16_t>(256, 9));
  // Cut inside the image data, after the header (33 bytes) that still reads.
  for (size_t keep : {png.size() - 20, size_t{45}, size_t{33}, size_t{20}}) {
    const UserError e = error_of([&] { read_gray_png_bytes(png.substr(0, keep), "cut.png"); });
    EXPECT_EQ(e.category(), ErrorCategory::kFormat) << keep;
    EXPECT_EQ(std::string(e.what()).rfind("cut.png: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("export the height map again"), std::string::npos)
        << e.what();
  }
}

TEST(GrayImage, TruncatedFileOnDiskNamesItsPath) {
  const auto path = testing::scratch_dir() / "cut.png";
  const std::string png = encode_test_png(8, 8, 16, PngColor::kGray, std::vector<uint16_t>(64, 9));
  std::ofstream(path, std::ios::binary) << png.substr(0, png.size() / 2);
  const UserError e = error_of([&] { read_gray_png(path); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line";
}

TEST(GrayImage, ChunkLongerThanTheFileIsRefusedBeforeAllocating) {
  // The IDAT chunk (right after the 33 bytes of signature and IHDR) claiming 2 GB.
  std::string png = encode_test_png(4, 4, 8, PngColor::kGray, std::vector<uint16_t>(16, 9));
  ASSERT_EQ(png.substr(37, 4), "IDAT");
  png.replace(33, 4, "\x7f\xff\xff\xff");
  const UserError e = error_of([&] { read_gray_png_bytes(png, "claims.png"); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(e.what()).find("a chunk at byte 33 claims 2147483647 bytes"),
            std::string::npos)
      << e.what();
}

TEST(GrayImage, NotAPngIsAFormatError) {
  const UserError e = error_of([] { read_gray_png_bytes("P5\n2 2\n255\nabcd", "map.pgm"); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(e.what()).find("map.pgm: not a PNG file"), std::string::npos) << e.what();
}

TEST(GrayImage, EmptyFileIsAFormatError) {
  const UserError e = error_of([] { read_gray_png_bytes("", "empty.png"); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(e.what()).find("empty.png: empty file"), std::string::npos) << e.what();
}

// The IHDR size fields sit at bytes 16 to 23; the CRC is not fixed, the size is read before it.
std::string with_size(std::string png, uint32_t width, uint32_t height) {
  for (int k = 0; k < 4; ++k) {
    png[16 + k] = static_cast<char>(width >> (24 - 8 * k));
    png[20 + k] = static_cast<char>(height >> (24 - 8 * k));
  }
  return png;
}

TEST(GrayImage, ZeroSizeIsAFormatError) {
  const std::string png = encode_test_png(2, 2, 8, PngColor::kGray, {1, 2, 3, 4});
  const UserError e = error_of([&] { read_gray_png_bytes(with_size(png, 0, 2), "zero.png"); });
  EXPECT_EQ(e.category(), ErrorCategory::kFormat);
  EXPECT_NE(std::string(e.what()).find("zero size (0 x 2 pixels)"), std::string::npos) << e.what();
}

TEST(GrayImage, AbsurdSizeIsRefusedBeforeDecoding) {
  const std::string png = encode_test_png(2, 2, 8, PngColor::kGray, {1, 2, 3, 4});
  const UserError e =
      error_of([&] { read_gray_png_bytes(with_size(png, 8193, 8192), "huge.png"); });
  EXPECT_EQ(e.category(), ErrorCategory::kResource);
  EXPECT_NE(std::string(e.what()).find("8193 x 8192 pixels"), std::string::npos) << e.what();
  // 8192 x 8192 itself is allowed: it fails only on the data, which is not there.
  const UserError at_limit =
      error_of([&] { read_gray_png_bytes(with_size(png, 8192, 8192), "big.png"); });
  EXPECT_EQ(at_limit.category(), ErrorCategory::kFormat) << at_limit.what();
}

TEST(GrayImage, MissingFileIsAFileError) {
  const auto path = testing::scratch_dir() / "missing.png";
  const UserError e = error_of([&] { read_gray_png(path); });
  EXPECT_EQ(e.category(), ErrorCategory::kFile);
  EXPECT_NE(std::string(e.what()).find("missing.png: cannot open"), std::string::npos) << e.what();
}

TEST(GrayImage, DirectoryIsAFileError) {
  const UserError e = error_of([] { read_gray_png(testing::scratch_dir()); });
  EXPECT_EQ(e.category(), ErrorCategory::kFile) << e.what();
}

}  // namespace
}  // namespace flatmorph::gray_image_test
