// The protocol parsers by name (the config's `imu.protocol`).
//
// Adding a protocol is one new file and nothing else: a file `drivers/serial_imu/<name>_parser.cpp`
// that defines `void register_<name>_parser(ImuParserRegistry&)`. CMake finds every
// `*_parser.cpp` and generates the call table (imu_protocols.inc), so the registration cannot be
// dropped by the linker and no list has to be edited by hand.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/serial_imu/imu_protocol_parser.hpp"

namespace vigs::drivers {

class ImuParserRegistry {
 public:
  using Factory = std::unique_ptr<ImuProtocolParser> (*)();
  /// Registers `name` (the value of `imu.protocol`); a duplicate name throws std::logic_error.
  void add(std::string_view name, Factory make);

 private:
  friend const ImuParserRegistry& imu_parser_registry();
  struct Entry {
    std::string name;
    Factory make;
  };
  std::vector<Entry> entries_;

 public:
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
};

/// Every protocol found at build time (built once, on first use; not for real-time threads).
[[nodiscard]] const ImuParserRegistry& imu_parser_registry();

/// Names accepted by make_imu_parser(), in registration order.
[[nodiscard]] std::vector<std::string> imu_protocol_names();

/// A new parser for `protocol`; throws std::invalid_argument naming the protocol and the known
/// ones.
[[nodiscard]] std::unique_ptr<ImuProtocolParser> make_imu_parser(std::string_view protocol);

}  // namespace vigs::drivers
