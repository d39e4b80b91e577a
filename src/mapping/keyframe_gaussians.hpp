#pragma once
// What a keyframe contributes to the map: points in the camera frame with their 3x3 covariances
// (as the tracker's GICP computes them) and colours. Defined here until the tracker's keyframe
// type lands; the mapper only needs these four arrays.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vigs::mapping {

struct KeyframeGaussians {
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();  ///< camera pose in the world
  std::vector<Eigen::Vector3f> points_c;                    ///< metres, camera frame
  std::vector<Eigen::Matrix3f> covariances_c;               ///< m^2, camera frame
  std::vector<Eigen::Vector3f> colors;                      ///< RGB in [0, 1]
};

}  // namespace vigs::mapping
