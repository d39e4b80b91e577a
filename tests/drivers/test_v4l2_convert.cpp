// Colour conversion through Debian's libv4lconvert on real buffers: a YUYV frame (4:2:2, JFIF
// full-range BT.601, made here from a photo) and an MJPEG frame (the same photo compressed by
// libjpeg at quality 95) are converted to rgb8 by V4l2Converter, created on a (fake) capture node
// through the driver's device seam, and compared with the PNG. Also the whole driver path: a
// YUYV colour node paired with Z16 lands converted in the 3-channel FramePool.
#include <gtest/gtest.h>
#include <jpeglib.h>
#include <linux/videodev2.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "drivers/v4l2/v4l2_converter.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "fake_v4l2_device.hpp"
#include "io/image_io.hpp"

namespace vigs::drivers {
namespace {

using testing::FakeV4l2Device;

ImageU8 photo() {
  // kodim10 (Kodak test set, 768x512 rgb), cropped to 320x240 to keep the test fast.
  const ImageU8 full = io::read_rgb(std::string(VIGS_SHARED_DATA_DIR) + "/images/kodim10.png");
  ImageU8 crop(320, 240, 3);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) {
      for (int c = 0; c < 3; ++c) crop.at(x, y, c) = full.at(x + 200, y + 100, c);
    }
  }
  return crop;
}

std::uint8_t clamp8(double v) {
  return static_cast<std::uint8_t>(std::lround(std::min(255.0, std::max(0.0, v))));
}

// YUYV (Y0 U Y1 V per pixel pair), JFIF full-range BT.601, chroma averaged over the pair.
std::vector<std::uint8_t> to_yuyv(const ImageU8& rgb) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(rgb.width) * rgb.height * 2);
  for (int y = 0; y < rgb.height; ++y) {
    for (int x = 0; x < rgb.width; x += 2) {
      double u = 0, v = 0;
      for (int k = 0; k < 2; ++k) {
        const double r = rgb.at(x + k, y, 0), g = rgb.at(x + k, y, 1), b = rgb.at(x + k, y, 2);
        out[(static_cast<std::size_t>(y) * rgb.width + x + k) * 2] =
            clamp8(0.299 * r + 0.587 * g + 0.114 * b);
        u += 128 - 0.168736 * r - 0.331264 * g + 0.5 * b;
        v += 128 + 0.5 * r - 0.418688 * g - 0.081312 * b;
      }
      out[(static_cast<std::size_t>(y) * rgb.width + x) * 2 + 1] = clamp8(u / 2);
      out[(static_cast<std::size_t>(y) * rgb.width + x) * 2 + 3] = clamp8(v / 2);
    }
  }
  return out;
}

std::vector<std::uint8_t> to_jpeg(const ImageU8& rgb, int quality) {
  jpeg_compress_struct cinfo{};
  jpeg_error_mgr jerr{};
  cinfo.err = jpeg_std_error(&jerr);
  jpeg_create_compress(&cinfo);
  unsigned char* mem = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &mem, &size);
  cinfo.image_width = static_cast<JDIMENSION>(rgb.width);
  cinfo.image_height = static_cast<JDIMENSION>(rgb.height);
  cinfo.input_components = 3;
  cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    auto* row = const_cast<JSAMPLE*>(
        &rgb.data[static_cast<std::size_t>(cinfo.next_scanline) * rgb.width * 3]);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  std::vector<std::uint8_t> out(mem, mem + size);
  jpeg_destroy_compress(&cinfo);
  std::free(mem);
  return out;
}

double psnr_db(const ImageU8& ref, std::span<const std::uint8_t> test) {
  double se = 0;
  for (std::size_t i = 0; i < ref.data.size(); ++i) {
    const double d = double(ref.data[i]) - double(test[i]);
    se += d * d;
  }
  return 10.0 * std::log10(255.0 * 255.0 / (se / static_cast<double>(ref.data.size())));
}

// A capture node for libv4lconvert to inspect (its own ENUM_FMT / QUERYCAP ioctls go to the fake).
int open_node(FakeV4l2Device& fake, std::uint32_t fourcc_code, int w, int h) {
  fake.add_node(
      "/dev/video7",
      {.pixelformat = fourcc_code,
       .width = static_cast<std::uint32_t>(w),
       .height = static_cast<std::uint32_t>(h),
       .bytes_per_line = fourcc_code == V4L2_PIX_FMT_YUYV ? static_cast<std::uint32_t>(2 * w) : 0u,
       .size_image = static_cast<std::uint32_t>(w * h * 2)});
  return fake.open("/dev/video7");
}

