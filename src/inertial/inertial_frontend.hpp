#pragma once
// IMU-seeded initial guess for GICP tracking, as in VIGS (Pak & Kim): the camera pose at
// frame k is composed from the last tracked camera pose and the body motion the IMU predicts,
//   T_w_c(k) = T_w_c(k-1) * T_c_b * T_b(k-1 -> k) * T_b_c,
// where T_b(k-1 -> k) comes from preintegration with gravity in the (z-up) world frame.
// After each GICP result the integrator restarts at that frame with R and p of the tracked
// body pose and v from the last two tracked body positions (dp / dt), and, optionally, a slow
// gyro-bias update from the IMU-vs-GICP rotation residual (gyro_bias_estimator.hpp).
//
// Samples are queued in a ring allocated at construction and integrated once each, lazily,
// up to the requested frame time; a prediction then adds one interpolated partial step. No
// call allocates, locks or logs after construction. Single-threaded: the tracker owns it.
#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/geometry/se3.hpp"
#include "core/history_ring.hpp"
#include "core/types/imu_sample.hpp"
#include "inertial/gyro_bias_estimator.hpp"
#include "inertial/nav_state.hpp"
#include "inertial/preintegrator.hpp"
#include "inertial/state_propagation.hpp"
#include "inertial/stillness_detector.hpp"

namespace vigs::inertial {

enum class VelocityReset {
  kDifference,  ///< v = (p_k - p_{k-1}) / dt (the paper; the mean velocity over the interval)
  kImu,         ///< the same difference, corrected by the preintegrated motion to time k
};

struct InertialFrontendOptions {
  IntegrationScheme scheme = IntegrationScheme::kMidpoint;
  ImuNoise noise;
  Eigen::Vector3d g_w_mps2{0.0, 0.0, -9.81};
  geometry::Pose T_b_c = geometry::Pose::Identity();  ///< camera-to-body extrinsic
  std::int64_t time_offset_ns = 0;  ///< IMU clock minus camera clock (imu.time_offset_s)
  int buffer_capacity = 4096;
  VelocityReset velocity_reset = VelocityReset::kDifference;
  bool estimate_gyro_bias = true;
  GyroBiasEstimatorOptions bias;
  /// Fused mode (update_fused): bias random walks (rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz)) and the
  /// initial standard deviations of velocity and biases at the first reset.
  double gyro_random_walk = 1.9393e-5;
  double accel_random_walk = 3.0e-3;
  double initial_velocity_sigma_mps = 0.1;
  double initial_gyro_bias_sigma_rps = 0.01;
  double initial_accel_bias_sigma_mps2 = 0.1;
  bool estimate_accel_bias = true;  ///< fused mode: false pins the accel bias (sigma 0)
  /// Fused mode: unmodelled white acceleration (m/s^2/sqrt(Hz), world frame) and extra
  /// accel-bias random walk (m/s^3/sqrt(Hz)) in the prediction (config::InertialSettings).
  double extra_accel_noise_density = 0.0;
  double extra_accel_random_walk = 0.0;
  /// Fused mode: prior sigma (rad) and random walk (rad/sqrt(s)) of gravity's tilt in the world
  /// frame (state_propagation.hpp); both 0 pin gravity at g_w_mps2.
  double initial_gravity_tilt_sigma_rad = 0.0;
  double gravity_tilt_random_walk = 0.0;
  /// Fused mode: zero-velocity update (ZUPT) when the IMU shows rest over an interval (the
  /// StillnessDetector's statistic over at least `zupt_window_s` at or below `zupt_threshold`):
  /// the interval's prediction leaves out the extra white acceleration (a body at rest does not
  /// accelerate) and the velocity is measured as 0 with sigma `zupt_sigma_mps`, gated by its
  /// Mahalanobis distance (kZuptGate) and by the speed between the last two fused poses (at
  /// most `zupt_max_tracked_speed_mps`): an IMU-only test cannot tell rest from an even glide,
  /// and a glide the filter has not yet learned would otherwise be held at v = 0 for good.
  /// Per-sample sigma: noise density times sqrt(rate_hz).
  bool zupt = true;
  double zupt_window_s = 0.2;
  double zupt_threshold = 7.0;
  double zupt_sigma_mps = 0.01;
  double zupt_max_tracked_speed_mps = 0.1;
  double rate_hz = 200.0;

  static InertialFrontendOptions from(const config::ImuSettings& imu,
                                      const config::ExtrinsicsSettings& extrinsics,
                                      const config::InertialSettings& inertial);
};

struct InertialFrontendCounters {
  long samples_added = 0;
  long samples_out_of_order = 0;  ///< older than the last queued sample: refused
  long samples_dropped = 0;       ///< oldest queued sample dropped because the ring was full
  long extrapolated = 0;          ///< frame time beyond the newest sample: reading held
  long resets = 0;
  long restarts = 0;  ///< restart(): the motion state forgotten (the tracker restarted its map)
  long zero_velocity_updates = 0;  ///< fused updates whose interval was still: ZUPT applied
  long zupt_gated = 0;  ///< still by the IMU, but refused by a gate (filter or tracked speed)
};

/// Mahalanobis gate of the zero-velocity update: chi-square, 3 degrees of freedom, 99.9 %. A
/// body gliding so evenly that the IMU reads it as still has a velocity the filter knows.
inline constexpr double kZuptGate = 16.27;

class InertialFrontend {
 public:
  explicit InertialFrontend(const InertialFrontendOptions& options);

