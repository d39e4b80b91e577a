#include "drivers/serial_imu/parser_factory.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "drivers/serial_imu/xsens_parser.hpp"

namespace vigs::drivers {
namespace {

struct Entry {
  std::string_view name;
  std::unique_ptr<ImuProtocolParser> (*make)();
};

constexpr std::array kProtocols{
    Entry{"xsens_mt",
          []() -> std::unique_ptr<ImuProtocolParser> { return std::make_unique<XsensMtParser>(); }},
};

constexpr std::array<std::string_view, kProtocols.size()> kNames = [] {
  std::array<std::string_view, kProtocols.size()> names{};
  for (std::size_t i = 0; i < kProtocols.size(); ++i) names[i] = kProtocols[i].name;
  return names;
}();

}  // namespace

std::span<const std::string_view> imu_protocol_names() noexcept {
  return kNames;
}

std::unique_ptr<ImuProtocolParser> make_imu_parser(std::string_view protocol) {
  for (const Entry& e : kProtocols) {
    if (e.name == protocol) return e.make();
  }
  std::string known;
  for (const Entry& e : kProtocols) known += (known.empty() ? "" : ", ") + std::string(e.name);
  throw std::invalid_argument("imu.protocol: unknown protocol '" + std::string(protocol) +
                              "' (known: " + known + ")");
}

}  // namespace vigs::drivers
