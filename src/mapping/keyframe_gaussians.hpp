#pragma once
// What a keyframe contributes to the map: points in the camera frame with their 3x3 covariances
// (as the tracker's GICP computes them) and colours, and how far apart the samples were taken.
// The tracker's keyframe is converted to this in the pipeline (pipeline/tracking_keyframe.hpp).
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vigs::mapping {

struct KeyframeGaussians {
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();  ///< camera pose in the world
  std::vector<Eigen::Vector3f> points_c;                    ///< metres, camera frame
  std::vector<Eigen::Matrix3f> covariances_c;               ///< m^2, camera frame
  std::vector<Eigen::Vector3f> colors;                      ///< RGB in [0, 1]
  /// Angle between neighbouring samples (pixel stride / focal length, rad): a sample at depth z
  /// stands for a z * sample_angle_rad wide patch. 0 = unknown: the GS-ICP SLAM scale rule.
  double sample_angle_rad = 0.0;
};

}  // namespace vigs::mapping
