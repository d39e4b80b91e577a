#pragma once
#include <string>

#include "core/config/camera_settings.hpp"
#include "core/config/dds_settings.hpp"
#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/config/mapping_settings.hpp"
#include "core/config/rt_settings.hpp"
#include "core/config/sim_settings.hpp"
#include "core/config/tracking_settings.hpp"
#include "core/config/visitor.hpp"

namespace vigs::config {

/// Everything one robot's YAML file can say. A new subsystem adds a settings struct with
/// `visit()` and one `section()` line here.
struct RobotConfig {
  std::string robot = "sim_office";
  CameraSettings camera;
  ImuSettings imu;
  InertialSettings inertial;
  ExtrinsicsSettings extrinsics;
  DdsSettings dds;
  RtSettings rt;
  TrackingSettings tracking;
  SimSettings sim;
  MappingSettings mapping;

  void visit(Visitor& v) {
    v.field("robot", robot, {}, "robot name, used in logs and status");
    v.section("camera", camera);
    v.section("imu", imu);
    v.section("inertial", inertial);
    v.section("extrinsics", extrinsics);
    v.section("dds", dds);
    v.section("rt", rt);
    v.section("tracking", tracking);
    v.section("sim", sim);
    v.section("mapping", mapping);
  }
};

}  // namespace vigs::config
