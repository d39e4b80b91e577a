#include "drivers/serial_imu/serial_imu_faults.hpp"

#include <string_view>

#include "drivers/serial_imu/imu_stamper.hpp"
#include "drivers/serial_imu/parser_counters.hpp"

namespace vigs::drivers {
namespace {

struct Field {
  std::string_view name;
  std::uint64_t SerialImuFaults::*member;
};

constexpr Field kFields[] = {
    {"bytes_read", &SerialImuFaults::bytes_read},
    {"packets_ok", &SerialImuFaults::packets_ok},
    {"samples_out", &SerialImuFaults::samples_out},
    {"bad_checksum", &SerialImuFaults::bad_checksum},
    {"resync_bytes_skipped", &SerialImuFaults::resync_bytes_skipped},
    {"oversize_length", &SerialImuFaults::oversize_length},
    {"sample_counter_gap", &SerialImuFaults::sample_counter_gap},
    {"samples_missed", &SerialImuFaults::samples_missed},
    {"non_monotonic_stamp", &SerialImuFaults::non_monotonic_stamp},
    {"ring_drops", &SerialImuFaults::ring_drops},
    {"malformed_payload", &SerialImuFaults::malformed_payload},
    {"incomplete_sample", &SerialImuFaults::incomplete_sample},
    {"unsupported_format", &SerialImuFaults::unsupported_format},
    {"non_finite_sample", &SerialImuFaults::non_finite_sample},
    {"other_messages", &SerialImuFaults::other_messages},
    {"clock_resets", &SerialImuFaults::clock_resets},
    {"read_errors", &SerialImuFaults::read_errors},
    {"hangups", &SerialImuFaults::hangups},
    {"truncated_at_hangup", &SerialImuFaults::truncated_at_hangup},
    {"reopens", &SerialImuFaults::reopens},
};

}  // namespace

io::Json SerialImuFaults::to_json_value() const {
  io::Json j = io::Json::object();
  for (const Field& f : kFields) j[std::string(f.name)] = this->*f.member;
  return j;
}

std::string SerialImuFaults::to_json() const {
  return io::json_line(to_json_value());
}

std::string SerialImuFaults::to_string() const {
  std::string out;
  for (const Field& f : kFields) {
    if (!out.empty()) out += ' ';
    out += f.name;
    out += '=';
    out += std::to_string(this->*f.member);
  }
  return out;
}

void SerialImuFaults::fill(const ParserCounters& c) noexcept {
  packets_ok = c.packets_ok.get();
  bad_checksum = c.bad_checksum.get();
  resync_bytes_skipped = c.resync_bytes_skipped.get();
  oversize_length = c.oversize_length.get();
  malformed_payload = c.malformed_payload.get();
  incomplete_sample = c.incomplete_sample.get();
  unsupported_format = c.unsupported_format.get();
  non_finite_sample = c.non_finite_sample.get();
  other_messages = c.other_messages.get();
}

void SerialImuFaults::fill(const StamperCounters& c) noexcept {
  samples_out = c.samples_out.get();
  sample_counter_gap = c.sample_counter_gap.get();
  samples_missed = c.samples_missed.get();
  non_monotonic_stamp = c.non_monotonic_stamp.get();
  clock_resets = c.clock_resets.get();
}

}  // namespace vigs::drivers
