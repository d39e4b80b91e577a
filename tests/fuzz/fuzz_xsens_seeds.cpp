// Writes seed inputs for fuzz_xsens_parser into a corpus directory (argument 1): clean messages in
// every decoded precision, an extended-length message, and a short faulty stream. The first byte
// of each seed is the fuzz target's chunking selector.
#include <array>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "drivers/serial_imu/byte_order.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"

namespace x = vigs::drivers::xsens;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_xsens_seeds CORPUS_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  int index = 0;
  auto write = [&](std::vector<std::uint8_t> bytes) {
    bytes.insert(bytes.begin(), static_cast<std::uint8_t>(7 * index));
    const std::string path = dir + "/seed_" + std::to_string(index++);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  };
  const std::array<double, 3> a{0.1, -0.2, 9.81}, g{0.01, 0.02, -0.03};
  std::vector<std::uint8_t> stream;
  for (auto p : {x::Precision::kFloat32, x::Precision::kFixed1220, x::Precision::kFloat64}) {
    const auto m = x::encode_mtdata2(0xFFFFFFCEu, a, g, p);
    write(m);
    stream.insert(stream.end(), m.begin(), m.end());
  }
  std::vector<std::uint8_t> payload;
  x::append_packet(payload, 0x2010, std::vector<std::uint8_t>(200, 0x22));
  std::uint8_t stf[4];
  vigs::drivers::store_be_u32(stf, 1234);
  x::append_packet(payload, x::kIdSampleTimeFine, stf);
  x::append_vec3(payload, x::kIdAcceleration, a, x::Precision::kFloat32);
  x::append_vec3(payload, x::kIdRateOfTurn, g, x::Precision::kFloat32);
  x::append_packet(payload, 0xE020, std::vector<std::uint8_t>(60, 0x33));
  write(x::encode_message(x::kMidMtData2, payload));
  auto faulty = stream;
  faulty[10] ^= 0x04;                                      // checksum failure in the first message
  faulty.insert(faulty.begin() + 45, {0x01, 0xFA, 0x02});  // garbage
  faulty.resize(faulty.size() - 9);                        // cut off
  write(faulty);
  write(stream);
  std::cout << "fuzz_xsens_seeds: wrote " << index << " seeds to " << dir << "\n";
  return 0;
}
