#pragma once
// When a tracked frame becomes a keyframe (its Gaussians go to the local map and the mapper):
// as GS-ICP SLAM, when the overlap with the map — the fraction of the frame's points with a
// map point within overlap distance after alignment (GicpResult::overlap_ratio) — falls below
// a ratio; additionally after a translation or rotation since the last keyframe.
#include "core/geometry/se3.hpp"

namespace vigs::tracking {

struct KeyframePolicy {
  struct Setting {
    double min_overlap_ratio = 0.7;  ///< GS-ICP SLAM's keyframe_th
    double max_translation_m = 0.3;
    double max_rotation_rad = 15.0 * 3.14159265358979323846 / 180.0;
  };
  Setting setting;

  [[nodiscard]] bool is_keyframe(double overlap_ratio, const geometry::Pose& T_w_last_kf,
                                 const geometry::Pose& T_w_c) const {
    const geometry::PoseError moved = geometry::pose_error(T_w_last_kf, T_w_c);
    return overlap_ratio < setting.min_overlap_ratio ||
           moved.translation_m > setting.max_translation_m ||
           moved.rotation_rad > setting.max_rotation_rad;
  }
};

}  // namespace vigs::tracking
