#pragma once
// The mapper task's body (mapping::Mapper) driven in lockstep with the odometry during a
// replay: each new tracking keyframe is handed over through the mapper's keyframe ring (its
// Gaussians from the tracker's raw kNN covariances, as GS-ICP SLAM, and the frame as training
// view), and after every frame the mapper runs one tick of `iterations_per_frame` optimisation
// iterations over its window of recent keyframes, or as many as a time budget per frame allows
// (mapping.budget_ms, see mapping/mapper.hpp). The pixels of the keyframe's points the
// tracker flagged moving are masked out of its training view (moving_pixels.hpp,
// mapping.moving_mask). Offline and deterministic in its schedule with an
// iteration count; not real time (a live mapper runs at its own rate on its own thread).
#include <cstdint>
#include <memory>
#include <vector>

#include "core/config/mapping_settings.hpp"
#include "core/geometry/se3.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "mapping/mapper.hpp"
#include "rt/worker_team.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

class LockstepMapper {
 public:
  /// Rasterizer threads from s.threads; iterations_per_frame >= 1; budget_ms > 0 replaces
  /// the count by a time budget per frame. tracker_pixel_stride: the stride the keyframes'
  /// points were sampled at (their footprint at insertion).
  LockstepMapper(const config::MappingSettings& s, const PinholeCamera& camera,
                 int iterations_per_frame, double budget_ms, int tracker_pixel_stride);

  /// Hands a keyframe to the mapper with `frame` as its training view (allocates: copies
  /// points and images; depth without a measurement becomes 0, that of moving points' pixels
  /// -1).
  void add_keyframe(const tracking::Keyframe& kf, const RgbdView& frame);
  /// Keeps a copy of the last `frames` frames (keep_frame) so that a keyframe published late
  /// (the tracker's moving test holds it tracking.moving_window_frames frames) is trained on
  /// its own images: add_keyframe(kf) finds them by kf.t_ns.
  void keep_frames(int frames);
  void keep_frame(const RgbdView& frame);
  /// add_keyframe with the kept frame stamped kf.t_ns; false (nothing added) when none is kept.
  /// `T_w_c_map`: where the map places it (the loop-corrected pose); null: kf.T_w_c. Mapper
  /// ids count every keyframe offered, kept frame or not, so that they are the loop closer's
  /// node indices (map_loop_correction.hpp).
  bool add_keyframe(const tracking::Keyframe& kf, const geometry::Pose* T_w_c_map = nullptr);
  /// One mapper tick: ingest, then iterations_per_frame iterations (none before a keyframe).
  void step() { mapper_->tick(); }

  [[nodiscard]] const mapping::GaussianMap& map() const { return mapper_->map(); }
  [[nodiscard]] const mapping::Mapper& mapper() const { return *mapper_; }
  [[nodiscard]] mapping::Mapper& mapper() { return *mapper_; }
  [[nodiscard]] long dropped_keyframes() const { return dropped_keyframes_; }

 private:
  PinholeCamera camera_;
  config::MovingMaskSettings moving_mask_;
  int stride_px_;
  rt::WorkerTeam pool_;
  mapping::KeyframeRing ring_;
  std::unique_ptr<mapping::Mapper> mapper_;
  struct KeptFrame {
    std::int64_t t_ns = -1;
    ImageU8 rgb;
    ImageF32 depth_m;
  };
  void add(std::uint64_t id, const tracking::Keyframe& kf, const ImageU8& rgb, ImageF32 depth_m,
           const geometry::Pose* T_w_c_map);
  std::vector<KeptFrame> kept_;
  std::size_t next_kept_ = 0;
  std::uint64_t next_id_ = 0;
  long dropped_keyframes_ = 0;
};

}  // namespace vigs::pipeline
