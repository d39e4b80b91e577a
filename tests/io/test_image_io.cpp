#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "io/image_io.hpp"

namespace vigs::io {
namespace {

namespace fs = std::filesystem;
const std::string kData = VIGS_SHARED_DATA_DIR;

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("vigs_image_io_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void dump(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(ImageIo, ReadsRealIclNuimColourAndDepth) {
  const auto rgb = read_rgb(kData + "/icl_nuim_livingroom1/color_00000.jpg");
  EXPECT_EQ(rgb.width, 640);
  EXPECT_EQ(rgb.height, 480);
  EXPECT_EQ(rgb.channels, 3);
  const auto depth_mm = read_png_u16(kData + "/icl_nuim_livingroom1/depth_00000.png");
  ASSERT_EQ(depth_mm.width, 640);
  const auto depth_m = read_depth_m(kData + "/icl_nuim_livingroom1/depth_00000.png", 1e-3);
  std::size_t valid = 0;
  double sum = 0;
  for (std::size_t i = 0; i < depth_m.data.size(); ++i) {
    EXPECT_FLOAT_EQ(depth_m.data[i], static_cast<float>(depth_mm.data[i] * 1e-3));
    if (depth_m.data[i] > 0) ++valid, sum += depth_m.data[i];
  }
  EXPECT_GT(valid, depth_m.data.size() / 2);
  const double mean = sum / static_cast<double>(valid);
  EXPECT_GT(mean, 0.5);  // a living room seen from ~2 m
  EXPECT_LT(mean, 6.0);
}

TEST(ImageIo, ReadsRealUhumans2FloatTiffDepthAndPng) {
  const auto depth = read_tiff_f32(kData + "/uhumans2_frames/depth_img_0.tiff");
  EXPECT_EQ(depth.width, 720);
  EXPECT_EQ(depth.height, 480);
  const auto rgb = read_rgb(kData + "/uhumans2_frames/left_img_0.png");
  EXPECT_EQ(rgb.width, 720);
  EXPECT_EQ(rgb.height, 480);
  const auto depth_m = read_depth_m(kData + "/uhumans2_frames/depth_img_0.tiff", 1.0);
  std::size_t valid = 0;
  for (float d : depth_m.data) valid += d > 0.0f;
  EXPECT_GT(valid, depth_m.data.size() / 2);
}

TEST(ImageIo, GrayPngStaysSingleChannel) {
  const auto gray = read_image_u8(kData + "/images/camera.png");
  EXPECT_EQ(gray.width, 512);
  EXPECT_EQ(gray.channels, 1);
  EXPECT_EQ(read_rgb(kData + "/images/camera.png").channels, 3);
}

TEST(ImageIo, PngRoundTrip8And16Bit) {
  TempDir dir;
  ImageU8 rgb(37, 21, 3);
  for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<std::uint8_t>(i * 7);
  write_png(dir.file("rgb.png"), rgb);
  EXPECT_EQ(read_image_u8(dir.file("rgb.png")).data, rgb.data);
  ImageU16 depth(19, 11, 1);
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    depth.data[i] = static_cast<std::uint16_t>(i * 331);
  }
  write_png_u16(dir.file("depth.png"), depth);
  EXPECT_EQ(read_png_u16(dir.file("depth.png")).data, depth.data);
  EXPECT_FALSE(fs::exists(dir.file("depth.png.tmp." + std::to_string(::getpid()))));
}

TEST(ImageIo, FailedWriteKeepsThePreviousFile) {
  TempDir dir;
  ImageU8 good(4, 4, 1, 9);
  write_png(dir.file("keep.png"), good);
  const auto before = slurp(dir.file("keep.png"));
  ImageU8 bad(4, 4, 2);  // 2 channels cannot be written
  EXPECT_THROW(write_png(dir.file("keep.png"), bad), ImageIoError);
  EXPECT_EQ(slurp(dir.file("keep.png")), before);
  EXPECT_THROW(write_png(dir.file("no/such/dir/x.png"), good), ImageIoError);
}

TEST(ImageIo, MalformedFilesGiveErrorsNamingTheFile) {
  TempDir dir;
  const auto expect_error = [](const auto& fn, const std::string& path, const std::string& what) {
    try {
      fn(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const ImageIoError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  auto png = slurp(kData + "/images/camera.png");
  png.resize(png.size() / 3);
  dump(dir.file("truncated.png"), png);
  expect_error(read_image_u8, dir.file("truncated.png"), "invalid PNG");
  auto jpg = slurp(kData + "/icl_nuim_livingroom1/color_00001.jpg");
  jpg.resize(200);
  dump(dir.file("truncated.jpg"), jpg);
  expect_error(read_image_u8, dir.file("truncated.jpg"), "invalid JPEG");
  dump(dir.file("garbage.bin"), std::vector<char>(100, 'x'));
  expect_error(read_image_u8, dir.file("garbage.bin"), "not a PNG or JPEG");
  expect_error(read_png_u16, kData + "/images/camera.png", "expected a single-channel 16-bit PNG");
  expect_error(read_tiff_f32, kData + "/images/camera.png", "not a TIFF");
  expect_error(read_image_u8, dir.file("missing.png"), "cannot open");
  auto tiff = slurp(kData + "/uhumans2_frames/depth_img_0.tiff");
  tiff.resize(tiff.size() / 2);
  dump(dir.file("truncated.tiff"), tiff);
  EXPECT_THROW(read_tiff_f32(dir.file("truncated.tiff")), ImageIoError);
}

}  // namespace
}  // namespace vigs::io
