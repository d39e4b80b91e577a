// ImuStamper: turns parsed DeviceImuSamples into host-stamped ImuSamples.
//
// Per read() of the port the driver calls begin_read(host_ns) with the time the bytes were in
// hand, feeds the parser with the stamper as its sink, then calls end_read(). Within one read:
//  1. the device counter is unwrapped (modulo 2^counter_bits); a sample whose counter does not
//     advance is dropped and counted (non_monotonic_stamp); `reset_after_backward` such samples in
//     a row mean the device restarted: the clock fit starts over (clock_resets);
//  2. a counter step above gap_factor nominal periods counts one sample_counter_gap (and the
//     samples it skipped in samples_missed);
//  3. the read's newest sample (the tightest latency bound) updates the ClockMapper, then every
//     sample of the read is stamped with the fit. A stamp not after its predecessor is dropped and
//     counted (non_monotonic_stamp).
// Warm-up: the first `warmup_samples` samples after a (re)start are held in a preallocated buffer
// and stamped once the fit has seen them all, so early high-latency reads do not leave a step in
// the output. release() stamps and emits held samples early (end of stream).
// Real-time: only the constructor allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types/imu_sample.hpp"
#include "drivers/serial_imu/clock_mapper.hpp"
#include "drivers/serial_imu/imu_protocol_parser.hpp"
#include "rt/counters.hpp"

namespace vigs::drivers {

struct ImuStamperSettings {
  double nominal_rate_hz = 200.0;  ///< expected sample rate (config imu.rate_hz)
  double gap_factor = 1.5;         ///< counter step above this many periods is a gap
  int warmup_samples = 64;         ///< held until the fit has seen this many samples
  int reset_after_backward = 8;    ///< consecutive non-advancing counters that restart the fit
  std::size_t max_samples_per_read = 512;  ///< batch capacity; larger reads are split
  ClockMapperSettings clock;
};

struct StamperCounters {
  rt::SingleWriterCounter samples_out;          ///< stamped samples handed to the output
  rt::SingleWriterCounter sample_counter_gap;   ///< counter steps above gap_factor periods
  rt::SingleWriterCounter samples_missed;       ///< samples those gaps skipped
  rt::SingleWriterCounter non_monotonic_stamp;  ///< dropped: counter or stamp did not advance
  rt::SingleWriterCounter clock_resets;         ///< device counter restarted: fit started over
};

class StampedSampleSink {
 public:
  virtual ~StampedSampleSink() = default;
  virtual void on_stamped(const ImuSample& sample) noexcept = 0;
};

class ImuStamper final : public ImuSampleSink {
 public:
  ImuStamper(DeviceClockSpec clock, const ImuStamperSettings& settings, StampedSampleSink& out);

  void begin_read(std::int64_t host_receive_ns) noexcept;
  void on_sample(const DeviceImuSample& sample) noexcept override;
  void end_read() noexcept;
  /// Emits samples still held for warm-up, stamped with the fit so far.
  void release() noexcept;
  /// Forgets the device time base and the fit (a new connection). Held samples are discarded;
  /// output stays monotonic with what was already emitted. Counters are kept.
  void reset() noexcept;

  [[nodiscard]] const StamperCounters& counters() const noexcept { return counters_; }
  [[nodiscard]] const ClockMapper& clock_mapper() const noexcept { return mapper_; }

 private:
  struct Pending {
    std::int64_t device_ns;
    DeviceImuSample sample;
  };
  void process_batch() noexcept;
  void emit(const Pending& p) noexcept;
  void restart(std::uint64_t raw_ticks) noexcept;

  DeviceClockSpec clock_;
  ImuStamperSettings s_;
  StampedSampleSink& out_;
  ClockMapper mapper_;
  std::uint64_t counter_mask_;
  double ns_per_tick_;
  double period_ticks_;

  std::int64_t host_ns_ = 0;
  std::vector<Pending> batch_;  // capacity reserved once; size() <= max_samples_per_read
  std::vector<Pending> held_;   // warm-up hold, capacity warmup_samples
  bool started_ = false;        // a first sample has set the counter origin
  bool warm_ = false;
  std::uint64_t last_raw_ = 0;
  std::int64_t unwrapped_ticks_ = 0;
  int backward_run_ = 0;
  std::int64_t last_stamp_ns_ = 0;
  bool has_last_stamp_ = false;
  StamperCounters counters_;
};

}  // namespace vigs::drivers
