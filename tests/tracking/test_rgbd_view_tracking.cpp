// The live form of a frame (raw 16-bit depth and its scale, viewed in place, as a FramePool slot
// gives it) tracks bit-identically to the replay form (a float metres image holding
// float(raw) * scale, as the recording reader made before RgbdView), and mono8 colour to its
// grey RGB expansion: the two paths share every line after the source.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/types/rgbd_view.hpp"
#include "io/image_io.hpp"
#include "tracking/settings_from_config.hpp"
#include "tracking/tracker.hpp"

namespace vigs::tracking {
namespace {

const std::string kIcl = std::string(VIGS_SHARED_DATA_DIR) + "/icl_nuim_livingroom1/";
const PinholeCamera kIclCamera{640, 480, 525.0, 525.0, 319.5, 239.5};

bool bit_identical(const geometry::Pose& a, const geometry::Pose& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

TEST(RgbdViewTracking, RawDepthViewTracksLikeFloatImage) {
  Tracker::Setting s = tracker_setting(config::TrackingSettings{});
  s.initial_guess = InitialGuessMode::previous_pose;
  Tracker live(kIclCamera, s), replay(kIclCamera, s);
  for (int i = 0; i < 4; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "%05d", i);
    const ImageU16 raw = io::read_png_u16(kIcl + "depth_" + name + ".png");
    const ImageU8 rgb = io::read_rgb(kIcl + "color_" + name + ".jpg");
    ImageF32 depth_m(raw.width, raw.height, 1);
    for (std::size_t k = 0; k < raw.data.size(); ++k)
      depth_m.data[k] = static_cast<float>(raw.data[k]) * 1e-3f;
    ImageU8 grey(rgb.width, rgb.height, 1), grey_rgb(rgb.width, rgb.height, 3);
    for (std::size_t p = 0; p < grey.data.size(); ++p) {
      grey.data[p] = rgb.data[3 * p + 1];
      for (int c = 0; c < 3; ++c) grey_rgb.data[3 * p + c] = grey.data[p];
    }
    const std::int64_t t_ns = i * 33'333'333LL;
    const TrackingOutput a = live.track(rgbd_view(t_ns, raw, 1e-3f, grey));
    const TrackingOutput b = replay.track(t_ns, depth_m, grey_rgb);
    SCOPED_TRACE(i);
    EXPECT_EQ(a.t_ns, t_ns);
    EXPECT_EQ(a.points.points, b.points.points);
    EXPECT_GT(a.points.points, 1000);
    EXPECT_EQ(a.status, b.status);
    EXPECT_TRUE(bit_identical(a.T_w_c, b.T_w_c));
    if (i > 0) {
      EXPECT_EQ(a.status, TrackingStatus::tracked);
    }
    ASSERT_EQ(live.last_keyframe().cloud_c.colors_rgb.size(),
              replay.last_keyframe().cloud_c.colors_rgb.size());
    EXPECT_TRUE(live.last_keyframe().cloud_c.colors_rgb ==
                replay.last_keyframe().cloud_c.colors_rgb);
  }
}

}  // namespace
}  // namespace vigs::tracking
