// libFuzzer target: XsensMtParser (and the ImuStamper behind it) on arbitrary bytes.
//
// Checks, beyond "no crash / no sanitizer report":
//  - the result does not depend on how the bytes are chunked (whole input vs. chunk sizes taken
//    from the input itself): same samples, same counters;
//  - every byte is accounted for: fed = in messages + skipped + pending;
//  - decoded samples stamped by the ImuStamper come out strictly increasing in time.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "drivers/serial_imu/imu_stamper.hpp"
#include "drivers/serial_imu/xsens_parser.hpp"

namespace {

using vigs::ImuSample;
using vigs::drivers::DeviceImuSample;
using vigs::drivers::ImuSampleSink;
using vigs::drivers::ParserCounters;
using vigs::drivers::XsensMtParser;

// Fixed-size record of what a parser emitted (bit patterns, so NaNs compare equal).
struct Record final : ImuSampleSink {
  std::uint64_t hash = 1469598103934665603ull;
  std::size_t count = 0;
  DeviceImuSample first[16];
  void mix(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    for (std::size_t i = 0; i < n; ++i) hash = (hash ^ b[i]) * 1099511628211ull;
  }
  void on_sample(const DeviceImuSample& s) noexcept override {
    mix(&s.device_ticks, sizeof s.device_ticks);
    mix(s.gyro_rps, sizeof s.gyro_rps);
    mix(s.accel_mps2, sizeof s.accel_mps2);
    if (count < 16) first[count] = s;
    ++count;
  }
};

struct Monotonic final : vigs::drivers::StampedSampleSink {
  std::int64_t last = 0;
  bool any = false;
  void on_stamped(const ImuSample& s) noexcept override {
    if (any && s.t_ns <= last) std::abort();
    last = s.t_ns;
    any = true;
  }
};

bool same_counters(const ParserCounters& a, const ParserCounters& b) {
  return a.bytes_fed.get() == b.bytes_fed.get() &&
         a.bytes_in_messages.get() == b.bytes_in_messages.get() &&
         a.packets_ok.get() == b.packets_ok.get() &&
         a.other_messages.get() == b.other_messages.get() &&
         a.bad_checksum.get() == b.bad_checksum.get() &&
         a.resync_bytes_skipped.get() == b.resync_bytes_skipped.get() &&
         a.oversize_length.get() == b.oversize_length.get() &&
         a.malformed_payload.get() == b.malformed_payload.get() &&
         a.incomplete_sample.get() == b.incomplete_sample.get() &&
         a.unsupported_format.get() == b.unsupported_format.get();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // The first byte picks the chunking: chunk sizes cycle through 1 .. (data[0] % 64) + 1.
  const std::size_t max_chunk = (data[0] % 64) + 1;
  const std::uint8_t* bytes = data + 1;
  const std::size_t n = size - 1;

  XsensMtParser whole;
  Record whole_out;
  whole.feed(bytes, n, whole_out);

  XsensMtParser chunked;
  Record chunked_out;
  std::size_t step = 1;
  for (std::size_t at = 0; at < n;) {
    const std::size_t len = step < n - at ? step : n - at;
    chunked.feed(bytes + at, len, chunked_out);
    at += len;
    step = step % max_chunk + 1;
  }

  if (whole_out.count != chunked_out.count || whole_out.hash != chunked_out.hash) std::abort();
  if (!same_counters(whole.counters(), chunked.counters())) std::abort();
  if (whole.pending_bytes() != chunked.pending_bytes()) std::abort();
  const ParserCounters& c = whole.counters();
  if (c.bytes_fed.get() !=
      c.bytes_in_messages.get() + c.resync_bytes_skipped.get() + whole.pending_bytes()) {
    std::abort();
  }

  // Stamp what was decoded, as one read per sample at a 5 ms host cadence.
  Monotonic out;
  vigs::drivers::ImuStamperSettings settings;
  settings.warmup_samples = 4;
  settings.reset_after_backward = 3;
  vigs::drivers::ImuStamper stamper(whole.clock(), settings, out);
  const std::size_t k = whole_out.count < 16 ? whole_out.count : 16;
  for (std::size_t i = 0; i < k; ++i) {
    stamper.begin_read(1'000'000'000 + static_cast<std::int64_t>(i) * 5'000'000);
    stamper.on_sample(whole_out.first[i]);
    stamper.end_read();
  }
  stamper.release();
  return 0;
}
