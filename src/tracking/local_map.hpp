#pragma once
// The tracker's GICP target: keyframe Gaussians in WORLD coordinates, held in a bounded voxel
// hash that is updated incrementally (no rebuild per keyframe).
//
// Layout: a fixed pool of `max_voxels` voxels of edge `voxel_m`, each with room for
// `points_per_voxel` points (position and covariance in world) and a last-seen stamp, plus
// an open-addressing hash (linear probing, backward-shift deletion) from voxel coordinates
// to pool slots. Everything is allocated in the constructor; insert, evict and nearest never
// allocate.
//
// Bound: at most max_voxels * points_per_voxel points. Memory is fixed at construction:
// max_voxels * points_per_voxel * 57 B (point 12 B + covariance 36 B + stamp and flag 5 B +
// insertion depth 4 B) +
// max_voxels * 24 B of voxel records + 2-4 * max_voxels * 4 B of hash table. Defaults (16384 voxels
// x 20 points): 327,680 points, about 17 MB.
//
// Policy: a keyframe's points go to the voxel they fall in; a full voxel is stamped as seen and
// keeps its points, except that with replace_depth_ratio > 0 a new point seen from nearer than
// that fraction of the camera depth of the voxel's farthest-seen point replaces it. Depth noise
// grows with depth (about z^2 on structured-light and stereo sensors), and walking down a
// corridor a voxel is first filled from far away: without replacement the map keeps exactly
// its noisiest observations. Voxels farther than `radius_m` from the
// camera are evicted before each insertion; when the pool runs out of free voxels during an
// insertion, the least recently seen sixteenth of the pool is evicted (ties by slot, so the
// map is deterministic).
//
// Moving objects (people): with confirm_distance_m > 0 a keyframe's point enters the map as
// TENTATIVE and becomes CONFIRMED when a later keyframe puts a point within confirm_distance_m
// of it (and the later point is confirmed at once). Static surfaces are re-observed by the next
// keyframe; a walking person has moved by then (0.3 m or more between keyframes at 1 m/s), so
// his points stay tentative and are dropped after confirm_keyframes keyframes. GICP
// correspondences (nearest()) use confirmed points only, once the map holds at least
// kMinConfirmedPoints of them (before that, right after the first keyframe, all points).
// Points the caller flags as moving (insert's `skip`) are not inserted at all.
//
// Correspondences: nearest() scans the query's voxel and its 26 neighbours, so it is exact
// for search radii up to voxel_m (the config requires voxel_m >= max correspondence dist).
// World coordinates must lie within +-2^20 voxels of the origin (+-104 km at 0.1 m); points
// beyond are not stored and queries beyond find nothing.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/config/tracking_components.hpp"
#include "core/geometry/se3.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::tracking {

class LocalMap {
 public:
  using Setting = config::LocalMapSetting;
  static constexpr std::size_t kMinConfirmedPoints = 500;

  LocalMap();
  explicit LocalMap(const Setting& setting);

  /// Evicts voxels farther than radius_m from the camera, makes room by least-recently-seen
  /// eviction if needed, then inserts the cloud (camera frame) at T_w_c with a new stamp.
  /// `skip` (nullable, one byte per point): points with a non-zero byte are not inserted.
  void insert(const GaussianCloud& cloud_c, const geometry::Pose& T_w_c,
              const std::vector<std::uint8_t>* skip = nullptr);
  /// Evicts every voxel whose centre is farther than radius_m from `position_w`.
  void evict_far(const Eigen::Vector3d& position_w);
  void clear();

  // GICP target interface (world frame).
  /// `hint` (a point index, or kNoHint): a candidate checked first, e.g. the query's match at
  /// the previous GICP iteration; its distance bounds the voxel scan, so most neighbours are
  /// skipped. The result is the exact nearest point either way.
  bool nearest(const Eigen::Vector3f& q_w, float max_sq_dist, std::uint32_t& index, float& sq_dist,
               std::uint32_t hint = kNoHint) const;
  static constexpr std::uint32_t kNoHint = 0xffffffffu;
  [[nodiscard]] const Eigen::Vector3f& point(std::uint32_t i) const { return points_w_[i]; }
  [[nodiscard]] const Eigen::Matrix3f& cov(std::uint32_t i) const { return covs_w_[i]; }

  /// Calls fn(point_w) for every point held (diagnostics and tests).
  template <class Fn>
  void for_each_point(Fn&& fn) const {
    const auto P = static_cast<std::size_t>(setting_.points_per_voxel);
    for (std::size_t s = 0; s < voxels_.size(); ++s) {
      if (!voxels_[s].used) continue;
      for (std::size_t k = 0; k < static_cast<std::size_t>(voxels_[s].count); ++k) {
        fn(points_w_[s * P + k]);
      }
    }
  }
  [[nodiscard]] bool confirmed(std::uint32_t i) const { return confirmed_[i] != 0; }
  [[nodiscard]] std::size_t num_confirmed() const { return num_confirmed_; }
  /// Tentative points dropped unconfirmed so far.
  [[nodiscard]] std::size_t pruned_points() const { return pruned_; }
  [[nodiscard]] std::size_t num_points() const { return num_points_; }
  [[nodiscard]] std::size_t num_voxels() const { return num_voxels_; }
  [[nodiscard]] std::size_t max_points() const { return points_w_.size(); }
  /// Bytes held by the map's buffers (constant after construction).
  [[nodiscard]] std::size_t memory_bytes() const;
  [[nodiscard]] std::uint64_t stamp() const { return stamp_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

 private:
  struct Voxel {
    std::int64_t key = 0;
    std::uint64_t last_seen = 0;
    std::int32_t count = 0;
    bool used = false;
  };
  static constexpr std::uint32_t kEmpty = 0xffffffffu;

  [[nodiscard]] std::int64_t key_of(const Eigen::Vector3f& p) const;
  [[nodiscard]] std::uint32_t home(std::int64_t key) const;
  [[nodiscard]] std::uint32_t find(std::int64_t key) const;  ///< slot or kEmpty
  std::uint32_t add_voxel(std::int64_t key);                 ///< kEmpty when the pool is full
  void remove_voxel(std::uint32_t slot);
  void evict_least_recent(std::size_t count);
  void prune_tentative();
  bool nearest_any(const Eigen::Vector3f& q_w, float max_sq_dist, std::uint32_t& index) const;
  template <bool kConfirmedOnly>
  bool nearest_impl(const Eigen::Vector3f& q_w, float max_sq_dist, std::uint32_t& index,
                    float& sq_dist, std::uint32_t hint) const;

  Setting setting_;
  float inv_voxel_ = 10.0f;
  std::vector<Eigen::Vector3f> points_w_;
  std::vector<Eigen::Matrix3f> covs_w_;
  std::vector<std::uint8_t> confirmed_;  ///< per point: 1 once re-observed
  std::vector<std::uint32_t> born_;      ///< per point: the stamp it was inserted at
  std::vector<float> depth_m_;           ///< per point: camera depth when inserted
  std::vector<Voxel> voxels_;
  std::vector<std::uint32_t> table_;                              ///< hash position -> voxel slot
  std::vector<std::uint32_t> free_;                               ///< free voxel slots (stack)
  std::vector<std::pair<std::uint64_t, std::uint32_t>> scratch_;  ///< LRU selection
  std::size_t num_points_ = 0;
  std::size_t num_confirmed_ = 0;
  std::size_t pruned_ = 0;
  bool confirmed_only_ = false;  ///< nearest() uses confirmed points only
  std::size_t num_voxels_ = 0;
  std::uint64_t stamp_ = 0;
};

}  // namespace vigs::tracking
