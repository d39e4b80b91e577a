#include "tracking/local_map.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "core/capacity_bytes.hpp"
#include "tracking/gicp_impl.hpp"

namespace vigs::tracking {

namespace {
constexpr std::int64_t kAxisBits = 21;
constexpr std::int64_t kAxisBias = std::int64_t{1} << (kAxisBits - 1);
constexpr std::int64_t kAxisMask = (std::int64_t{1} << kAxisBits) - 1;

std::int64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (((x + kAxisBias) & kAxisMask) << (2 * kAxisBits)) |
         (((y + kAxisBias) & kAxisMask) << kAxisBits) | ((z + kAxisBias) & kAxisMask);
}
void unpack(std::int64_t key, std::int64_t& x, std::int64_t& y, std::int64_t& z) {
  x = ((key >> (2 * kAxisBits)) & kAxisMask) - kAxisBias;
  y = ((key >> kAxisBits) & kAxisMask) - kAxisBias;
  z = (key & kAxisMask) - kAxisBias;
}
}  // namespace

LocalMap::LocalMap() : LocalMap(Setting{}) {}

LocalMap::LocalMap(const Setting& setting) : setting_(setting) {
  setting_.max_voxels = std::max(1, setting_.max_voxels);
  setting_.points_per_voxel = std::max(1, setting_.points_per_voxel);
  inv_voxel_ = static_cast<float>(1.0 / setting_.voxel_m);
  const auto nv = static_cast<std::size_t>(setting_.max_voxels);
  points_w_.resize(nv * static_cast<std::size_t>(setting_.points_per_voxel));
  covs_w_.resize(points_w_.size());
  confirmed_.resize(points_w_.size());
  born_.resize(points_w_.size());
  depth_m_.resize(points_w_.size());
  voxels_.resize(nv);
  table_.assign(std::bit_ceil(2 * nv), kEmpty);
  free_.reserve(nv);
  scratch_.reserve(nv);
  clear();
}

void LocalMap::clear() {
  std::fill(table_.begin(), table_.end(), kEmpty);
  free_.clear();
  for (std::size_t s = voxels_.size(); s-- > 0;) {
    voxels_[s] = Voxel{};
    free_.push_back(static_cast<std::uint32_t>(s));
  }
  num_points_ = 0;
  num_voxels_ = 0;
  num_confirmed_ = 0;
  confirmed_only_ = false;
}

std::size_t LocalMap::memory_bytes() const {
  return capacity_bytes(points_w_, covs_w_, confirmed_, born_, depth_m_, voxels_, table_, free_,
                        scratch_);
}

std::int64_t LocalMap::key_of(const Eigen::Vector3f& p) const {
  return pack(static_cast<std::int64_t>(std::floor(p.x() * inv_voxel_)),
              static_cast<std::int64_t>(std::floor(p.y() * inv_voxel_)),
              static_cast<std::int64_t>(std::floor(p.z() * inv_voxel_)));
}

std::uint32_t LocalMap::home(std::int64_t key) const {
  auto h = static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull;
  h ^= h >> 29;
  return static_cast<std::uint32_t>(h & (table_.size() - 1));
}

std::uint32_t LocalMap::find(std::int64_t key) const {
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = home(key);; i = (i + 1) & mask) {
    const std::uint32_t slot = table_[i];
    if (slot == kEmpty) return kEmpty;
    if (voxels_[slot].key == key) return slot;
  }
}

std::uint32_t LocalMap::add_voxel(std::int64_t key) {
  if (free_.empty()) return kEmpty;
  const std::uint32_t slot = free_.back();
  free_.pop_back();
  voxels_[slot] = Voxel{key, stamp_, 0, true};
  const std::size_t mask = table_.size() - 1;
  std::size_t i = home(key);
  while (table_[i] != kEmpty) i = (i + 1) & mask;
  table_[i] = slot;
  ++num_voxels_;
  return slot;
}

