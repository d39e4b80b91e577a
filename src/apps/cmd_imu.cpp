// `vigs imu listen` and `vigs imu play`: check a serial IMU (wiring, baud, protocol, faults)
// without the pipeline, and play an IMU CSV as Xsens wire bytes on a pseudo-terminal so the
// real driver can be tried without hardware.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "apps/commands.hpp"
#include "apps/finite_option.hpp"
#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"
#include "drivers/serial_imu/euroc_imu_csv.hpp"
#include "drivers/serial_imu/pseudo_terminal.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "io/json_text.hpp"
#include "rt/clock.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::apps {
namespace {

struct ListenOptions {
  std::string config_file;
  std::string port;
  int baud = 0;
  std::string protocol;
  double seconds = 5.0;
};

// Figures keep the report's established 9 significant digits.
io::Json json_vec(const double v[3]) {
  return {io::rounded(v[0], 9), io::rounded(v[1], 9), io::rounded(v[2], 9)};
}

int run_listen(const ListenOptions& o) {
  const auto cfg = o.config_file.empty()
                       ? config::load_config_text(config::default_config_text(),
                                                  std::string(config::kDefaultConfigName))
                       : config::load_config_file(o.config_file);
  drivers::SerialImuDriverSettings s = drivers::serial_imu_settings(cfg.imu, cfg.rt);
  if (!o.port.empty()) s.port = o.port;
  if (o.baud > 0) s.baud = o.baud;
  if (!o.protocol.empty()) s.protocol = o.protocol;
  s.realtime_thread = false;  // a diagnostic tool: no SCHED_FIFO or CPU pinning needed
  s.pin_cpu = false;

  rt::SpscRing<ImuSample> ring(static_cast<std::size_t>(cfg.rt.imu_ring_capacity));
  drivers::SerialImuDriver driver(s, ring);
  driver.start();
  const std::int64_t end_ns = rt::monotonic_ns() + rt::s_to_ns(o.seconds);
  std::uint64_t count = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  double accel_sum[3] = {}, gyro_sum[3] = {};
  ImuSample sample;
  for (;;) {
    while (ring.try_pop(sample)) {
      if (count == 0) first_ns = sample.t_ns;
      last_ns = sample.t_ns;
      ++count;
      for (int k = 0; k < 3; ++k) {
        accel_sum[k] += sample.accel_mps2[k];
        gyro_sum[k] += sample.gyro_rps[k];
      }
    }
    if (rt::monotonic_ns() >= end_ns) break;
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(10));
  }
  driver.stop();
  while (ring.try_pop(sample)) {  // samples released at stop
    if (count == 0) first_ns = sample.t_ns;
    last_ns = sample.t_ns;
    ++count;
    for (int k = 0; k < 3; ++k) {
      accel_sum[k] += sample.accel_mps2[k];
      gyro_sum[k] += sample.gyro_rps[k];
    }
  }
  double accel_mean[3] = {}, gyro_mean[3] = {};
  for (int k = 0; k < 3; ++k) {
    accel_mean[k] = count ? accel_sum[k] / static_cast<double>(count) : 0.0;
    gyro_mean[k] = count ? gyro_sum[k] / static_cast<double>(count) : 0.0;
  }
  const double span_s = rt::ns_to_s(last_ns - first_ns);
  io::Json j;
  j["port"] = s.port;
  j["baud"] = s.baud;
  j["protocol"] = s.protocol;
  j["seconds"] = io::rounded(o.seconds, 9);
  j["samples"] = count;
  j["rate_hz"] =
      io::rounded(count > 1 && span_s > 0 ? static_cast<double>(count - 1) / span_s : 0.0, 9);
  j["mean_accel_mps2"] = json_vec(accel_mean);
  j["mean_gyro_rps"] = json_vec(gyro_mean);
  j["faults"] = driver.faults().to_json_value();
  std::cout << io::json_line(j) << "\n";
  return count > 0 ? 0 : 3;
}

struct PlayOptions {
  std::string csv;
  double delay_s = 1.0;
  double max_gap_s = 1.0;
  std::uint32_t stf0 = 0;
};

