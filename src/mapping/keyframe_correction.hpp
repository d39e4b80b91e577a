#pragma once
// Moving the map with the keyframe poses it was built from. When the loop closer re-solves
// the keyframe poses (tracking/loop_closure.hpp), each keyframe's part of the map moves rigidly
// with it, as GS-SLAM systems with a back end move their submaps: every Gaussian keeps the id
// of the keyframe that inserted it (its anchor, MapperKeyframe::id), and that keyframe's
// correction T_new_old = T_w_c(new) T_w_c(old)^-1 maps its mean and its rotation; scale,
// opacity and colour are unchanged by a rigid motion. Optimisation moves a Gaussian after
// insertion by what the views ask of it, which is a refinement of where its keyframe put it.
// Without this the map keeps the odometry's drift wherever the camera came back: a corridor
// walked again is inserted a second time, a few decimetres off, over the first.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "mapping/gaussian_map.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping {

struct KeyframeCorrection {
  std::uint64_t id = 0;  ///< MapperKeyframe::id
  Eigen::Isometry3d T_new_old =
      Eigen::Isometry3d::Identity();  ///< world frame, applied on the left
};

/// Moves the Gaussians whose anchor (one per Gaussian, `anchor.size() == map.size()`) has a
/// correction; ids in `corrections` are unique. Returns how many moved.
std::size_t move_anchored(GaussianMap& map, const std::vector<std::uint32_t>& anchor,
                          const std::vector<KeyframeCorrection>& corrections);

/// The same correction of a view: T_c_w becomes T_c_w T_new_old^-1.
void move_camera(RenderCamera& camera, const Eigen::Isometry3d& T_new_old);

}  // namespace vigs::mapping
