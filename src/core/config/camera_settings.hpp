#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// RGB-D camera: pinhole intrinsics of the (depth-registered) colour image and the driver.
/// Defaults are the uHumans2 office camera (720x480, 90 deg horizontal FOV, 20 Hz).
struct CameraSettings {
  std::string driver = "replay";  ///< openni2 | v4l2 | replay
  std::string device;             ///< OpenNI2 URI or .oni path, /dev/videoN; empty = first found
  std::string colour_device;      ///< v4l2: the colour node (device is the Z16 depth node)
  std::string colour_format = "YUYV";  ///< v4l2 colour node's fourcc: YUYV | MJPG | GREY
  int width_px = 720;
  int height_px = 480;
  double fx_px = 415.69219381653056;
  double fy_px = 415.69219381653056;
  double cx_px = 360.0;
  double cy_px = 240.0;
  double rate_hz = 20.0;
  std::string trigger_chip;           ///< GPIO frame sync: gpiochip name/path; empty = none
  int trigger_line = 0;               ///< line offset of the camera's strobe on that chip
  double trigger_tolerance_ms = 3.0;  ///< |frame - offset - edge| accepted
  double trigger_offset_ms = 0.0;     ///< expected frame stamp minus edge stamp
  double depth_scale_m = 0.001;       ///< metres per raw depth unit of a 16-bit depth image
  double min_depth_m = 0.1;
  double max_depth_m = 10.0;

  void visit(Visitor& v) {
    v.field("driver", driver, {"openni2", "v4l2", "replay"}, "RGB-D source");
    v.field("device", device, {}, "OpenNI2 URI or .oni file, or V4L2 device; empty = first found");
    v.field("colour_device", colour_device, {},
            "v4l2: colour capture node (device is then the Z16 depth node)");
    v.field("colour_format", colour_format, {"YUYV", "MJPG", "GREY"},
            "v4l2: colour node pixel format");
    v.field("width_px", width_px, {"px", 16, 8192, "image width"});
    v.field("height_px", height_px, {"px", 16, 8192, "image height"});
    v.field("fx_px", fx_px, {"px", 1.0, 1e5, "focal length x"});
    v.field("fy_px", fy_px, {"px", 1.0, 1e5, "focal length y"});
    v.field("cx_px", cx_px, {"px", 0.0, 8192.0, "principal point x"});
    v.field("cy_px", cy_px, {"px", 0.0, 8192.0, "principal point y"});
    v.field("rate_hz", rate_hz, {"Hz", 1.0, 120.0, "frame rate; the tracker runs at this rate"});
    v.field("trigger_chip", trigger_chip, {},
            "GPIO frame sync: gpiochip (gpiochip0 or /dev/gpiochip0); empty = no sync");
    v.field("trigger_line", trigger_line, {"-", 0, 1023, "GPIO line offset of the strobe"});
    v.field("trigger_tolerance_ms", trigger_tolerance_ms,
            {"ms", 0.01, 100.0, "frame-to-edge match tolerance (under half a frame period)"});
    v.field("trigger_offset_ms", trigger_offset_ms,
            {"ms", -100.0, 100.0, "expected frame stamp minus its edge's stamp"});
    v.field("depth_scale_m", depth_scale_m,
            {"m", 1e-6, 1.0, "metres per raw unit of 16-bit depth (0.001 = millimetres)"});
    v.field("min_depth_m", min_depth_m, {"m", 0.0, 100.0, "nearer depth is ignored"});
    v.field("max_depth_m", max_depth_m, {"m", 0.1, 1000.0, "farther depth is ignored"});
    v.require(cx_px < width_px && cy_px < height_px, "cx_px",
              "principal point must lie inside the image");
    v.require(min_depth_m < max_depth_m, "max_depth_m", "max_depth_m must exceed min_depth_m");
    v.require(driver != "v4l2" || device.starts_with("/dev/"), "device",
              "v4l2: device must be the depth node's path under /dev/");
    v.require(driver != "v4l2" || colour_device.starts_with("/dev/"), "colour_device",
              "v4l2: colour_device must be the colour node's path under /dev/");
    v.require(driver != "v4l2" || colour_device != device, "colour_device",
              "v4l2: the colour and depth nodes must differ");
    v.require(trigger_chip.empty() || trigger_chip.starts_with("/dev/gpiochip") ||
                  trigger_chip.starts_with("gpiochip"),
              "trigger_chip", "trigger_chip must be gpiochipN or /dev/gpiochipN");
    v.require(trigger_tolerance_ms * rate_hz < 500.0, "trigger_tolerance_ms",
              "trigger_tolerance_ms must stay under half a frame period (1000 / rate_hz / 2)");
  }
};

}  // namespace vigs::config
