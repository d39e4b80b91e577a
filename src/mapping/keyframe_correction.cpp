#include "mapping/keyframe_correction.hpp"

#include <algorithm>
#include <stdexcept>

namespace vigs::mapping {

std::size_t move_anchored(GaussianMap& map, const std::vector<std::uint32_t>& anchor,
                          const std::vector<KeyframeCorrection>& corrections) {
  if (anchor.size() != map.size())
    throw std::invalid_argument("move_anchored: one anchor per Gaussian expected");
  if (corrections.empty()) return 0;
  // Ids are dense from 0 (one per keyframe): a lookup table indexed by id.
  std::uint64_t max_id = 0;
  for (const KeyframeCorrection& c : corrections) max_id = std::max(max_id, c.id);
  std::vector<int> slot(static_cast<std::size_t>(max_id) + 1, -1);
  struct Motion {
    Eigen::Matrix3f R;
    Eigen::Vector3f t;
    Eigen::Quaternionf q;
  };
  std::vector<Motion> motions;
  motions.reserve(corrections.size());
  for (const KeyframeCorrection& c : corrections) {
    slot[static_cast<std::size_t>(c.id)] = static_cast<int>(motions.size());
    const Eigen::Matrix3d R = c.T_new_old.linear();
    motions.push_back({R.cast<float>(), c.T_new_old.translation().cast<float>(),
                       Eigen::Quaternionf(Eigen::Quaterniond(R).normalized().cast<float>())});
  }
  std::size_t moved = 0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (anchor[i] >= slot.size() || slot[anchor[i]] < 0) continue;
    const Motion& m = motions[static_cast<std::size_t>(slot[anchor[i]])];
    float* mu = &map.mean_w[3 * i];
    const Eigen::Vector3f p = m.R * Eigen::Vector3f(mu[0], mu[1], mu[2]) + m.t;
    mu[0] = p.x();
    mu[1] = p.y();
    mu[2] = p.z();
    float* q = &map.quat_wxyz[4 * i];  // body -> world, so the correction multiplies on the left
    const Eigen::Quaternionf r = m.q * Eigen::Quaternionf(q[0], q[1], q[2], q[3]);
    q[0] = r.w();
    q[1] = r.x();
    q[2] = r.y();
    q[3] = r.z();
    ++moved;
  }
  return moved;
}

void move_camera(RenderCamera& camera, const Eigen::Isometry3d& T_new_old) {
  camera.set_T_w_c(T_new_old * camera.T_w_c());
}

}  // namespace vigs::mapping