TEST(V4l2Convert, YuyvFromAPngComesBackAsThePng) {
  const ImageU8 png = photo();
  const auto yuyv = to_yuyv(png);
  FakeV4l2Device fake;
  const int fd = open_node(fake, V4L2_PIX_FMT_YUYV, png.width, png.height);
  V4l2Converter conv(fake, fd, V4l2PixelFormat::kYuyv, 320, 240, 640);
  std::vector<std::uint8_t> rgb(png.data.size());
  ASSERT_TRUE(conv.to_rgb8(yuyv, rgb)) << conv.error();
  const double db = psnr_db(png, rgb);
  RecordProperty("yuyv_psnr_db", std::to_string(db));
  // 4:2:2 chroma and libv4lconvert's integer coefficients cost a little: 43.6 dB here.
  EXPECT_GT(db, 38.0);
  // The raw YUYV bytes read as rgb would be nowhere near (the check can fail).
  std::vector<std::uint8_t> raw(yuyv.begin(), yuyv.begin() + static_cast<long>(rgb.size() / 2));
  raw.resize(rgb.size(), 0);
  EXPECT_LT(psnr_db(png, raw), 15.0);
}

TEST(V4l2Convert, MjpegFromAPngComesBackAsThePng) {
  const ImageU8 png = photo();
  const auto jpeg = to_jpeg(png, 95);
  FakeV4l2Device fake;
  const int fd = open_node(fake, V4L2_PIX_FMT_MJPEG, png.width, png.height);
  V4l2Converter conv(fake, fd, V4l2PixelFormat::kMjpeg, 320, 240, 0);
  std::vector<std::uint8_t> rgb(png.data.size());
  ASSERT_TRUE(conv.to_rgb8(jpeg, rgb)) << conv.error();
  const double db = psnr_db(png, rgb);
  RecordProperty("mjpeg_psnr_db", std::to_string(db));
  EXPECT_GT(db, 38.0);
  // A frame cut short (a USB transfer lost mid-frame) is refused or decoded damaged, never a crash.
  std::vector<std::uint8_t> cut(jpeg.begin(), jpeg.begin() + static_cast<long>(jpeg.size() / 3));
  if (conv.to_rgb8(cut, rgb)) {
    EXPECT_LT(psnr_db(png, rgb), db);
  }
}

TEST(V4l2Convert, YuyvColourNodeLandsConvertedInThePool) {
  const ImageU8 png = photo();
  const auto yuyv = to_yuyv(png);
  constexpr std::uint32_t w = 320, h = 240;
  FakeV4l2Device fake;
  fake.add_node("/dev/depth", {.pixelformat = V4L2_PIX_FMT_Z16,
                               .width = w,
                               .height = h,
                               .bytes_per_line = 2 * w,
                               .size_image = 2 * w * h});
  fake.add_node("/dev/colour", {.pixelformat = V4L2_PIX_FMT_YUYV,
                                .width = w,
                                .height = h,
                                .bytes_per_line = 2 * w,
                                .size_image = 2 * w * h});
  rt::FramePool pool({.slots = 4, .width = w, .height = h, .colour_channels = 3});
  rt::SpscRing<rt::FrameHandle> ring(2);
  V4l2RgbdDriverSettings s;
  s.depth_device = "/dev/depth";
  s.colour_device = "/dev/colour";
  s.colour_format = V4l2PixelFormat::kYuyv;
  s.width_px = w;
  s.height_px = h;
  s.realtime_thread = false;
  s.pin_cpu = false;
  V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.start();
  std::vector<std::uint8_t> depth(2 * w * h, 0);
  ASSERT_TRUE(fake.push_frame("/dev/depth", {.bytes = depth, .t_ns = 1'000'000'000}));
  ASSERT_TRUE(fake.push_frame("/dev/colour", {.bytes = yuyv, .t_ns = 1'000'000'000}));
  rt::FrameHandle hd;
  for (int i = 0; i < 5000 && !ring.try_pop(hd); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(hd.valid());
  EXPECT_GT(psnr_db(png, pool.frame(hd).colour), 32.0);
  pool.release(hd);
  driver.stop();
}

}  // namespace
}  // namespace vigs::drivers
