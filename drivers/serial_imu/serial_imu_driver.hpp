// SerialImuDriver: reads a serial IMU on its own real-time thread and pushes host-stamped
// ImuSamples into an rt ring.
//
// Thread: rt thread table entry `imu_driver`, created by start(), joined by stop(). Loop: poll()
// the port with a timeout (so stop() returns within about poll_timeout_ms), read() what is there,
// note CLOCK_MONOTONIC, feed the protocol parser, stamp (ImuStamper), push.
// Ring policy: push_or_drop: when the ring is full the newest sample is dropped and counted
// (ring_drops); the driver never blocks.
// A hang-up (device unplugged, pty master closed) is counted once per episode; a message it cut
// off is dropped and counted (truncated_at_hangup) and held warm-up samples are released. The
// port is then closed and reopened by path every reopen_interval_ms (without allocating) until it
// comes back (counted in reopens; the new connection gets a new device time base) or stop().
// A port named /dev/pts/N is never reopened (pty numbers are reused at once by other terminals).
// Real-time: the parser, stamper buffers and read buffer are allocated by the constructor; the
// loop does not allocate, lock or log.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/types/imu_sample.hpp"
#include "drivers/serial_imu/imu_protocol_parser.hpp"
#include "drivers/serial_imu/imu_stamper.hpp"
#include "drivers/serial_imu/serial_bytes.hpp"
#include "drivers/serial_imu/serial_imu_faults.hpp"
#include "drivers/serial_imu/serial_port.hpp"
#include "rt/counters.hpp"
#include "rt/rt_thread.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::config {
struct ImuSettings;
struct RtSettings;
}  // namespace vigs::config

namespace vigs::drivers {

struct SerialImuDriverSettings {
  std::string port = "/dev/ttyUSB0";
  int baud = 921600;
  std::string protocol = "xsens_mt";
  int poll_timeout_ms = 20;      ///< bound on stop() latency
  int reopen_interval_ms = 500;  ///< after a hang-up, reopen the port this often (0: never)
  bool realtime_thread = true;   ///< request the thread table's SCHED_FIFO priority
  bool pin_cpu = true;           ///< pin to the thread table's CPU
  ImuStamperSettings stamper;
};

/// Driver settings from the robot config (imu.port, imu.baud, imu.protocol, imu.rate_hz,
/// rt.realtime_priorities, rt.pin_cpus).
[[nodiscard]] SerialImuDriverSettings serial_imu_settings(const config::ImuSettings& imu,
                                                          const config::RtSettings& rt);

class SerialImuDriver {
 public:
  /// Builds the parser (throws std::invalid_argument for an unknown protocol) and all buffers.
  SerialImuDriver(const SerialImuDriverSettings& settings, rt::SpscRing<ImuSample>& out);
  ~SerialImuDriver();
  SerialImuDriver(const SerialImuDriver&) = delete;
  SerialImuDriver& operator=(const SerialImuDriver&) = delete;

  /// Recorder taps (set before start(); either may be null): every stamped sample, and every
  /// read's raw bytes. A full tap drops the newest item and counts it (tap_sample_drops,
  /// tap_byte_drops); the driver never waits for the recorder.
  void set_taps(rt::SpscRing<ImuSample>* samples, rt::SpscRing<SerialBytes>* bytes) noexcept {
    output_.tap = samples;
    bytes_tap_ = bytes;
  }
  /// Opens the port (throws std::system_error naming it) and starts the read thread.
  void start();
  /// Stops and joins the read thread, then closes the port. Idempotent.
  void stop();
  [[nodiscard]] bool running() const noexcept { return thread_.has_value(); }

  /// Counter snapshot; callable from any thread at any time.
  [[nodiscard]] SerialImuFaults faults() const noexcept;
  /// What the OS granted the read thread (valid while running).
  [[nodiscard]] const rt::ThreadApplyStatus* thread_status() const noexcept;

 private:
  class RingOutput final : public StampedSampleSink {
   public:
    explicit RingOutput(rt::SpscRing<ImuSample>& ring) : ring_(ring) {}
    void on_stamped(const ImuSample& sample) noexcept override;
    rt::SingleWriterCounter drops;
    rt::SpscRing<ImuSample>* tap = nullptr;
    rt::SingleWriterCounter tap_drops;

   private:
    rt::SpscRing<ImuSample>& ring_;
  };

  void run(const std::stop_token& stop) noexcept;
  void tap_bytes(std::int64_t t_ns, std::size_t n) noexcept;

  SerialImuDriverSettings settings_;
  RingOutput output_;
  std::unique_ptr<ImuProtocolParser> parser_;
  ImuStamper stamper_;
  SerialPort port_;
  std::array<std::uint8_t, 4096> read_buf_{};
  rt::SingleWriterCounter bytes_read_;
  rt::SingleWriterCounter read_errors_;
  rt::SingleWriterCounter hangups_;
  rt::SingleWriterCounter truncated_at_hangup_;
  rt::SingleWriterCounter reopens_;
  rt::SpscRing<SerialBytes>* bytes_tap_ = nullptr;
  rt::SingleWriterCounter tap_byte_drops_;
  std::optional<rt::RtThread> thread_;
};

}  // namespace vigs::drivers