  /// Queues one sample. Refuses (returns false) samples older than the last one queued.
  bool add_sample(const ImuSample& s);

  /// Frame times t_ns below are camera stamps; the IMU is read at t_ns + time_offset_ns.
  /// Camera pose guess at t_ns. nullopt before the first reset_from_tracked() or for a time
  /// before the last reset.
  [[nodiscard]] std::optional<geometry::Pose> predict_camera_pose(std::int64_t t_ns);
  /// The predicted body state at t_ns (same conditions).
  [[nodiscard]] std::optional<NavState> predict_state(std::int64_t t_ns);

  /// Tracked camera pose at t_ns from GICP: restarts the integrator at t_ns. Returns false for
  /// a time before the last reset.
  bool reset_from_tracked(std::int64_t t_ns, const geometry::Pose& T_w_c);

  /// Fused mode (state_propagation.hpp). The camera pose predicted at t_ns with its 6x6
  /// covariance (of e = [phi; rho] about the world origin, tracking/pose_prior.hpp), from the
  /// filter state (R, p, v, biases) and covariance at the last update, propagated with the
  /// preintegration covariance and the bias random walks. nullopt as predict_camera_pose.
  struct PosePrediction {
    geometry::Pose T_w_c = geometry::Pose::Identity();
    Mat6 covariance = Mat6::Zero();
  };
  [[nodiscard]] std::optional<PosePrediction> predict_camera_pose_fused(std::int64_t t_ns);
  /// Fused mode: the tracker's fused estimate T_w_c at t_ns with its posterior information Y
  /// (prior + GICP, metric) updates the whole state — pose, velocity, gyro and accel bias —
  /// by fused_pose_update and restarts the integrator there. The first call starts the filter
  /// (at rest: v = 0) and ignores Y. Returns false for a time before the last update.
  bool update_fused(std::int64_t t_ns, const geometry::Pose& T_w_c, const Mat6& information);
  /// Fused-mode covariance of [dtheta, dp, dv, dbg, dba, dg] at the last update.
  [[nodiscard]] const MatS& state_covariance() const { return P_; }
  [[nodiscard]] const Eigen::Vector3d& velocity_w_mps() const { return state_.v_w_b_mps; }

  /// Forgets the motion state, keeping the samples and the bias estimates: the next
  /// reset_from_tracked / update_fused starts again as at the first frame (that pose exact, the
  /// body at rest, the fused covariance at its initial sigmas). For a tracker that restarted its
  /// map after losing the track: the velocity the IMU alone carried through the lost frames has
  /// diverged, and every guess from it would lose the new map at once.
  void restart() noexcept {
    started_ = false;
    ++counters_.restarts;
  }

  /// Biases used for the next interval; setting them before the first reset seeds them.
  void set_biases(const Eigen::Vector3d& gyro_rps, const Eigen::Vector3d& accel_mps2);
  [[nodiscard]] const Eigen::Vector3d& bias_gyro_rps() const { return bias_.bias_rps(); }
  [[nodiscard]] const Eigen::Vector3d& bias_accel_mps2() const { return bias_accel_mps2_; }
  /// Gravity in the world frame: g_w_mps2 of the options, tilted by the fused filter's estimate.
  [[nodiscard]] const Eigen::Vector3d& gravity_w_mps2() const { return g_w_mps2_; }
  [[nodiscard]] const NavState& state_at_reset() const { return state_; }
  [[nodiscard]] const Preintegrator& preintegrator() const { return pi_; }
  [[nodiscard]] const GyroBiasEstimator& bias_estimator() const { return bias_; }
  [[nodiscard]] const InertialFrontendCounters& counters() const { return counters_; }

 private:
  void advance_to(std::int64_t t_ns);
  /// Fused mode: integrates up to t and returns the predicted state and covariance, with the
  /// zero-velocity update applied when the interval was still (its bias part kept, and the
  /// update counted, only when `commit`).
  bool propagate_fused(std::int64_t t_ns, bool commit, NavState& s_pred, MatS& P_pred);
  /// Moves the biases and gravity's tilt by their parts of a filter correction dx.
  void correct_biases(const VecS& dx);
  [[nodiscard]] ImuSample reading_at(std::int64_t t_ns);

  InertialFrontendOptions options_;
  HistoryRing<ImuSample> queue_;  ///< samples added but not yet integrated
  std::int64_t last_queued_t_ns_ = INT64_MIN;
  ImuSample last_consumed_;
  bool has_consumed_ = false;

  Preintegrator pi_;
  bool started_ = false;
  NavState state_;              ///< body state at the last reset
  geometry::Pose T_w_c_last_;   ///< last tracked camera pose
  std::int64_t t_last_ns_ = 0;  ///< time of the last reset
  GyroBiasEstimator bias_;
  StillnessDetector still_;
  double tracked_speed_mps_ = 0.0;  ///< between the last two fused poses (body origin)
  Eigen::Vector3d bias_accel_mps2_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d g_w_mps2_;
  MatS P_ = MatS::Zero();
  InertialFrontendCounters counters_;
};

}  // namespace vigs::inertial
