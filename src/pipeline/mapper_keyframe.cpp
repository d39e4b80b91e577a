#include "pipeline/mapper_keyframe.hpp"

#include <algorithm>

#include "core/types/rgbd_view.hpp"
#include "mapping/rgbd_keyframe.hpp"
#include "pipeline/moving_pixels.hpp"
#include "pipeline/tracking_keyframe.hpp"

namespace vigs::pipeline {

std::unique_ptr<mapping::MapperKeyframe> make_mapper_keyframe(
    std::uint64_t id, const tracking::Keyframe& kf, const PinholeCamera& camera, int stride_px,
    const config::MovingMaskSettings& moving_mask, const ImageU8& rgb, ImageF32 depth_m,
    const geometry::Pose* T_w_c_map) {
  const int stride = std::max(1, stride_px);
  auto m = std::make_unique<mapping::MapperKeyframe>();
  m->id = id;
  // the people's pixels first, so that they give no colour to the points beside them either
  if (moving_mask.enabled) mask_moving_pixels(kf, camera, stride, moving_mask.dilation_px, depth_m);
  m->gaussians = to_keyframe_gaussians(kf, keyframe_sample_angle_rad(camera, stride));
  mapping::footprint_colours(camera, rgbd_view(kf.t_ns, depth_m, rgb), stride, m->gaussians);
  if (T_w_c_map != nullptr) m->gaussians.T_w_c = *T_w_c_map;
  m->camera = mapping::RenderCamera::from(camera, m->gaussians.T_w_c);
  m->rgb.resize(rgb.data.size());
  std::transform(rgb.data.begin(), rgb.data.end(), m->rgb.begin(),
                 [](std::uint8_t c) { return static_cast<float>(c) / 255.0f; });
  m->depth_m = std::move(depth_m.data);
  return m;
}

}  // namespace vigs::pipeline