void LocalMap::remove_voxel(std::uint32_t slot) {
  const std::size_t mask = table_.size() - 1;
  std::size_t i = home(voxels_[slot].key);
  while (table_[i] != slot) i = (i + 1) & mask;
  // Backward-shift deletion keeps every probe chain unbroken without tombstones.
  for (;;) {
    table_[i] = kEmpty;
    std::size_t j = i;
    for (;;) {
      j = (j + 1) & mask;
      if (table_[j] == kEmpty) {
        const std::size_t base = slot * static_cast<std::size_t>(setting_.points_per_voxel);
        for (std::size_t k = 0; k < static_cast<std::size_t>(voxels_[slot].count); ++k) {
          num_confirmed_ -= confirmed_[base + k];
        }
        num_points_ -= static_cast<std::size_t>(voxels_[slot].count);
        voxels_[slot] = Voxel{};
        free_.push_back(slot);
        --num_voxels_;
        return;
      }
      const std::size_t k = home(voxels_[table_[j]].key);
      const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
      if (!stays) break;
    }
    table_[i] = table_[j];
    i = j;
  }
}

void LocalMap::evict_far(const Eigen::Vector3d& position_w) {
  const double r2 = setting_.radius_m * setting_.radius_m;
  for (std::uint32_t s = 0; s < voxels_.size(); ++s) {
    if (!voxels_[s].used) continue;
    std::int64_t x = 0, y = 0, z = 0;
    unpack(voxels_[s].key, x, y, z);
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)) +
         Eigen::Vector3d::Constant(0.5)) *
        setting_.voxel_m;
    if ((centre - position_w).squaredNorm() > r2) remove_voxel(s);
  }
}

void LocalMap::evict_least_recent(std::size_t count) {
  scratch_.clear();
  for (std::uint32_t s = 0; s < voxels_.size(); ++s) {
    if (voxels_[s].used) scratch_.emplace_back(voxels_[s].last_seen, s);
  }
  const std::size_t evict = std::min(count, scratch_.size());
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(evict),
                   scratch_.end());
  for (std::size_t e = 0; e < evict; ++e) remove_voxel(scratch_[e].second);
}

void LocalMap::prune_tentative() {
  const auto P = static_cast<std::size_t>(setting_.points_per_voxel);
  const auto keep = static_cast<std::uint64_t>(std::max(1, setting_.confirm_keyframes));
  for (std::uint32_t s = 0; s < voxels_.size(); ++s) {
    Voxel& v = voxels_[s];
    if (!v.used) continue;
    const std::size_t base = s * P;
    std::size_t out = 0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(v.count); ++k) {
      const std::size_t at = base + k;
      if (confirmed_[at] == 0 && stamp_ - born_[at] > keep) {
        ++pruned_;
        continue;
      }
      if (out != k) {
        points_w_[base + out] = points_w_[at];
        covs_w_[base + out] = covs_w_[at];
        confirmed_[base + out] = confirmed_[at];
        born_[base + out] = born_[at];
        depth_m_[base + out] = depth_m_[at];
      }
      ++out;
    }
    num_points_ -= static_cast<std::size_t>(v.count) - out;
    v.count = static_cast<std::int32_t>(out);
    // An emptied voxel stays allocated until evicted (its stamp says when it was last seen).
  }
}

