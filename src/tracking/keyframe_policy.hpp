#pragma once
// When a tracked frame becomes a keyframe (its Gaussians go to the local map and the mapper):
// as GS-ICP SLAM, when the overlap with the map — the fraction of the frame's points with a
// map point within overlap distance after alignment (GicpResult::overlap_ratio) — falls below
// a ratio; additionally after a translation or rotation since the last keyframe.
#include "core/config/tracking_components.hpp"
#include "core/geometry/se3.hpp"

namespace vigs::tracking {

struct KeyframePolicy {
  using Setting = config::KeyframeSetting;
  Setting setting;

  [[nodiscard]] bool is_keyframe(double overlap_ratio, const geometry::Pose& T_w_last_kf,
                                 const geometry::Pose& T_w_c) const {
    const geometry::PoseError moved = geometry::pose_error(T_w_last_kf, T_w_c);
    return overlap_ratio < setting.min_overlap_ratio ||
           moved.translation_m > setting.max_translation_m ||
           moved.rotation_rad > setting.max_rotation_rad();
  }
};

}  // namespace vigs::tracking
