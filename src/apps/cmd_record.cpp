// `vigs record --config ROBOT.yaml --out F.mcap [--seconds S]`: run the robot's drivers (camera:
// OpenNI2 device or .oni clip, or a V4L2 depth + colour pair; serial IMU; GPIO frame sync) and
// record their taps with the Recorder (src/record) until S seconds have passed, or SIGINT /
// SIGTERM. A progress line on a terminal; one JSON summary on stdout at the end.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "apps/commands.hpp"
#include "core/config/yaml_loader.hpp"
#include "drivers/gpio_trigger/gpio_trigger.hpp"
#include "drivers/openni2/openni2_driver.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "io/json_text.hpp"
#include "record/recorder.hpp"
#include "rt/clock.hpp"

namespace vigs::apps {
namespace {

std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
extern "C" void on_record_stop_signal(int sig) {
  g_stop_signal.store(sig, std::memory_order_relaxed);  // async-signal-safe: a lock-free store
}

struct RecordOptions {
  std::string config_file;
  std::string out;
  double seconds = 0;  // 0: until a signal
};

constexpr std::uint32_t kMainRing = 4;  // the consumer here only releases: tiny
constexpr std::uint32_t kFrameTap = 16;

int run_record(const RecordOptions& o) {
  const config::RobotConfig cfg = config::load_config_file(o.config_file);
  if (o.out == o.config_file) throw std::runtime_error("--out must not be the config file");
  const bool camera_openni2 = cfg.camera.driver == "openni2";
  const bool camera_v4l2 = cfg.camera.driver == "v4l2";
  const bool imu_serial = cfg.imu.driver == "serial";
  const bool sync = !cfg.camera.trigger_chip.empty() && (camera_openni2 || camera_v4l2);
  if (!camera_openni2 && !camera_v4l2 && !imu_serial) {
    throw std::runtime_error(o.config_file +
                             ": nothing to record: camera.driver is not openni2 or v4l2 and "
                             "imu.driver is not serial");
  }

  // Rings and pool: 1 slot being filled + main ring + tap + 1 held by each consumer.
  const auto w = static_cast<std::uint32_t>(cfg.camera.width_px);
  const auto h = static_cast<std::uint32_t>(cfg.camera.height_px);
  const std::uint32_t channels = camera_v4l2 && cfg.camera.colour_format == "GREY" ? 1u : 3u;
  std::optional<rt::FramePool> pool;
  rt::SpscRing<rt::FrameHandle> main_ring(kMainRing), frame_tap(kFrameTap);
  rt::SpscRing<ImuSample> imu_ring(1024), imu_tap(4096);
  rt::SpscRing<drivers::SerialBytes> bytes_tap(1024);
  rt::SpscRing<drivers::TriggerEdge> edge_ring(64), edge_tap(256);
  record::Recorder recorder(o.out);

  std::unique_ptr<drivers::Openni2Driver> openni2;
  std::unique_ptr<drivers::V4l2RgbdDriver> v4l2;
  std::unique_ptr<drivers::SerialImuDriver> imu;
  std::unique_ptr<drivers::GpioTrigger> trigger;
  std::unique_ptr<drivers::TriggerMatcher> matcher;
  if (camera_openni2 || camera_v4l2) {
    pool.emplace(rt::FramePoolSettings{.slots = 1 + kMainRing + kFrameTap + 2,
                                       .width = w,
                                       .height = h,
                                       .colour_channels = channels});
    recorder.add_frames(*pool, frame_tap,
                        {cfg.camera.fx_px, cfg.camera.fy_px, cfg.camera.cx_px, cfg.camera.cy_px});
  }
  if (sync) {
    trigger = std::make_unique<drivers::GpioTrigger>(
        drivers::gpio_trigger_settings(cfg.camera, cfg.rt), edge_ring);
    trigger->set_tap(&edge_tap);
    matcher = std::make_unique<drivers::TriggerMatcher>(
        edge_ring, drivers::trigger_match_settings(cfg.camera.trigger_tolerance_ms,
                                                   cfg.camera.trigger_offset_ms));
    recorder.add_edges(edge_tap, trigger->source());
  }
  if (camera_openni2) {
    openni2 = std::make_unique<drivers::Openni2Driver>(
        drivers::openni2_settings(cfg.camera, cfg.rt), *pool, main_ring);
    openni2->set_tap(&frame_tap);
    if (matcher) openni2->set_trigger(matcher.get());
  } else if (camera_v4l2) {
    v4l2 = std::make_unique<drivers::V4l2RgbdDriver>(
        drivers::v4l2_rgbd_settings(cfg.camera, cfg.rt), *pool, main_ring);
    v4l2->set_tap(&frame_tap);
    if (matcher) v4l2->set_trigger(matcher.get());
  }
  if (imu_serial) {
    imu = std::make_unique<drivers::SerialImuDriver>(drivers::serial_imu_settings(cfg.imu, cfg.rt),
                                                     imu_ring);
    imu->set_taps(&imu_tap, &bytes_tap);
    recorder.add_imu(imu_tap);
    recorder.add_serial(bytes_tap, cfg.imu.port);
  }

  g_stop_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_record_stop_signal;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);

