#include "tracking/tracker.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <utility>

namespace vigs::tracking {
namespace {

/// The frame's cloud, stamp and pose into `k` (vector assignment reuses k's capacity).
void copy_into_keyframe(const GaussianCloud& cloud, std::int64_t t_ns, const geometry::Pose& T_w_c,
                        Keyframe& k) {
  k.t_ns = t_ns;
  k.T_w_c = T_w_c;
  k.cloud_c.points_m = cloud.points_m;
  k.cloud_c.cov_raw_m2 = cloud.cov_raw_m2;
  k.cloud_c.cov_m2 = cloud.cov_m2;
  k.cloud_c.colors_rgb = cloud.colors_rgb;
}

}  // namespace

std::string_view to_string(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::initialized:
      return "initialized";
    case TrackingStatus::tracked:
      return "tracked";
    case TrackingStatus::lost_low_inliers:
      return "lost_low_inliers";
    case TrackingStatus::lost_diverged:
      return "lost_diverged";
    case TrackingStatus::lost_degenerate:
      return "lost_degenerate";
  }
  return "unknown";
}

Tracker::Tracker(const PinholeCamera& camera, const Setting& setting, const geometry::Pose& T_w_c0)
    : setting_(setting),
      team_(setting.preprocess_threads, setting.worker),
      pre_(camera, setting.preprocess, team_),
      gicp_(setting.gicp, setting.gicp.num_threads == team_.size() ? &team_ : nullptr),
      map_(setting.local_map),
      policy_{setting.keyframe},
      camera_(camera),
      T_w_c0_(T_w_c0) {
  // Sized for a whole frame at start-up: track() does not allocate afterwards.
  const std::size_t n = pre_.max_points();
  cloud_.reserve(n);
  source_.points_m.reserve(n);
  source_.cov_m2.reserve(n);
  keyframe_.cloud_c.reserve(n);
  keyframe_.moving.reserve(n);
  gicp_.reserve(n);
  if (moving_test_on()) {
    history_ = FrameHistory(camera, 2 * setting.moving_window_frames + 1,
                            std::max(1, setting.preprocess.depth.pixel_stride));
    held_capacity_ = static_cast<std::size_t>(setting.held_keyframes());
    held_.emplace(std::bit_ceil(held_capacity_));
    spare_.resize(held_capacity_);
    for (Keyframe& k : spare_) {
      k.cloud_c.reserve(n);
      k.moving.reserve(n);
    }
  }
}

void Tracker::set_pose_prior(const geometry::Pose& T_w_c_mean, const Matrix6d& information) {
  prior_.T_mean = T_w_c_mean;
  // Metric information into the GICP cost's units (its residual weights are the modelled
  // covariances without the variance scale).
  prior_.information = information * setting_.gicp_variance_scale;
  prior_pending_ = T_w_c_mean.matrix().allFinite() && information.allFinite();
}

geometry::Pose Tracker::guess(std::int64_t t_ns, const geometry::Pose* T_w_c_imu,
                              bool& fell_back) const {
  fell_back = false;
  switch (setting_.initial_guess) {
    case InitialGuessMode::imu:
      if (T_w_c_imu != nullptr) return *T_w_c_imu;
      fell_back = true;
      [[fallthrough]];
    case InitialGuessMode::constant_velocity:
      if (frames_ < 2) return T_w_last_;
      return predict_constant_velocity(T_w_prev_, t_prev_ns_, T_w_last_, t_last_ns_, t_ns);
    case InitialGuessMode::previous_pose:
      break;
  }
  return T_w_last_;
}

const GaussianCloud& Tracker::gicp_source() {
  const auto stride = static_cast<std::size_t>(std::max(1, setting_.gicp_source_stride));
  if (stride == 1) return cloud_;
  source_.points_m.clear();  // keeps capacity (reserved for the whole grid at construction)
  source_.cov_m2.clear();
  const auto take = [&](std::size_t i) {
    source_.points_m.push_back(cloud_.points_m[i]);
    source_.cov_m2.push_back(cloud_.cov_m2[i]);
  };
  const PixelGrid& grid = pre_.last_grid();
  if (grid.describes(cloud_.size())) {
    const auto w = static_cast<std::size_t>(grid.width);
    for (std::size_t row = 0; row < static_cast<std::size_t>(grid.height); row += stride) {
      for (std::size_t col = 0; col < w; col += stride) {
        const std::int32_t i = grid.point_at[row * w + col];
        if (i >= 0) take(static_cast<std::size_t>(i));
      }
    }
  } else {
    for (std::size_t i = 0; i < cloud_.size(); i += stride * stride) take(i);
  }
  return source_;
}

void Tracker::hold_keyframe(std::int64_t t_ns, const geometry::Pose& T_w_c) {
  // A spare is left whenever fewer than held_capacity_ are held (the caller checks).
  HeldKeyframe held{std::move(spare_.back()), frames_};
  spare_.pop_back();
  copy_into_keyframe(cloud_, t_ns, T_w_c, held.keyframe);
  [[maybe_unused]] const bool pushed = held_->try_push(std::move(held));
  assert(pushed && "the ring's capacity is at least held_capacity_");
  T_w_newest_kf_ = T_w_c;
}

void Tracker::drop_held_keyframes() {
  while (HeldKeyframe* held = held_ ? held_->front() : nullptr) {
    spare_.push_back(std::move(held->keyframe));  // within the capacity reserved at start
    held_->pop();
  }
}

