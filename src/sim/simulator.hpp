#pragma once
// Puts the simulator together: floor plan, camera route, people, IMU and ground truth at the
// IMU rate, RGB-D frames at the camera rate, all delivered in time order to a SimSink.
// Deterministic for a configuration (including its seed).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "core/config/robot_config.hpp"
#include "sim/imu_synth.hpp"
#include "sim/people.hpp"
#include "sim/renderer.hpp"
#include "sim/scene.hpp"
#include "sim/sim_sink.hpp"
#include "sim/trajectory.hpp"

namespace vigs::sim {

struct SimStats {
  std::int64_t frames = 0;
  std::int64_t imu_samples = 0;
  double sequence_s = 0.0;
  double route_length_m = 0.0;     ///< path length of the whole route
  double sequence_length_m = 0.0;  ///< path length within the generated sequence
  double wall_s = 0.0;             ///< run time
  double render_s = 0.0;           ///< ray casting (overlaps with writing the previous frame)
  bool stopped = false;            ///< ended early by the `stop` flag of run()
};

class Simulator {
 public:
  /// Uses cfg.sim (preset, humans, seconds, seed, gray, noise, motion), cfg.camera, cfg.imu and
  /// cfg.extrinsics. Throws std::invalid_argument on an unknown preset.
  explicit Simulator(const config::RobotConfig& cfg);

  /// Generates the whole sequence into `sink`, calling it from this thread only. While frame j
  /// is written, frame j+1 is already being rendered. `progress(done_s, total_s)` is called
  /// after every frame when given. When `stop` is given and becomes true (e.g. set by a signal
  /// handler), the run ends after the frame being written, with the IMU and ground truth up to
  /// that frame, and SimStats::stopped is set; the sink is then closed as after a full run.
  SimStats run(SimSink& sink, const std::function<void(double, double)>& progress = {},
               const std::atomic<bool>* stop = nullptr);

  /// Body pose T_w_b and camera pose T_w_c = T_w_b T_b_c at time t.
  [[nodiscard]] geometry::Pose body_pose(double t_s) const;
  [[nodiscard]] geometry::Pose camera_pose(double t_s) const { return body_pose(t_s) * T_b_c_; }
  /// Sequence length (cfg.sim.seconds clamped to the route; 0 = whole route).
  [[nodiscard]] double duration_s() const { return duration_s_; }

  [[nodiscard]] const Scene& scene() const { return scene_; }
  [[nodiscard]] const Trajectory& trajectory() const { return *trajectory_; }
  [[nodiscard]] const std::vector<Walker>& walkers() const { return walkers_; }
  [[nodiscard]] const Renderer& renderer() const { return *renderer_; }
  [[nodiscard]] const geometry::Pose& T_b_c() const { return T_b_c_; }
  [[nodiscard]] const PinholeCamera& camera() const { return camera_; }

  /// Renders the frame at t (as run() does for frame `index`).
  void render_at(double t_s, std::uint64_t index, RgbdFrame& out) const;

 private:
  config::RobotConfig cfg_;
  Scene scene_;
  std::unique_ptr<Trajectory> trajectory_;
  std::vector<Walker> walkers_;
  PinholeCamera camera_;
  std::unique_ptr<Renderer> renderer_;
  geometry::Pose T_b_c_;
  double duration_s_ = 0.0;
};

}  // namespace vigs::sim