void LocalMap::insert(const GaussianCloud& cloud_c, const geometry::Pose& T_w_c,
                      const std::vector<std::uint8_t>* skip) {
  ++stamp_;
  evict_far(T_w_c.translation());
  const bool confirm = setting_.confirm_distance_m > 0.0;
  if (confirm) prune_tentative();
  const float confirm_sq =
      static_cast<float>(setting_.confirm_distance_m * setting_.confirm_distance_m);
  const Eigen::Matrix3f R = T_w_c.linear().cast<float>();
  const Eigen::Vector3f t = T_w_c.translation().cast<float>();
  const auto P = static_cast<std::size_t>(setting_.points_per_voxel);
  const bool use_skip = skip != nullptr && skip->size() == cloud_c.size();
  const auto replace_ratio = static_cast<float>(setting_.replace_depth_ratio);
  for (std::size_t i = 0; i < cloud_c.size(); ++i) {
    if (use_skip && (*skip)[i] != 0) continue;
    const Eigen::Vector3f p = R * cloud_c.points_m[i] + t;
    if (!((p * inv_voxel_).cwiseAbs().maxCoeff() < static_cast<float>(kAxisBias - 2))) {
      continue;  // outside the addressable grid (+-2^20 voxels) or NaN
    }
    // Re-observation by this keyframe confirms both points (earlier keyframes' points only:
    // a point of this keyframe does not confirm its neighbour in the same frame).
    std::uint8_t is_confirmed = confirm ? 0 : 1;
    if (confirm) {
      std::uint32_t j = 0;
      if (nearest_any(p, confirm_sq, j)) {
        if (confirmed_[j] == 0) {
          confirmed_[j] = 1;
          ++num_confirmed_;
        }
        is_confirmed = 1;
      }
    }
    const std::int64_t key = key_of(p);
    std::uint32_t slot = find(key);
    if (slot == kEmpty) {
      if (free_.empty()) {
        // Pool full: free a sixteenth of it, least recently seen first (voxels this
        // keyframe already touched carry the newest stamp and go last).
        evict_least_recent(std::max<std::size_t>(1, voxels_.size() / 16));
      }
      slot = add_voxel(key);
      if (slot == kEmpty) continue;
    }
    Voxel& v = voxels_[slot];
    v.last_seen = stamp_;
    const float depth_m = cloud_c.points_m[i].z();
    std::size_t at = slot * P + static_cast<std::size_t>(v.count);
    if (static_cast<std::size_t>(v.count) >= P) {
      if (replace_ratio <= 0.0f) continue;
      // Full: the point seen from farthest (the noisiest, as depth noise grows with depth)
      // gives way to one seen from clearly nearer.
      std::size_t worst = slot * P;
      for (std::size_t k = worst + 1; k < slot * P + P; ++k) {
        if (depth_m_[k] > depth_m_[worst]) worst = k;
      }
      if (!(depth_m < replace_ratio * depth_m_[worst])) continue;
      at = worst;
      num_confirmed_ -= confirmed_[at];
    } else {
      ++v.count;
      ++num_points_;
    }
    points_w_[at] = p;
    covs_w_[at] = R * cloud_c.cov_m2[i] * R.transpose();
    confirmed_[at] = is_confirmed;
    born_[at] = static_cast<std::uint32_t>(stamp_);
    depth_m_[at] = depth_m;
    num_confirmed_ += is_confirmed;
  }
  confirmed_only_ = confirm && num_confirmed_ >= kMinConfirmedPoints;
}

bool LocalMap::nearest_any(const Eigen::Vector3f& q_w, float max_sq_dist,
                           std::uint32_t& index) const {
  // Points of earlier keyframes only: those of the current one carry the current stamp.
  const auto cur = static_cast<std::uint32_t>(stamp_);
  const Eigen::Vector3f g = q_w * inv_voxel_;
  const std::int64_t c[3] = {static_cast<std::int64_t>(std::floor(g.x())),
                             static_cast<std::int64_t>(std::floor(g.y())),
                             static_cast<std::int64_t>(std::floor(g.z()))};
  const auto voxel = static_cast<float>(setting_.voxel_m);
  // Distance from q to the lower / upper face of its voxel, per axis: a voxel d steps away
  // along an axis is at least (face + (|d| - 1) voxel) away along it.
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = (g[a] - static_cast<float>(c[a])) * voxel;
    hi[a] = voxel - lo[a];
  }
  const auto gap2 = [&](int a, std::int64_t d) {
    if (d == 0) return 0.0f;
    const float f = (d < 0 ? lo[a] : hi[a]) + static_cast<float>((d < 0 ? -d : d) - 1) * voxel;
    return f * f;
  };
  const auto P = static_cast<std::uint32_t>(setting_.points_per_voxel);
  float best = max_sq_dist;
  bool found = false;
  const auto scan = [&](std::int64_t dx, std::int64_t dy, std::int64_t dz) {
    const std::uint32_t slot = find(pack(c[0] + dx, c[1] + dy, c[2] + dz));
    if (slot == kEmpty) return;
    const std::uint32_t base = slot * P;
    const auto n = static_cast<std::uint32_t>(voxels_[slot].count);
    for (std::uint32_t k = 0; k < n; ++k) {
      if (born_[base + k] == cur) continue;
      const float d2 = (points_w_[base + k] - q_w).squaredNorm();
      if (d2 < best) {
        best = d2;
        index = base + k;
        found = true;
      }
    }
  };
  // confirm_distance_m <= voxel_m is not required: scan as many voxels as the radius needs,
  // the home voxel first, and skip every voxel wholly beyond the best distance so far (the
  // result is the exact nearest either way).
  const auto reach = static_cast<std::int64_t>(std::ceil(std::sqrt(max_sq_dist) * inv_voxel_));
  scan(0, 0, 0);
  for (std::int64_t dx = -reach; dx <= reach; ++dx) {
    const float bx = gap2(0, dx);
    if (bx >= best) continue;
    for (std::int64_t dy = -reach; dy <= reach; ++dy) {
      const float by = bx + gap2(1, dy);
      if (by >= best) continue;
      for (std::int64_t dz = -reach; dz <= reach; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        if (by + gap2(2, dz) >= best) continue;
        scan(dx, dy, dz);
      }
    }
  }
  return found;
}

