// Camera files for `vigs align`: the three accepted forms and errors naming file and key.
#include <gtest/gtest.h>

#include <string>

#include "tracking/camera_file.hpp"

namespace vigs::tracking {
namespace {

const std::string kData = VIGS_SHARED_DATA_DIR;

TEST(CameraFile, VigsYaml) {
  const PinholeCamera c = parse_camera_text(
      "fx: 525.0\nfy: 526.0\ncx: 319.5\ncy: 239.5\nwidth: 640\nheight: 480\n", "cam.yaml");
  EXPECT_EQ(c.width_px, 640);
  EXPECT_EQ(c.height_px, 480);
  EXPECT_DOUBLE_EQ(c.fx_px, 525.0);
  EXPECT_DOUBLE_EQ(c.fy_px, 526.0);
  EXPECT_DOUBLE_EQ(c.cx_px, 319.5);
  EXPECT_DOUBLE_EQ(c.cy_px, 239.5);
}

TEST(CameraFile, KimeraSensorYaml) {
  const PinholeCamera c = load_camera_file(kData + "/uhumans2_frames/sensorLeft.yaml");
  EXPECT_EQ(c.width_px, 720);
  EXPECT_EQ(c.height_px, 480);
  EXPECT_DOUBLE_EQ(c.fx_px, 415.69219381653056);
  EXPECT_DOUBLE_EQ(c.cx_px, 360.0);
  EXPECT_DOUBLE_EQ(c.cy_px, 240.0);
}

TEST(CameraFile, Open3dJson) {
  const PinholeCamera c = load_camera_file(kData + "/icl_nuim_livingroom1/camera_primesense.json");
  EXPECT_EQ(c.width_px, 640);
  EXPECT_DOUBLE_EQ(c.fx_px, 525.0);
  EXPECT_DOUBLE_EQ(c.fy_px, 525.0);
  EXPECT_DOUBLE_EQ(c.cx_px, 319.5);
  EXPECT_DOUBLE_EQ(c.cy_px, 239.5);
}

std::string error_of(const std::string& text) {
  try {
    parse_camera_text(text, "bad.yaml");
  } catch (const CameraFileError& e) {
    return e.what();
  }
  return "";
}

TEST(CameraFile, ErrorsNameFileAndKey) {
  EXPECT_EQ(error_of("fx: 1\nfy: 1\ncx: 1\nwidth: 4\nheight: 4\n"), "bad.yaml: missing key 'cy'");
  EXPECT_NE(error_of("fx: one\nfy: 1\ncx: 1\ncy: 1\nwidth: 4\nheight: 4\n").find("'fx'"),
            std::string::npos);
  EXPECT_NE(error_of("intrinsics: [1, 2, 3]\nresolution: [4, 4]\n").find("'intrinsics'"),
            std::string::npos);
  EXPECT_NE(error_of("fx: 1\nfy: 1\ncx: 9\ncy: 1\nwidth: 4\nheight: 4\n").find("principal"),
            std::string::npos);
  EXPECT_NE(error_of("[1, 2").find("bad.yaml"), std::string::npos);
  EXPECT_THROW(load_camera_file("/nonexistent/cam.yaml"), CameraFileError);
}

}  // namespace
}  // namespace vigs::tracking
