#include "drivers/serial_imu/imu_stamper.hpp"

#include <cmath>
#include <stdexcept>

namespace vigs::drivers {

ImuStamper::ImuStamper(DeviceClockSpec clock, const ImuStamperSettings& settings,
                       StampedSampleSink& out)
    : clock_(clock), s_(settings), out_(out), mapper_(settings.clock) {
  if (!(clock.tick_hz > 0.0) || clock.counter_bits == 0 || clock.counter_bits > 64) {
    throw std::invalid_argument("ImuStamper: device clock needs tick_hz > 0 and 1..64 bits");
  }
  if (!(settings.nominal_rate_hz > 0.0) || settings.warmup_samples < 0 ||
      settings.max_samples_per_read == 0) {
    throw std::invalid_argument("ImuStamper: invalid settings");
  }
  counter_mask_ =
      clock.counter_bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << clock.counter_bits) - 1;
  ns_per_tick_ = 1e9 / clock.tick_hz;
  period_ticks_ = clock.tick_hz / settings.nominal_rate_hz;
  batch_.reserve(settings.max_samples_per_read);
  held_.reserve(static_cast<std::size_t>(settings.warmup_samples));
  warm_ = settings.warmup_samples == 0;
}

void ImuStamper::begin_read(std::int64_t host_receive_ns) noexcept {
  host_ns_ = host_receive_ns;
  batch_.clear();
}

void ImuStamper::restart(std::uint64_t raw_ticks) noexcept {
  release();
  mapper_.reset();
  started_ = true;
  warm_ = s_.warmup_samples == 0;
  last_raw_ = raw_ticks;
  unwrapped_ticks_ = 0;
  backward_run_ = 0;
}

void ImuStamper::reset() noexcept {
  batch_.clear();
  held_.clear();
  mapper_.reset();
  started_ = false;
  warm_ = s_.warmup_samples == 0;
  backward_run_ = 0;
}

void ImuStamper::on_sample(const DeviceImuSample& sample) noexcept {
  const std::uint64_t raw = sample.device_ticks & counter_mask_;
  if (!started_) {
    restart(raw);
  } else {
    const std::uint64_t step = (raw - last_raw_) & counter_mask_;
    const std::uint64_t half = (counter_mask_ >> 1) + 1;
    if (step == 0 || step >= half) {
      if (++backward_run_ < s_.reset_after_backward) {
        counters_.non_monotonic_stamp.add();
        return;
      }
      // The device restarted its counter: begin a new time base with this sample.
      process_batch();
      batch_.clear();
      counters_.clock_resets.add();
      restart(raw);
    } else {
      backward_run_ = 0;
      const double periods = static_cast<double>(step) / period_ticks_;
      if (periods > s_.gap_factor) {
        counters_.sample_counter_gap.add();
        counters_.samples_missed.add(static_cast<std::uint64_t>(std::llround(periods)) - 1);
      }
      unwrapped_ticks_ += static_cast<std::int64_t>(step);
      last_raw_ = raw;
    }
  }
  if (batch_.size() == s_.max_samples_per_read) {
    process_batch();
    batch_.clear();
  }
  const auto device_ns =
      static_cast<std::int64_t>(std::llround(static_cast<double>(unwrapped_ticks_) * ns_per_tick_));
  batch_.push_back({device_ns, sample});  // within reserved capacity: no allocation
}

void ImuStamper::end_read() noexcept {
  process_batch();
  batch_.clear();
}

void ImuStamper::process_batch() noexcept {
  if (batch_.empty()) return;
  mapper_.observe(batch_.back().device_ns, host_ns_);
  for (const Pending& p : batch_) {
    if (warm_) {
      emit(p);
      continue;
    }
    held_.push_back(p);  // within reserved capacity
    if (held_.size() >= static_cast<std::size_t>(s_.warmup_samples)) {
      warm_ = true;
      release();
    }
  }
}

void ImuStamper::release() noexcept {
  for (const Pending& p : held_) emit(p);
  held_.clear();
}

void ImuStamper::emit(const Pending& p) noexcept {
  const std::int64_t t_ns = mapper_.map(p.device_ns);
  if (has_last_stamp_ && t_ns <= last_stamp_ns_) {
    counters_.non_monotonic_stamp.add();
    return;
  }
  last_stamp_ns_ = t_ns;
  has_last_stamp_ = true;
  ImuSample out;
  out.t_ns = t_ns;
  for (int i = 0; i < 3; ++i) {
    out.gyro_rps[i] = p.sample.gyro_rps[i];
    out.accel_mps2[i] = p.sample.accel_mps2[i];
  }
  counters_.samples_out.add();
  out_.on_stamped(out);
}

}  // namespace vigs::drivers
