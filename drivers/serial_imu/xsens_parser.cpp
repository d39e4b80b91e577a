#include "drivers/serial_imu/xsens_parser.hpp"

#include "drivers/serial_imu/parser_factory.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "drivers/serial_imu/byte_order.hpp"

namespace vigs::drivers {
namespace {

using xsens::Precision;

// Index of the first preamble in p[from, n), or n.
std::size_t find_preamble(const std::uint8_t* p, std::size_t from, std::size_t n) noexcept {
  if (from >= n) return n;
  const void* hit = std::memchr(p + from, xsens::kPreamble, n - from);
  return hit == nullptr ? n : static_cast<std::size_t>(static_cast<const std::uint8_t*>(hit) - p);
}

enum class FieldResult : std::uint8_t { kOk, kMalformed, kUnsupported };

// Three values of one Acceleration / RateOfTurn packet, in the precision its data ID names.
FieldResult decode_vec3(std::uint16_t id, const std::uint8_t* f, std::size_t size,
                        double out[3]) noexcept {
  switch (static_cast<Precision>(id & xsens::kPrecisionMask)) {
    case Precision::kFloat32:
      if (size != 12) return FieldResult::kMalformed;
      for (int i = 0; i < 3; ++i) out[i] = static_cast<double>(load_be_f32(f + 4 * i));
      return FieldResult::kOk;
    case Precision::kFixed1220:
      if (size != 12) return FieldResult::kMalformed;
      for (int i = 0; i < 3; ++i) {
        const auto raw = static_cast<std::int32_t>(load_be_u32(f + 4 * i));
        out[i] = static_cast<double>(raw) / 1048576.0;  // 2^20
      }
      return FieldResult::kOk;
    case Precision::kFloat64:
      if (size != 24) return FieldResult::kMalformed;
      for (int i = 0; i < 3; ++i) out[i] = load_be_f64(f + 8 * i);
      return FieldResult::kOk;
    case Precision::kFixed1632:
      return size == 18 ? FieldResult::kUnsupported : FieldResult::kMalformed;
  }
  return FieldResult::kMalformed;
}

}  // namespace

XsensMtParser::Check XsensMtParser::check(const std::uint8_t* p, std::size_t avail) noexcept {
  if (avail < 2) return {Verdict::kNeedMore, 2};
  if (p[1] != xsens::kBusIdMaster) return {Verdict::kReject, 0};
  if (avail < xsens::kHeaderSize) return {Verdict::kNeedMore, xsens::kHeaderSize};
  std::size_t header = xsens::kHeaderSize;
  std::size_t data_size = p[3];
  if (p[3] == xsens::kExtendedLength) {
    if (avail < xsens::kExtendedHeaderSize) return {Verdict::kNeedMore, xsens::kExtendedHeaderSize};
    header = xsens::kExtendedHeaderSize;
    data_size = load_be_u16(p + 4);
    if (data_size > xsens::kMaxDataSize) {
      counters_.oversize_length.add();
      return {Verdict::kReject, 0};
    }
  }
  const std::size_t total = header + data_size + 1;
  if (avail < total) return {Verdict::kNeedMore, total};
  std::uint8_t sum = 0;
  for (std::size_t i = 1; i < total; ++i) sum = static_cast<std::uint8_t>(sum + p[i]);
  if (sum != 0) {
    counters_.bad_checksum.add();
    return {Verdict::kReject, 0};
  }
  return {Verdict::kAccept, total};
}

void XsensMtParser::accept(const std::uint8_t* msg, std::size_t size,
                           ImuSampleSink& sink) noexcept {
  counters_.bytes_in_messages.add(size);
  if (msg[2] != xsens::kMidMtData2) {
    counters_.other_messages.add();
    return;
  }
  const std::size_t header =
      msg[3] == xsens::kExtendedLength ? xsens::kExtendedHeaderSize : xsens::kHeaderSize;
  const std::uint8_t* data = msg + header;
  const std::size_t len = size - header - 1;

  DeviceImuSample s;
  bool has_time = false, has_accel = false, has_gyro = false;
  std::size_t i = 0;
  while (i < len) {
    if (len - i < 3) {
      counters_.malformed_payload.add();
      return;
    }
    const std::uint16_t id = load_be_u16(data + i);
    const std::size_t field_size = data[i + 2];
    i += 3;
    if (field_size > len - i) {
      counters_.malformed_payload.add();
      return;
    }
    const std::uint8_t* field = data + i;
    i += field_size;

    FieldResult r = FieldResult::kOk;
    switch (id & xsens::kTypeMask) {
      case xsens::kIdSampleTimeFine:
        if (id != xsens::kIdSampleTimeFine || field_size != 4) {
          r = FieldResult::kMalformed;
        } else {
          s.device_ticks = load_be_u32(field);
          has_time = true;
        }
        break;
      case xsens::kIdAcceleration:
        r = decode_vec3(id, field, field_size, s.accel_mps2);
        has_accel = true;
        break;
      case xsens::kIdRateOfTurn:
        r = decode_vec3(id, field, field_size, s.gyro_rps);
        has_gyro = true;
        break;
      default:
        break;  // other outputs (orientation, status, ...) are not ours: skip
    }
    if (r == FieldResult::kMalformed) {
      counters_.malformed_payload.add();
      return;
    }
    if (r == FieldResult::kUnsupported) {
      counters_.unsupported_format.add();
      return;
    }
  }
  if (!(has_time && has_accel && has_gyro)) {
    counters_.incomplete_sample.add();
    return;
  }
  // A sample that is not finite never leaves the driver: dropped and counted.
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(s.accel_mps2[k]) || !std::isfinite(s.gyro_rps[k])) {
      counters_.non_finite_sample.add();
      return;
    }
  }
  counters_.packets_ok.add();
  sink.on_sample(s);
}

