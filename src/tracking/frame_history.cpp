#include "tracking/frame_history.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::tracking {

FrameHistory::FrameHistory(const PinholeCamera& camera, int frames, int cell_px)
    : camera_(camera), cell_px_(std::max(1, cell_px)) {
  cols_ = (camera.width_px + cell_px_ - 1) / cell_px_;
  rows_ = (camera.height_px + cell_px_ - 1) / cell_px_;
  slots_.resize(static_cast<std::size_t>(std::max(0, frames)));
  for (Slot& s : slots_) {
    s.depth_m.assign(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_), 0.0f);
  }
  // A keyframe has at most one point per cell: flag() then never allocates.
  hit_.reserve(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_));
}

void FrameHistory::record(const RgbdView& frame, const geometry::Pose& T_w_c, bool valid) {
  if (slots_.empty()) return;
  Slot& s = slots_[next_];
  next_ = (next_ + 1) % slots_.size();
  s.t_ns = frame.t_ns;
  s.T_c_w = T_w_c.inverse();
  s.valid = valid && frame.width_px == camera_.width_px && frame.height_px == camera_.height_px;
  if (!s.valid) return;
  frame.with_depth_m([&](auto depth_at) {
    float* out = s.depth_m.data();
    for (int cv = 0; cv < rows_; ++cv) {
      for (int cu = 0; cu < cols_; ++cu) {
        const float z = depth_at(cu * cell_px_, cv * cell_px_);
        *out++ = std::isfinite(z) && z > 0.0f ? z : 0.0f;
      }
    }
  });
}

bool FrameHistory::sees_through(const Slot& s, int cu, int cv, float z_m) const {
  if (cu < 1 || cv < 1 || cu + 1 >= cols_ || cv + 1 >= rows_) return false;
  for (int dv = -1; dv <= 1; ++dv) {
    const float* row = s.depth_m.data() + static_cast<std::size_t>(cv + dv) * cols_;
    for (int du = -1; du <= 1; ++du) {
      const float d = row[cu + du];
      if (!(d > z_m)) return false;  // nearer, equal, or no measurement: no evidence
    }
  }
  return true;
}

int FrameHistory::flag(const GaussianCloud& cloud_c, const geometry::Pose& T_w_c,
                       std::int64_t t_self_ns, float margin_m, std::vector<std::uint8_t>& moving) {
  const std::size_t n = cloud_c.size();
  moving.assign(n, 0);  // capacity reused: allocates only when the cloud grows
  if (slots_.empty() || !(margin_m > 0.0f)) return 0;
  hit_.assign(n, 0);
  const auto fx = static_cast<float>(camera_.fx_px), fy = static_cast<float>(camera_.fy_px);
  const auto cx = static_cast<float>(camera_.cx_px), cy = static_cast<float>(camera_.cy_px);
  const float inv_cell = 1.0f / static_cast<float>(cell_px_);
  for (const Slot& s : slots_) {
    if (!s.valid || s.t_ns == t_self_ns) continue;
    const geometry::Pose T_s_c = s.T_c_w * T_w_c;
    const Eigen::Matrix3f R = T_s_c.linear().cast<float>();
    const Eigen::Vector3f t = T_s_c.translation().cast<float>();
    for (std::size_t i = 0; i < n; ++i) {
      if (hit_[i] != 0) continue;
      const Eigen::Vector3f q = R * cloud_c.points_m[i] + t;
      if (!(q.z() > 0.05f)) continue;
      const float u = (fx * q.x() / q.z() + cx) * inv_cell + 0.5f;
      const float v = (fy * q.y() / q.z() + cy) * inv_cell + 0.5f;
      if (!(u >= 0.0f && v >= 0.0f && u < static_cast<float>(cols_) &&
            v < static_cast<float>(rows_))) {
        continue;
      }
      if (sees_through(s, static_cast<int>(u), static_cast<int>(v), q.z() + margin_m)) hit_[i] = 1;
    }
  }
  const auto flagged = static_cast<std::size_t>(std::count(hit_.begin(), hit_.end(), 1));
  if (static_cast<double>(flagged) > kMaxFraction * static_cast<double>(n)) {
    ++suspect_;
    return 0;
  }
  std::copy(hit_.begin(), hit_.end(), moving.begin());
  return static_cast<int>(flagged);
}

}  // namespace vigs::tracking
