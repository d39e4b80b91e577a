#pragma once
// The RgbdView of a FramePool slot (rt/frame_pool.hpp), for the live path: the view points at
// the slot's own pixels (raw 16-bit depth, rgb8 or mono8 colour, rows unpadded), so nothing is
// copied or converted per frame; depth becomes metres pixel by pixel inside the consumer.
// Valid while the caller holds the slot's handle. Here, not in rt/ or core/, because rt knows
// nothing of frames' meaning and core nothing of rt.
#include <cstddef>

#include "core/types/rgbd_view.hpp"
#include "rt/frame_pool.hpp"

namespace vigs::pipeline {

/// `depth_scale_m`: metres per raw depth unit (camera.depth_scale_m; OpenNI2: 0.001).
inline RgbdView pool_frame_view(const rt::Frame& frame, const rt::FramePoolSettings& pool,
                                float depth_scale_m) {
  RgbdView v;
  v.t_ns = frame.t_ns;
  v.width_px = static_cast<int>(pool.width);
  v.height_px = static_cast<int>(pool.height);
  v.depth_encoding = DepthEncoding::u16_scaled;
  v.depth_u16 = frame.depth.data();
  v.depth_row_stride = pool.width;
  v.depth_scale_m = depth_scale_m;
  v.colour_encoding = pool.colour_channels == 1 ? ColourEncoding::mono8 : ColourEncoding::rgb8;
  v.colour = frame.colour.data();
  v.colour_row_stride = static_cast<std::size_t>(pool.width) * pool.colour_channels;
  return v;
}

}  // namespace vigs::pipeline
