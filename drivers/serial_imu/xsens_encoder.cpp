#include "drivers/serial_imu/xsens_encoder.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "drivers/serial_imu/byte_order.hpp"

namespace vigs::drivers::xsens {

std::vector<std::uint8_t> encode_message(std::uint8_t mid, std::span<const std::uint8_t> data) {
  if (data.size() > kMaxDataSize) {
    throw std::length_error("xsens message data of " + std::to_string(data.size()) +
                            " bytes exceeds the maximum of " + std::to_string(kMaxDataSize));
  }
  std::vector<std::uint8_t> msg;
  msg.reserve(kExtendedHeaderSize + data.size() + 1);
  msg.push_back(kPreamble);
  msg.push_back(kBusIdMaster);
  msg.push_back(mid);
  if (data.size() > kMaxStandardDataSize) {
    msg.push_back(kExtendedLength);
    msg.push_back(static_cast<std::uint8_t>(data.size() >> 8));
    msg.push_back(static_cast<std::uint8_t>(data.size()));
  } else {
    msg.push_back(static_cast<std::uint8_t>(data.size()));
  }
  msg.insert(msg.end(), data.begin(), data.end());
  msg.push_back(checksum_of(msg.data() + 1, msg.size() - 1));
  return msg;
}

void append_packet(std::vector<std::uint8_t>& payload, std::uint16_t data_id,
                   std::span<const std::uint8_t> bytes) {
  if (bytes.size() > 255) throw std::length_error("MTData2 packet longer than 255 bytes");
  std::uint8_t head[3];
  store_be_u16(head, data_id);
  head[2] = static_cast<std::uint8_t>(bytes.size());
  payload.insert(payload.end(), head, head + 3);
  payload.insert(payload.end(), bytes.begin(), bytes.end());
}

void append_vec3(std::vector<std::uint8_t>& payload, std::uint16_t type_id,
                 const std::array<double, 3>& v, Precision precision) {
  std::uint8_t bytes[24];
  std::size_t size = 0;
  switch (precision) {
    case Precision::kFloat32:
      for (int i = 0; i < 3; ++i) store_be_f32(bytes + 4 * i, static_cast<float>(v[i]));
      size = 12;
      break;
    case Precision::kFixed1220:
      for (int i = 0; i < 3; ++i) {
        const double scaled = std::round(v[i] * 1048576.0);
        if (!(std::fabs(scaled) <= 2147483647.0)) {
          throw std::out_of_range("value outside the fixed 12.20 range");
        }
        store_be_u32(bytes + 4 * i, static_cast<std::uint32_t>(static_cast<std::int32_t>(scaled)));
      }
      size = 12;
      break;
    case Precision::kFloat64:
      for (int i = 0; i < 3; ++i) store_be_f64(bytes + 8 * i, v[i]);
      size = 24;
      break;
    case Precision::kFixed1632:
      throw std::invalid_argument("fixed 16.32 precision is not supported");
  }
  append_packet(payload,
                static_cast<std::uint16_t>(type_id | static_cast<std::uint16_t>(precision)),
                std::span<const std::uint8_t>(bytes, size));
}

std::vector<std::uint8_t> encode_mtdata2(std::uint32_t sample_time_fine,
                                         const std::array<double, 3>& accel_mps2,
                                         const std::array<double, 3>& gyro_rps,
                                         Precision precision) {
  std::vector<std::uint8_t> payload;
  payload.reserve(3 + 4 + 2 * (3 + 24));
  std::uint8_t stf[4];
  store_be_u32(stf, sample_time_fine);
  append_packet(payload, kIdSampleTimeFine, stf);
  append_vec3(payload, kIdAcceleration, accel_mps2, precision);
  append_vec3(payload, kIdRateOfTurn, gyro_rps, precision);
  return encode_message(kMidMtData2, payload);
}

}  // namespace vigs::drivers::xsens
