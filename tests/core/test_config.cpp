#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "core/config/yaml_printer.hpp"

namespace vigs::config {
namespace {

const std::string kRobots = std::string(VIGS_SOURCE_DIR) + "/firmware_config/robots/";

/// Loads `text`, expects exactly one diagnostic and returns it.
Diagnostic single_error(const std::string& text) {
  try {
    load_config_text(text, "robot.yaml");
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.diagnostics().size(), 1u) << e.what();
    return e.diagnostics().front();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {};
}

TEST(Config, ShippedRobotFilesLoad) {
  const auto sim = load_config_file(kRobots + "sim_office.yaml");
  EXPECT_EQ(sim.camera.width_px, 720);
  EXPECT_EQ(sim.camera.height_px, 480);
  EXPECT_DOUBLE_EQ(sim.camera.fx_px, 415.69219381653056);
  EXPECT_DOUBLE_EQ(sim.imu.rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(sim.imu.gyro_noise_density, 1.6968e-4);
  EXPECT_DOUBLE_EQ(sim.imu.accel_random_walk, 3.0e-3);
  EXPECT_DOUBLE_EQ(sim.extrinsics.t_b_c_m[1], 0.05);
  EXPECT_EQ(sim.dds.interface_ip, "127.0.0.1");
  const auto live = load_config_file(kRobots + "xtion_serial_imu.yaml");
  EXPECT_EQ(live.camera.driver, "openni2");
  EXPECT_EQ(live.imu.driver, "serial");
}

TEST(Config, BuiltInDefaultIsTheShippedSimOffice) {
  std::ifstream in(kRobots + "sim_office.yaml");
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(std::string(default_config_text()), file);
}

TEST(Config, AbsentKeysKeepDeclaredDefaults) {
  const auto cfg = load_config_text("camera:\n  rate_hz: 30\n", "robot.yaml");
  EXPECT_DOUBLE_EQ(cfg.camera.rate_hz, 30.0);
  EXPECT_EQ(cfg.camera.width_px, CameraSettings{}.width_px);
  EXPECT_DOUBLE_EQ(cfg.imu.gravity_mps2, 9.81);
}

TEST(Config, TypoInKeyNamesKeyLineAndSuggestion) {
  const auto d = single_error("robot: r\nimu:\n  rate_hz: 200\n  gyro_nosie_density: 1e-4\n");
  EXPECT_EQ(d.file, "robot.yaml");
  EXPECT_EQ(d.line, 4);
  EXPECT_EQ(d.column, 3);
  EXPECT_EQ(d.key, "imu.gyro_nosie_density");
  EXPECT_NE(d.message.find("unknown key"), std::string::npos);
  EXPECT_NE(d.message.find("gyro_noise_density"), std::string::npos);
  EXPECT_EQ(d.to_string().rfind("robot.yaml:4:3: key 'imu.gyro_nosie_density'", 0), 0u);
}

TEST(Config, UnknownSectionIsAnError) {
  const auto d = single_error("camrea:\n  rate_hz: 20\n");
  EXPECT_EQ(d.key, "camrea");
  EXPECT_EQ(d.line, 1);
  EXPECT_NE(d.message.find("did you mean 'camera'"), std::string::npos);
}

TEST(Config, OutOfRangeValueNamesRangeAndUnit) {
  const auto d = single_error("camera:\n  rate_hz: 500\n");
  EXPECT_EQ(d.key, "camera.rate_hz");
  EXPECT_EQ(d.line, 2);
  EXPECT_NE(d.message.find("out of range [1, 120] Hz"), std::string::npos) << d.message;
}

TEST(Config, WrongTypesAreErrors) {
  EXPECT_NE(single_error("camera:\n  width_px: wide\n").message.find("expected an integer"),
            std::string::npos);
  EXPECT_NE(single_error("camera:\n  width_px: 640.5\n").message.find("expected an integer"),
            std::string::npos);
  EXPECT_NE(single_error("imu:\n  rate_hz: fast\n").message.find("expected a finite number"),
            std::string::npos);
  EXPECT_NE(single_error("dds:\n  enabled: maybe\n").message.find("true or false"),
            std::string::npos);
  EXPECT_NE(single_error("imu:\n  rate_hz: [1, 2]\n").message.find("got a list"),
            std::string::npos);
  EXPECT_NE(single_error("camera: 5\n").message.find("expected a mapping"), std::string::npos);
  EXPECT_NE(single_error("imu:\n  rate_hz:\n").message.find("has no value"), std::string::npos);
  EXPECT_NE(single_error("imu:\n  rate_hz: .inf\n").message.find("finite"), std::string::npos);
}

TEST(Config, EnumerationListsAllowedValues) {
  const auto d = single_error("camera:\n  driver: kinect\n");
  EXPECT_EQ(d.key, "camera.driver");
  EXPECT_NE(d.message.find("openni2, v4l2, replay"), std::string::npos);
}

TEST(Config, VectorLengthAndCrossFieldRules) {
  EXPECT_NE(single_error("extrinsics:\n  t_b_c_m: [0, 1]\n").message.find("got 2"),
            std::string::npos);
  const auto rot = single_error("extrinsics:\n  R_b_c: [1,0,0, 0,1,0, 0,0,-1]\n");
  EXPECT_EQ(rot.key, "extrinsics.R_b_c");
  EXPECT_EQ(rot.line, 2);
  EXPECT_NE(rot.message.find("proper rotation"), std::string::npos);
  EXPECT_NE(single_error("rt:\n  imu_ring_capacity: 1000\n").message.find("power of two"),
            std::string::npos);
}

TEST(Config, AllErrorsReportedNotOnlyTheFirst) {
  try {
    load_config_text("camera:\n  rate_hz: 0\n  widht_px: 3\nimu:\n  baud: x\n", "r.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.diagnostics().size(), 3u) << e.what();
    EXPECT_EQ(e.diagnostics()[0].line, 2);
    EXPECT_EQ(e.diagnostics()[1].line, 3);
    EXPECT_EQ(e.diagnostics()[2].line, 5);
  }
}

TEST(Config, SyntaxErrorAndMissingFileAreClear) {
  const auto d = single_error("camera:\n  rate_hz: [1, 2\n");
  EXPECT_NE(d.message.find("YAML syntax error"), std::string::npos);
  EXPECT_GT(d.line, 0);
  try {
    load_config_file("/nonexistent/robot.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.yaml: cannot open file"),
              std::string::npos);
  }
}

TEST(Config, PrintedConfigLoadsBackIdentically) {
  auto cfg = load_config_file(kRobots + "xtion_serial_imu.yaml");
  const std::string printed = print_config(cfg);
  EXPECT_NE(printed.find("gyro_noise_density"), std::string::npos);
  EXPECT_NE(printed.find("[rad/s/sqrt(Hz)]"), std::string::npos);
  const auto again = load_config_text(printed, "printed.yaml");
  EXPECT_EQ(print_config(again), printed);
  EXPECT_EQ(again.imu.port, cfg.imu.port);
  EXPECT_EQ(again.extrinsics.t_b_c_m, cfg.extrinsics.t_b_c_m);
}

}  // namespace
}  // namespace vigs::config
