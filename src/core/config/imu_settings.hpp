#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// Serial IMU: port, wire protocol and the continuous-time noise model used by
/// preintegration. Defaults are the uHumans2 simulated IMU.
struct ImuSettings {
  std::string driver = "replay";  ///< serial | replay
  std::string port = "/dev/ttyUSB0";
  int baud = 921600;
  std::string protocol = "xsens_mt";
  double rate_hz = 200.0;
  double gyro_noise_density = 1.6968e-4;  ///< rad/s/sqrt(Hz)
  double gyro_random_walk = 1.9393e-5;    ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;    ///< m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;      ///< m/s^3/sqrt(Hz)
  double gravity_mps2 = 9.81;             ///< magnitude; world z points up
  double time_offset_s = 0.0;             ///< t_imu = t_camera + offset

  void visit(Visitor& v) {
    v.field("driver", driver, {"serial", "replay"}, "IMU source");
    v.field("port", port, {}, "serial device path");
    v.field("baud", baud, {"bit/s", 1200, 4000000, "line rate; non-standard rates use BOTHER"});
    v.field("protocol", protocol, {},
            "wire protocol parser; any registered protocol (vigs config check lists them)");
    v.field("rate_hz", rate_hz, {"Hz", 10.0, 4000.0, "nominal sample rate"});
    v.field("gyro_noise_density", gyro_noise_density,
            {"rad/s/sqrt(Hz)", 0.0, 1.0, "gyroscope white noise density"});
    v.field("gyro_random_walk", gyro_random_walk,
            {"rad/s^2/sqrt(Hz)", 0.0, 1.0, "gyroscope bias random walk"});
    v.field("accel_noise_density", accel_noise_density,
            {"m/s^2/sqrt(Hz)", 0.0, 10.0, "accelerometer white noise density"});
    v.field("accel_random_walk", accel_random_walk,
            {"m/s^3/sqrt(Hz)", 0.0, 10.0, "accelerometer bias random walk"});
    v.field("gravity_mps2", gravity_mps2, {"m/s^2", 9.7, 9.9, "local gravity magnitude"});
    v.field("time_offset_s", time_offset_s, {"s", -0.5, 0.5, "IMU clock minus camera clock"});
  }
};

}  // namespace vigs::config
