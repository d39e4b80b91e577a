// `vigs rgbd play FILE.oni`: run the OpenNI2 RGB-D driver on a clip played back by real OpenNI2
// and print one JSON line per delivered frame, then the driver's counters.
#include <iostream>
#include <sstream>
#include <string>

#include "apps/commands.hpp"
#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"
#include "drivers/openni2/openni2_driver.hpp"
#include "io/json_text.hpp"
#include "rt/clock.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::apps {
namespace {

struct PlayOptions {
  std::string file;
  std::string config_file;
  int width_px = 0;
  int height_px = 0;
  int ring_capacity = 64;
  int frame_timeout_ms = 2000;
};

int run_play(const PlayOptions& o) {
  const auto cfg = o.config_file.empty()
                       ? config::load_config_text(config::default_config_text(),
                                                  std::string(config::kDefaultConfigName))
                       : config::load_config_file(o.config_file);
  drivers::Openni2DriverSettings s = drivers::openni2_settings(cfg.camera, cfg.rt);
  s.uri = o.file;
  if (o.width_px > 0) s.width_px = static_cast<std::uint32_t>(o.width_px);
  if (o.height_px > 0) s.height_px = static_cast<std::uint32_t>(o.height_px);
  s.frame_timeout_ms = o.frame_timeout_ms;
  s.realtime_thread = false;  // a diagnostic tool: no SCHED_FIFO or CPU pinning needed
  s.pin_cpu = false;

  // Ring plus one slot being filled plus the one this loop holds: nothing drops unless printing
  // falls a whole ring behind OpenNI2.
  const auto ring_capacity = static_cast<std::uint32_t>(o.ring_capacity);
  rt::FramePool pool({.slots = ring_capacity + 2,
                      .width = s.width_px,
                      .height = s.height_px,
                      .colour_channels = 3});
  rt::SpscRing<rt::FrameHandle> ring(ring_capacity);
  drivers::Openni2Driver driver(s, pool, ring);
  driver.start();
  const std::size_t centre = (s.height_px / 2) * s.width_px + s.width_px / 2;
  std::int64_t last_t_ns = 0;
  for (;;) {
    rt::FrameHandle h;
    if (!ring.try_pop(h)) {
      rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(1));
      continue;
    }
    if (!h.valid()) break;  // end-of-stream marker
    const rt::Frame& f = pool.frame(h);
    io::Json j;
    j["sequence"] = f.sequence;
    j["t_ns"] = f.t_ns;
    j["dt_ms"] = io::rounded(last_t_ns == 0 ? 0.0 : rt::ns_to_ms(f.t_ns - last_t_ns), 10);
    j["centre_depth_mm"] = f.depth[centre];
    j["centre_rgb"] = {int{f.colour[3 * centre]}, int{f.colour[3 * centre + 1]},
                       int{f.colour[3 * centre + 2]}};
    std::cout << io::json_line(j) << "\n";
    last_t_ns = f.t_ns;
    pool.release(h);
  }
  driver.stop();
  const drivers::RgbdDriverCounters c = driver.counters();
  std::cout << io::json_line({{"file", o.file},
                              {"width_px", s.width_px},
                              {"height_px", s.height_px},
                              {"state", std::string(drivers::to_string(driver.state()))},
                              {"fault", std::string(drivers::to_string(driver.fault()))},
                              {"counters", drivers::to_json_value(c)}})
            << "\n";
  if (driver.fault() != drivers::DeviceFault::kNone) {
    // The frames before the fault were printed; the stream did not end cleanly.
    std::cerr << "vigs rgbd play: " << driver.fault_message() << "\n";
    return 1;
  }
  return c.delivered > 0 ? 0 : 3;
}

}  // namespace

void add_rgbd_command(CLI::App& app, ExitCode& exit_code) {
  auto* rgbd = app.add_subcommand("rgbd", "RGB-D driver tools (OpenNI2)");
  rgbd->require_subcommand(1);

  static PlayOptions play;
  auto* p = rgbd->add_subcommand(
      "play",
      "Play a .oni clip through real OpenNI2 and the RGB-D driver thread; prints one JSON line "
      "per frame, then the driver's counters");
  p->add_option("FILE", play.file, ".oni clip (vigs mcap oni makes one)")->required();
  p->add_option("--config", play.config_file, "robot YAML (default: built-in sim_office)")
      ->check(CLI::ExistingFile);
  p->add_option("--width", play.width_px, "px (default: camera.width_px)")
      ->check(CLI::Range(1, 8192));
  p->add_option("--height", play.height_px, "px (default: camera.height_px)")
      ->check(CLI::Range(1, 8192));
  p->add_option("--ring", play.ring_capacity, "driver-to-consumer ring capacity (power of two)")
      ->check(CLI::Range(1, 4096));
  p->add_option("--frame-timeout-ms", play.frame_timeout_ms,
                "playback watchdog: no frame for this long ends the stream as failed (exit 1)")
      ->check(CLI::Range(100, 600000));
  p->callback([&exit_code] {
    try {
      exit_code.value = run_play(play);
    } catch (const std::exception& e) {
      std::cerr << "vigs rgbd play: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
