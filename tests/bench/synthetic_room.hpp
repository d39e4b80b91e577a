#pragma once
// A synthetic textured box room for the mapping benchmark: RGB-D views are ray-cast
// analytically, back-projected into keyframes and inserted as Gaussians.
#include <cmath>
#include <vector>

#include "core/types/image.hpp"
#include "mapping/insertion.hpp"
#include "mapping/rgbd_keyframe.hpp"

namespace vigs::bench {

struct RoomView {
  ImageU8 rgb;
  ImageF32 depth_m;
  Eigen::Isometry3d T_w_c;
};

/// Room [-3, 3] x [-1.5, 1.5] x [-2, 2] m with stripe-and-checker texture.
inline RoomView render_room(const PinholeCamera& k, const Eigen::Isometry3d& T_w_c) {
  RoomView v{ImageU8(k.width_px, k.height_px, 3), ImageF32(k.width_px, k.height_px, 1), T_w_c};
  const Eigen::Vector3d lo(-3, -1.5, -2), hi(3, 1.5, 2);
  const Eigen::Vector3d o = T_w_c.translation();
  for (int y = 0; y < k.height_px; ++y) {
    for (int x = 0; x < k.width_px; ++x) {
      const Eigen::Vector3d d_c((x - k.cx_px) / k.fx_px, (y - k.cy_px) / k.fy_px, 1.0);
      const Eigen::Vector3d d = T_w_c.linear() * d_c;
      double t = 1e9;
      int axis = 0;
      for (int a = 0; a < 3; ++a) {
        if (std::abs(d(a)) < 1e-12) continue;
        const double ta = ((d(a) > 0 ? hi(a) : lo(a)) - o(a)) / d(a);
        if (ta > 0 && ta < t) {
          t = ta;
          axis = a;
        }
      }
      const Eigen::Vector3d p = o + t * d;
      const int u = static_cast<int>(std::floor(p((axis + 1) % 3) * 4));
      const int w = static_cast<int>(std::floor(p((axis + 2) % 3) * 4));
      const double stripe = 0.5 + 0.5 * std::sin(p((axis + 1) % 3) * 11.0 + axis);
      const bool check = ((u + w) & 1) != 0;
      v.rgb.at(x, y, 0) = static_cast<std::uint8_t>(60 + 150 * stripe);
      v.rgb.at(x, y, 1) = static_cast<std::uint8_t>(check ? 200 : 70);
      v.rgb.at(x, y, 2) = static_cast<std::uint8_t>(40 + 60 * axis);
      v.depth_m.at(x, y) = static_cast<float>(t);  // d_c.z == 1, so t is the camera z
    }
  }
  return v;
}

/// Camera at `pos` looking along yaw (radians about world y) with world y down.
inline Eigen::Isometry3d room_pose(double yaw, const Eigen::Vector3d& pos) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = pos;
  return T;
}

/// Inserts Gaussians from `n_views` views around the room until about `target` exist.
inline mapping::GaussianMap build_room_map(const PinholeCamera& k, int n_views, double voxel_m,
                                           int stride_px) {
  mapping::GaussianMap map;
  mapping::GaussianInserter ins(mapping::InsertSettings{voxel_m, 0.1, 1e-4});
  mapping::RgbdSampling s;
  s.stride_px = stride_px;
  for (int i = 0; i < n_views; ++i) {
    const double yaw = 2 * M_PI * i / n_views;
    const Eigen::Vector3d pos(0.8 * std::cos(3.0 * i), 0.3 * std::sin(1.7 * i),
                              0.5 * std::sin(2.0 * i));
    const RoomView v = render_room(k, room_pose(yaw, pos));
    ins.insert(map, mapping::keyframe_from_rgbd(k, v.rgb, v.depth_m, v.T_w_c, s));
  }
  return map;
}

}  // namespace vigs::bench