bool LocalMap::nearest(const Eigen::Vector3f& q_w, float max_sq_dist, std::uint32_t& index,
                       float& sq_dist, std::uint32_t hint) const {
  return confirmed_only_ ? nearest_impl<true>(q_w, max_sq_dist, index, sq_dist, hint)
                         : nearest_impl<false>(q_w, max_sq_dist, index, sq_dist, hint);
}

template <bool kConfirmedOnly>
bool LocalMap::nearest_impl(const Eigen::Vector3f& q_w, float max_sq_dist, std::uint32_t& index,
                            float& sq_dist, std::uint32_t hint) const {
  const Eigen::Vector3f g = q_w * inv_voxel_;
  if (!(g.cwiseAbs().maxCoeff() < static_cast<float>(kAxisBias - 2))) {
    return false;  // outside the addressable grid (or NaN)
  }
  const std::int64_t c[3] = {static_cast<std::int64_t>(std::floor(g.x())),
                             static_cast<std::int64_t>(std::floor(g.y())),
                             static_cast<std::int64_t>(std::floor(g.z()))};
  const auto voxel = static_cast<float>(setting_.voxel_m);
  // Squared distance from q to the lower / upper face of its voxel, per axis.
  float lo2[3], hi2[3];
  for (int a = 0; a < 3; ++a) {
    const float f = (g[a] - static_cast<float>(c[a])) * voxel;
    lo2[a] = f * f;
    hi2[a] = (voxel - f) * (voxel - f);
  }
  const auto P = static_cast<std::uint32_t>(setting_.points_per_voxel);
  float best = max_sq_dist;
  bool found = false;
  if (hint < points_w_.size() && (!kConfirmedOnly || confirmed_[hint] != 0)) {
    const float d2 = (points_w_[hint] - q_w).squaredNorm();
    if (d2 < best) {
      best = d2;
      index = hint;
      found = true;
    }
  }
  const auto scan = [&](std::int64_t dx, std::int64_t dy, std::int64_t dz) {
    const std::uint32_t slot = find(pack(c[0] + dx, c[1] + dy, c[2] + dz));
    if (slot == kEmpty) return;
    const std::uint32_t base = slot * P;
    const auto n = static_cast<std::uint32_t>(voxels_[slot].count);
    for (std::uint32_t k = 0; k < n; ++k) {
      if constexpr (kConfirmedOnly) {
        if (confirmed_[base + k] == 0) continue;
      }
      const float d2 = (points_w_[base + k] - q_w).squaredNorm();
      if (d2 < best) {
        best = d2;
        index = base + k;
        found = true;
      }
    }
  };
  scan(0, 0, 0);  // home voxel first: its best bound prunes most neighbours
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    const float bx = dx < 0 ? lo2[0] : (dx > 0 ? hi2[0] : 0.0f);
    if (bx >= best) continue;
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      const float by = bx + (dy < 0 ? lo2[1] : (dy > 0 ? hi2[1] : 0.0f));
      if (by >= best) continue;
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const float bz = by + (dz < 0 ? lo2[2] : (dz > 0 ? hi2[2] : 0.0f));
        if (bz >= best) continue;  // the whole voxel is farther than the best so far
        scan(dx, dy, dz);
      }
    }
  }
  if (found) sq_dist = best;
  return found;
}

template GicpResult Gicp::align<LocalMap>(const LocalMap&, const GaussianCloud&,
                                          const geometry::Pose&, const PosePrior*);

}  // namespace vigs::tracking
