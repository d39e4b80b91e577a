// Serial IMU parser throughput (MB/s of wire bytes) on clean and corrupted Xsens MTData2 streams,
// beside a baseline parser run on the same bytes in the same process.
//
// Baseline ("naive"): the textbook way to write such a parser. Each read is appended to a
// std::vector buffer; from the front it looks for a preamble, copies the candidate message into
// a new std::vector, checks it, copies the payload and each field into further vectors, and on
// any failure erases one byte from the front of the buffer and starts again (vector::erase).
// Same accept/reject rules and results as XsensMtParser (checked at set-up).
//
// Streams (20000 messages of 42 bytes, fed in 4096-byte reads like the driver's):
//  clean         every message intact;
//  corrupt10     10% of all bytes replaced by random values (most messages die: resync stress);
//  msgfault10    10% of messages with one flipped bit (checksum failures, resync per message).
// No BENCHMARK_MAIN here: this file joins bench_inertial (see tests/bench/CMakeLists.txt).
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "drivers/serial_imu/byte_order.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "drivers/serial_imu/xsens_parser.hpp"

namespace {

using vigs::drivers::DeviceImuSample;
using vigs::drivers::ImuSampleSink;
namespace xs = vigs::drivers::xsens;

constexpr std::size_t kMessages = 20000;
constexpr std::size_t kReadSize = 4096;

struct CountingSink final : ImuSampleSink {
  std::uint64_t count = 0;
  double checksum = 0.0;
  void on_sample(const DeviceImuSample& s) noexcept override {
    ++count;
    checksum += s.accel_mps2[2];
  }
};

std::vector<std::uint8_t> make_stream(int kind) {
  std::mt19937 rng(1234);
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < kMessages; ++i) {
    const double t = static_cast<double>(i) * 0.005;
    auto m =
        xs::encode_mtdata2(static_cast<std::uint32_t>(50 * i),
                           {0.3 * std::sin(t), 0.2 * std::cos(t), 9.81 + 0.1 * std::sin(3 * t)},
                           {0.01 * std::cos(t), -0.02, 0.5 * std::sin(2 * t)});
    if (kind == 2 && rng() % 10 == 0)
      m[4 + rng() % (m.size() - 4)] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    out.insert(out.end(), m.begin(), m.end());
  }
  if (kind == 1) {
    for (auto& b : out) {
      if (rng() % 10 == 0) b = static_cast<std::uint8_t>(rng());
    }
  }
  return out;
}

const std::vector<std::uint8_t>& stream(int kind) {
  static const std::array<std::vector<std::uint8_t>, 3> streams{make_stream(0), make_stream(1),
                                                                make_stream(2)};
  return streams.at(static_cast<std::size_t>(kind));
}

// ---- baseline ----
class NaiveParser {
 public:
  void feed(const std::uint8_t* data, std::size_t size, ImuSampleSink& sink) {
    buffer_.insert(buffer_.end(), data, data + size);
    for (;;) {
      std::size_t start = 0;
      while (start < buffer_.size() && buffer_[start] != xs::kPreamble) ++start;
      buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start));
      if (buffer_.size() < 4) return;
      if (buffer_[1] != xs::kBusIdMaster) {
        buffer_.erase(buffer_.begin());
        continue;
      }
      std::size_t header = 4, len = buffer_[3];
      if (len == 0xFF) {
        if (buffer_.size() < 6) return;
        header = 6;
        len = vigs::drivers::load_be_u16(&buffer_[4]);
        if (len > xs::kMaxDataSize) {
          buffer_.erase(buffer_.begin());
          continue;
        }
      }
      if (buffer_.size() < header + len + 1) return;
      const std::vector<std::uint8_t> msg(
          buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(header + len + 1));
      std::uint8_t sum = 0;
      for (std::size_t i = 1; i < msg.size(); ++i) sum = static_cast<std::uint8_t>(sum + msg[i]);
      if (sum != 0) {
        buffer_.erase(buffer_.begin());
        continue;
      }
      buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(msg.size()));
      if (msg[2] == xs::kMidMtData2)
        decode(std::vector<std::uint8_t>(msg.begin() + static_cast<std::ptrdiff_t>(header),
                                         msg.end() - 1),
               sink);
    }
  }

 private:
  static void decode(const std::vector<std::uint8_t>& payload, ImuSampleSink& sink) {
    DeviceImuSample s;
    int found = 0;
    for (std::size_t i = 0; i + 3 <= payload.size();) {
      const std::uint16_t id = vigs::drivers::load_be_u16(&payload[i]);
      const std::size_t n = payload[i + 2];
      if (i + 3 + n > payload.size()) return;
      const std::vector<std::uint8_t> field(
          payload.begin() + static_cast<std::ptrdiff_t>(i + 3),
          payload.begin() + static_cast<std::ptrdiff_t>(i + 3 + n));
      if (id == xs::kIdSampleTimeFine && n == 4) {
        s.device_ticks = vigs::drivers::load_be_u32(field.data());
        found |= 1;
      } else if (id == xs::kIdAcceleration && n == 12) {
        for (int k = 0; k < 3; ++k) s.accel_mps2[k] = vigs::drivers::load_be_f32(&field[4 * k]);
        found |= 2;
      } else if (id == xs::kIdRateOfTurn && n == 12) {
        for (int k = 0; k < 3; ++k) s.gyro_rps[k] = vigs::drivers::load_be_f32(&field[4 * k]);
        found |= 4;
      }
      i += 3 + n;
    }
    if (found == 7) sink.on_sample(s);
  }

  std::vector<std::uint8_t> buffer_;
};

template <class Parser>
std::uint64_t run_once(Parser& p, const std::vector<std::uint8_t>& bytes, CountingSink& sink) {
  for (std::size_t at = 0; at < bytes.size(); at += kReadSize) {
    p.feed(bytes.data() + at, std::min(kReadSize, bytes.size() - at), sink);
  }
  return sink.count;
}

template <class Parser>
void BM_Parse(benchmark::State& state) {
  const auto& bytes = stream(static_cast<int>(state.range(0)));
  std::uint64_t samples = 0;
  for (auto _ : state) {
    Parser p;
    CountingSink sink;
    samples = run_once(p, bytes, sink);
    benchmark::DoNotOptimize(sink.checksum);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
  state.counters["samples_per_pass"] = static_cast<double>(samples);
  static const char* const kNames[] = {"clean", "corrupt10", "msgfault10"};
  state.SetLabel(kNames[state.range(0)]);
}

// Both parsers must agree on every stream, or the comparison means nothing.
[[maybe_unused]] const bool kAgree = [] {
  for (int kind = 0; kind < 3; ++kind) {
    vigs::drivers::XsensMtParser a;
    NaiveParser b;
    CountingSink sa, sb;
    run_once(a, stream(kind), sa);
    run_once(b, stream(kind), sb);
    if (sa.count != sb.count || sa.checksum != sb.checksum) {
      throw std::logic_error("bench_serial_parser: baseline and parser disagree");
    }
  }
  return true;
}();

BENCHMARK_TEMPLATE(BM_Parse, vigs::drivers::XsensMtParser)
    ->DenseRange(0, 2)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Parse, NaiveParser)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

}  // namespace