int run_play(const PlayOptions& o) {
  const auto rows = drivers::read_euroc_imu_csv(o.csv);
  // Playback sleeps through every stamp gap, so a gap is bounded before anything is played: a
  // CSV with a one-hour hole is an error naming the line, not an hour-long sleep.
  std::int64_t widest_ns = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::int64_t gap_ns = rows[i].t_ns - rows[i - 1].t_ns;
    widest_ns = std::max(widest_ns, gap_ns);
    if (static_cast<double>(gap_ns) * 1e-9 > o.max_gap_s) {
      throw std::runtime_error(o.csv + ":" + std::to_string(rows[i].line) + ": stamp gap of " +
                               std::to_string(static_cast<double>(gap_ns) * 1e-9) +
                               " s after the previous sample exceeds --max-gap " +
                               io::json_line(io::Json(o.max_gap_s)) + " s");
    }
  }
  drivers::PseudoTerminal pty;  // the slave held open raw until a reader opens it
  const std::string& slave = pty.slave_path();
  std::cout << io::json_line({{"pty", slave},
                              {"samples", rows.size()},
                              {"duration_s",
                               io::rounded(rt::ns_to_s(rows.back().t_ns - rows.front().t_ns), 6)},
                              {"max_gap_s", io::rounded(rt::ns_to_s(widest_ns), 6)}})
            << std::endl;

  const std::int64_t start_ns = rt::monotonic_ns() + rt::s_to_ns(o.delay_s);
  std::uint64_t bytes = 0;
  for (const auto& r : rows) {
    const std::int64_t dt_ns = r.t_ns - rows.front().t_ns;
    const auto stf =
        static_cast<std::uint32_t>(o.stf0 + static_cast<std::uint64_t>(dt_ns / 100'000));
    const auto msg =
        drivers::xsens::encode_mtdata2(stf, {r.accel_mps2[0], r.accel_mps2[1], r.accel_mps2[2]},
                                       {r.gyro_rps[0], r.gyro_rps[1], r.gyro_rps[2]});
    rt::sleep_until_ns(start_ns + dt_ns);
    if (!pty.write_all(msg))
      throw std::system_error(errno, std::generic_category(), "write to pty master");
    bytes += msg.size();
  }
  // Give a reader time to drain before the hang-up discards unread bytes.
  rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(200));
  pty.close_master();
  std::cout << io::json_line({{"bytes_written", bytes}}) << std::endl;
  return 0;
}

}  // namespace

void add_imu_command(CLI::App& app, ExitCode& exit_code) {
  auto* imu = app.add_subcommand("imu", "Serial IMU tools (driver check, pty playback)");
  imu->require_subcommand(1);

  static ListenOptions listen;
  auto* l = imu->add_subcommand(
      "listen",
      "Run the serial IMU driver for a while and print samples, rate and fault counters "
      "as JSON");
  l->add_option("--config", listen.config_file, "robot YAML (default: built-in sim_office)")
      ->check(CLI::ExistingFile);
  l->add_option("--port", listen.port, "serial device (default: imu.port)");
  l->add_option("--baud", listen.baud, "bit/s (default: imu.baud); non-standard rates use BOTHER")
      ->check(CLI::Range(1, 4'000'000));
  l->add_option("--protocol", listen.protocol, "wire protocol (default: imu.protocol)");
  l->add_option("--seconds", listen.seconds, "how long to listen")
      ->check(kFiniteNumber & CLI::Range(0.1, 3600.0));
  l->callback([&exit_code] {
    try {
      exit_code.value = run_listen(listen);
    } catch (const std::exception& e) {
      std::cerr << "vigs imu listen: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });

  static PlayOptions play;
  auto* p = imu->add_subcommand(
      "play",
      "Play an EuRoC IMU CSV as Xsens MTData2 bytes on a new pseudo-terminal, paced by "
      "its timestamps; prints the pty path first");
  p->add_option("CSV", play.csv, "EuRoC imu0.csv (t_ns, w xyz, a xyz)")
      ->required()
      ->check(CLI::ExistingFile);
  p->add_option("--delay", play.delay_s, "seconds to wait before the first sample")
      ->check(kFiniteNumber & CLI::Range(0.0, 60.0));
  p->add_option("--stf0", play.stf0, "first SampleTimeFine value (10 kHz ticks)");
  p->add_option("--max-gap", play.max_gap_s,
                "largest stamp gap allowed between samples, s; a wider one is an error")
      ->check(kFiniteNumber & CLI::Range(1e-6, 3600.0))
      ->capture_default_str();
  p->callback([&exit_code] {
    try {
      exit_code.value = run_play(play);
    } catch (const std::exception& e) {
      std::cerr << "vigs imu play: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