void XsensMtParser::drop_held_front(std::size_t count) noexcept {
  std::memmove(held_buf_.data(), held_buf_.data() + count, held_ - count);
  held_ -= count;
}

void XsensMtParser::feed(const std::uint8_t* data, std::size_t size, ImuSampleSink& sink) noexcept {
  counters_.bytes_fed.add(size);
  const std::uint8_t* p = data;
  std::size_t n = size;

  // 1. Decide the candidate held from earlier calls, topping it up from the input.
  while (held_ > 0) {
    if (held_buf_[0] != xsens::kPreamble) {
      const std::size_t k = find_preamble(held_buf_.data(), 0, held_);
      counters_.resync_bytes_skipped.add(k);
      drop_held_front(k);
      continue;
    }
    const Check c = check(held_buf_.data(), held_);
    if (c.verdict == Verdict::kAccept) {
      accept(held_buf_.data(), c.size, sink);
      drop_held_front(c.size);
    } else if (c.verdict == Verdict::kReject) {
      const std::size_t k = find_preamble(held_buf_.data(), 1, held_);
      counters_.resync_bytes_skipped.add(k);
      drop_held_front(k);
    } else {
      if (n == 0) return;
      const std::size_t take = std::min(c.size - held_, n);
      std::memcpy(held_buf_.data() + held_, p, take);
      held_ += take;
      p += take;
      n -= take;
    }
  }

  // 2. Parse straight from the input; copy only an unfinished tail.
  while (n > 0) {
    const std::size_t k = find_preamble(p, 0, n);
    counters_.resync_bytes_skipped.add(k);
    p += k;
    n -= k;
    if (n == 0) return;
    const Check c = check(p, n);
    if (c.verdict == Verdict::kAccept) {
      accept(p, c.size, sink);
      p += c.size;
      n -= c.size;
    } else if (c.verdict == Verdict::kReject) {
      counters_.resync_bytes_skipped.add(1);
      ++p;
      --n;
    } else {
      std::memcpy(held_buf_.data(), p, n);  // n < c.size <= kMaxMessageSize
      held_ = n;
      return;
    }
  }
}

}  // namespace vigs::drivers

namespace vigs::drivers {

// Found by CMake through this file's name (see parser_factory.hpp).
void register_xsens_parser(ImuParserRegistry& registry) {
  registry.add("xsens_mt", []() -> std::unique_ptr<ImuProtocolParser> {
    return std::make_unique<XsensMtParser>();
  });
}

}  // namespace vigs::drivers
