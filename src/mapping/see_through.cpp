#include "mapping/see_through.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/compact_kept.hpp"

namespace vigs::mapping {

namespace {

constexpr std::uint16_t kMaxCount = std::numeric_limits<std::uint16_t>::max();

void add_one(std::uint16_t& c) {
  if (c < kMaxCount) ++c;
}

}  // namespace

std::size_t SeeThrough::vote(const GaussianMap& map, const RenderCamera& cam, const float* depth_m,
                             std::vector<char>& keep, MapBlocks* blocks,
                             const std::uint32_t* anchor, std::uint32_t voter_id,
                             const std::uint8_t* far) {
  const std::size_t n = map.size();
  if (through_.size() > n) {  // the map lost Gaussians without compact(): counts are stale
    through_.clear();
    seen_.clear();
  }
  through_.resize(n, 0);  // Gaussians appended since the last vote start with none
  seen_.resize(n, 0);
  keep.assign(n, 1);
  if (!depth_m || cam.width_px < 3 || cam.height_px < 3) return 0;
  // the vote looks only at means inside the image in front of the camera (z > 1 mm)
  std::size_t pruned = 0;
  for_ranges_in_view(map, cam, blocks, [&](std::size_t lo, std::size_t hi) {
    pruned += vote_range(map, cam, depth_m, lo, hi, keep, anchor, voter_id, far);
  });
  return pruned;
}

std::size_t SeeThrough::vote_range(const GaussianMap& map, const RenderCamera& cam,
                                   const float* depth_m, std::size_t lo, std::size_t hi,
                                   std::vector<char>& keep, const std::uint32_t* anchor,
                                   std::uint32_t voter_id, const std::uint8_t* far_flags) {
  const int w = cam.width_px, h = cam.height_px;
  const double* R = cam.R_c_w;
  const double* t = cam.t_c_w;
  const double frac = std::clamp(s_.min_fraction, 0.0, 1.0);
  const auto min_count = static_cast<std::uint16_t>(std::clamp(s_.min_count, 1, int{kMaxCount}));
  const bool by_age = anchor != nullptr && s_.max_age_keyframes > 0;
  const auto max_age = static_cast<std::int64_t>(s_.max_age_keyframes);
  std::size_t pruned = 0;
  for (std::size_t i = lo; i < hi; ++i) {
    if (map.opacity_logit[i] <= kRemovedLogit) continue;  // removed, awaiting compaction
    if (by_age && static_cast<std::int64_t>(voter_id) - anchor[i] > max_age) continue;
    const float* m = &map.mean_w[3 * i];
    const double z = R[6] * m[0] + R[7] * m[1] + R[8] * m[2] + t[2];
    if (!(z > 1e-3)) continue;
    const double x = R[0] * m[0] + R[1] * m[1] + R[2] * m[2] + t[0];
    const double y = R[3] * m[0] + R[4] * m[1] + R[5] * m[2] + t[1];
    const double u = cam.fx_px * x / z + cam.cx_px, v = cam.fy_px * y / z + cam.cy_px;
    // the 3x3 neighbourhood must lie inside the image
    if (!(u >= 0.5 && v >= 0.5 && u < w - 1.5 && v < h - 1.5)) continue;
    const int uc = static_cast<int>(std::lround(u)), vc = static_cast<int>(std::lround(v));
    const double margin = s_.margin_m + s_.margin_per_m * z;
    const double far_z = z + margin;
    // a far-field Gaussian stands for "no depth here": a missing pixel agrees with it
    const bool far = far_flags != nullptr && far_flags[i] != 0;
    const bool missing_far = s_.missing_far && !far;
    bool all_behind = true, votes = true;
    for (int dv = -1; dv <= 1 && votes; ++dv) {
      const float* row = depth_m + static_cast<std::size_t>(vc + dv) * w + uc;
      for (int du = -1; du <= 1; ++du) {
        const float d = row[du];
        if (d < 0.0f || (!(d > 0.0f) && !missing_far && !far)) {  // moving, or missing
          votes = false;
          break;
        }
        // missing: beyond the range, so behind (missing_far), or the far Gaussian's own "far"
        if (d > 0.0f ? !(d > far_z) : far) all_behind = false;
      }
    }
    if (!votes) continue;
    const float d_c = depth_m[static_cast<std::size_t>(vc) * w + uc];
    if (all_behind) {
      add_one(through_[i]);
    } else if (d_c > 0.0f ? std::abs(d_c - z) <= margin : far) {
      add_one(seen_[i]);
    } else {
      continue;  // hidden behind a nearer surface, or at an edge: no vote
    }
    const std::uint16_t th = through_[i];
    if (th >= min_count && th >= frac * (static_cast<double>(th) + seen_[i])) {
      keep[i] = 0;
      ++pruned;
    }
  }
  return pruned;
}

void SeeThrough::compact(const std::vector<char>& keep) {
  if (through_.size() > keep.size()) {  // counts past the mask belong to no kept Gaussian
    through_.resize(keep.size());
    seen_.resize(keep.size());
  }
  compact_kept(through_, keep);
  compact_kept(seen_, keep);
}

}  // namespace vigs::mapping