  recorder.start();  // the file exists before any driver runs
  try {
    if (trigger) trigger->start();
    if (openni2) openni2->start();
    if (v4l2) v4l2->start();
    if (imu) imu->start();
  } catch (...) {
    // A device that cannot be opened: nothing was recorded, so leave no file behind.
    if (imu) imu->stop();
    if (openni2) openni2->stop();
    if (v4l2) v4l2->stop();
    if (trigger) trigger->stop();
    try {
      recorder.stop();
    } catch (...) {
    }
    (void)std::remove(o.out.c_str());
    throw;
  }

  const bool tty = ::isatty(STDERR_FILENO) == 1;
  const std::int64_t t0 = rt::monotonic_ns();
  const std::int64_t end_ns = o.seconds > 0 ? t0 + rt::s_to_ns(o.seconds) : INT64_MAX;
  std::int64_t next_progress = t0;
  bool camera_ended = false;
  auto drops = [&] {
    std::uint64_t d = 0;
    if (openni2) d += openni2->counters().tap_dropped;
    if (v4l2) d += v4l2->counters().rgbd.tap_dropped;
    if (imu) d += imu->faults().tap_sample_drops + imu->faults().tap_byte_drops;
    if (trigger) d += trigger->counters().tap_dropped;
    return d;
  };
  while (g_stop_signal.load(std::memory_order_relaxed) == 0) {
    const std::int64_t now = rt::monotonic_ns();
    if (now >= end_ns) break;
    rt::FrameHandle hd;
    while (main_ring.try_pop(hd)) {
      if (!hd.valid()) {
        camera_ended = true;  // a clip played to its end, or a camera lost for good
      } else {
        pool->release(hd);
      }
    }
    if (camera_ended && !imu && !trigger) break;  // nothing else to wait for
    if (tty && now >= next_progress) {
      const record::RecorderStats s = recorder.stats();
      std::fprintf(stderr, "\r%7.1f s  frames %llu  imu %llu  %.1f MB  drops %llu   ",
                   rt::ns_to_s(now - t0), static_cast<unsigned long long>(s.frames),
                   static_cast<unsigned long long>(s.imu_samples), s.bytes_written / 1e6,
                   static_cast<unsigned long long>(drops()));
      next_progress = now + rt::ms_to_ns(500);
    }
    rt::sleep_until_ns(now + rt::ms_to_ns(5));
  }
  if (imu) imu->stop();
  if (openni2) openni2->stop();
  if (v4l2) v4l2->stop();
  if (trigger) trigger->stop();
  rt::FrameHandle left;
  while (main_ring.try_pop(left)) pool->release(left);
  const std::uint64_t total_drops = drops();
  recorder.stop();  // drains the taps, writes the summary; throws naming the file on failure
  if (tty) std::fputc('\n', stderr);

  const record::RecorderStats s = recorder.stats();
  io::Json j{{"file", o.out},
             {"seconds", io::rounded(rt::ns_to_s(rt::monotonic_ns() - t0), 10)},
             {"frames", s.frames},
             {"imu_samples", s.imu_samples},
             {"serial_chunks", s.serial_chunks},
             {"serial_bytes", s.serial_bytes},
             {"edges", s.edges},
             {"chunks", s.chunks},
             {"bytes", s.bytes_written},
             {"tap_drops", total_drops}};
  if (imu) {
    const drivers::SerialImuFaults f = imu->faults();
    j["imu_driver_samples"] = f.samples_out;
    j["serial_bytes_read"] = f.bytes_read;
  }
  if (openni2) j["camera_fault"] = std::string(drivers::to_string(openni2->fault()));
  j["signal"] = g_stop_signal.load();
  std::cout << io::json_line(j) << "\n";
  std::cout.flush();
  if (!std::cout) throw std::runtime_error("cannot write the summary to stdout");
  return s.frames + s.imu_samples + s.edges > 0 ? 0 : 3;
}

}  // namespace

void add_record_command(CLI::App& app, ExitCode& exit_code) {
  static RecordOptions opt;
  auto* r = app.add_subcommand(
      "record",
      "Record the robot's live drivers (camera, serial IMU with its raw bytes, GPIO frame sync) "
      "into a chunked, crash-safe MCAP file");
  r->add_option("--config", opt.config_file, "robot YAML")->required()->check(CLI::ExistingFile);
  r->add_option("--out", opt.out, "MCAP file to write (written in place, chunk by chunk)")
      ->required();
  r->add_option("--seconds", opt.seconds, "stop after this long (default: until SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e7));
  r->callback([&exit_code] {
    try {
      exit_code.value = run_record(opt);
    } catch (const std::exception& e) {
      std::cerr << "vigs record: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
