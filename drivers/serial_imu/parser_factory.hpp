// The protocol parsers by name (the config's `imu.protocol`). A new protocol adds its parser file
// and one row to the table in parser_factory.cpp.
#pragma once

#include <memory>
#include <span>
#include <string_view>

#include "drivers/serial_imu/imu_protocol_parser.hpp"

namespace vigs::drivers {

/// Names accepted by make_imu_parser().
[[nodiscard]] std::span<const std::string_view> imu_protocol_names() noexcept;

/// A new parser for `protocol`; throws std::invalid_argument naming the protocol and the known
/// ones.
[[nodiscard]] std::unique_ptr<ImuProtocolParser> make_imu_parser(std::string_view protocol);

}  // namespace vigs::drivers
