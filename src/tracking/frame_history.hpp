#pragma once
// Moving people: the free-space test against recent frames. The tracker keeps the depth of its
// last few frames (sampled every `cell_px` pixels) with their poses. A keyframe point is MOVING
// when some recent frame looked through the place where it now is: projected into that frame,
// the frame measured a surface farther than the point by more than a margin, in every cell of
// the 3x3 neighbourhood (so a point on a depth edge or a small pose error never counts). A
// person who walked in was not there a moment before (earlier frames see the wall behind
// him); one who walks away is gone a moment later (later frames): the tracker therefore
// inserts a keyframe only once `window` frames after it are in the history too.
//
// Unlike a test against the map, this compares frames a fraction of a second apart, whose
// relative poses are accurate even when the absolute pose has drifted. A frame where more than
// `max_fraction` of the points would be flagged is assumed to be a pose error: nothing is
// flagged (counted in `suspect_keyframes`).
//
// The depth slots are allocated at construction; record() never allocates, flag() only while
// the largest cloud seen grows.
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::tracking {

class FrameHistory {
 public:
  FrameHistory() = default;
  /// `frames`: slots kept (the oldest is overwritten); `cell_px`: depth sampling step.
  FrameHistory(const PinholeCamera& camera, int frames, int cell_px);

  /// Stores frame `t_ns`'s depth (sampled) with its pose; `valid` false (a pose that is only a
  /// guess) keeps the slot out of flag().
  void record(const RgbdView& frame, const geometry::Pose& T_w_c, bool valid);

  /// Flags (sets moving[i] = 1) the points of `cloud_c`, taken at T_w_c, that some other valid
  /// frame saw free space at, by more than `margin_m`. The frame stamped `t_self_ns` (the
  /// cloud's own) is skipped. Returns the number of points flagged (0 when suspect).
  int flag(const GaussianCloud& cloud_c, const geometry::Pose& T_w_c, std::int64_t t_self_ns,
           float margin_m, std::vector<std::uint8_t>& moving);

  [[nodiscard]] int size() const { return static_cast<int>(slots_.size()); }
  [[nodiscard]] std::int64_t suspect_keyframes() const { return suspect_; }
  /// Flag no point of a keyframe when more than this fraction would be flagged.
  static constexpr double kMaxFraction = 0.5;

 private:
  struct Slot {
    std::int64_t t_ns = 0;
    geometry::Pose T_c_w = geometry::Pose::Identity();
    bool valid = false;
    std::vector<float> depth_m;  ///< cols_ x rows_, 0 = no measurement
  };
  /// True when every cell of the 3x3 block around (cu, cv) measured farther than z_m.
  [[nodiscard]] bool sees_through(const Slot& s, int cu, int cv, float z_m) const;

  PinholeCamera camera_;
  int cell_px_ = 1;
  int cols_ = 0, rows_ = 0;
  std::vector<Slot> slots_;
  std::size_t next_ = 0;
  std::vector<std::uint8_t> hit_;  ///< per point, scratch of flag()
  std::int64_t suspect_ = 0;
};

}  // namespace vigs::tracking