void Tracker::make_keyframe(std::int64_t t_ns, const geometry::Pose& T_w_c) {
  copy_into_keyframe(cloud_, t_ns, T_w_c, keyframe_);
  keyframe_.moving.assign(cloud_.size(), 0);
  map_.insert(cloud_, T_w_c, &keyframe_.moving);
  T_w_newest_kf_ = T_w_c;
}

int Tracker::release_held_keyframe() {
  // Swapping with keyframe_ exchanges buffers of the same reserved capacity; keyframe_'s old
  // buffers become the spare.
  HeldKeyframe* held = held_->front();
  std::swap(keyframe_, held->keyframe);
  spare_.push_back(std::move(held->keyframe));
  held_->pop();
  const int moving = history_.flag(keyframe_.cloud_c, keyframe_.T_w_c, keyframe_.t_ns,
                                   static_cast<float>(setting_.moving_margin_m), keyframe_.moving);
  map_.insert(keyframe_.cloud_c, keyframe_.T_w_c, &keyframe_.moving);
  return moving;
}

TrackingOutput Tracker::track(const RgbdView& frame, const geometry::Pose* T_w_c_imu) {
  const std::int64_t t_ns = frame.t_ns;
  TrackingOutput out;
  out.t_ns = t_ns;
  out.points = pre_.process(frame, cloud_);
  if (frames_ == 0) {
    out.T_w_c = out.T_w_c_guess = T_w_c_imu != nullptr ? *T_w_c_imu : T_w_c0_;
    out.status = TrackingStatus::initialized;
    out.pose_from_gicp = false;
    out.keyframe = true;
    make_keyframe(t_ns, out.T_w_c);
  } else {
    out.T_w_c_guess = guess(t_ns, T_w_c_imu, out.guess_fell_back);
    out.prior_used = prior_pending_;
    out.gicp =
        gicp_.align(map_, gicp_source(), out.T_w_c_guess, prior_pending_ ? &prior_ : nullptr);
    out.degenerate = out.gicp.degenerate_directions > 0;
    const geometry::PoseError correction = geometry::pose_error(out.T_w_c_guess, out.gicp.T_t_s);
    if (out.gicp.verdict == GicpVerdict::diverged ||
        correction.translation_m > setting_.max_correction_m ||
        correction.rotation_rad > setting_.max_correction_rad()) {
      out.status = TrackingStatus::lost_diverged;
    } else if (out.gicp.verdict == GicpVerdict::degenerate && !out.prior_used) {
      out.status = TrackingStatus::lost_degenerate;
    } else if (out.gicp.inlier_ratio < setting_.min_inlier_ratio) {
      out.status = TrackingStatus::lost_low_inliers;
    } else {
      out.status = TrackingStatus::tracked;
    }
    out.pose_from_gicp = out.status == TrackingStatus::tracked;
    out.T_w_c = out.pose_from_gicp ? out.gicp.T_t_s : out.T_w_c_guess;
    if (out.pose_from_gicp) {
      // The prior's terms are already in GICP units: divide the whole posterior by the scale.
      out.information = out.gicp.information_posterior / setting_.gicp_variance_scale;
    }
    // While keyframes are held the map lacks them, so the overlap with it says nothing new:
    // only the motion since the newest keyframe counts then.
    const double overlap = held_count() > 0 ? 1.0 : out.gicp.overlap_ratio;
    const bool new_keyframe =
        out.pose_from_gicp && policy_.is_keyframe(overlap, T_w_newest_kf_, out.T_w_c);
    lost_in_a_row_ = out.pose_from_gicp ? 0 : lost_in_a_row_ + 1;
    if (setting_.reinit_after_lost_frames > 0 &&
        lost_in_a_row_ >= setting_.reinit_after_lost_frames) {
      // The old map no longer matches what the camera sees from where the guess puts it:
      // start again here, as at the first frame.
      map_.clear();
      drop_held_keyframes();
      make_keyframe(t_ns, out.T_w_c);
      out.keyframe = true;
      out.reinitialized = true;
      lost_in_a_row_ = 0;
    } else if (new_keyframe && moving_test_on()) {
      // Inserted once the frames after it are seen. (The ring cannot be full: a keyframe
      // held at frame f leaves at frame f + moving_window_frames.)
      if (held_count() < held_capacity_) {
        hold_keyframe(t_ns, out.T_w_c);
        out.held = true;
      }
    } else if (new_keyframe) {
      make_keyframe(t_ns, out.T_w_c);
      out.keyframe = true;
    }
  }
  if (moving_test_on()) {
    history_.record(frame, out.T_w_c, out.pose_from_gicp || frames_ == 0);
    // At most one completes per frame: held keyframes come from distinct frames.
    const HeldKeyframe* oldest = held_->front();
    if (oldest != nullptr && frames_ - oldest->frame >= setting_.moving_window_frames) {
      out.moving_points = release_held_keyframe();
      out.keyframe = true;
    }
  }
  prior_pending_ = false;
  T_w_prev_ = T_w_last_;
  t_prev_ns_ = t_last_ns_;
  T_w_last_ = out.T_w_c;
  t_last_ns_ = t_ns;
  ++frames_;
  return out;
}

}  // namespace vigs::tracking
