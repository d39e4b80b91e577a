#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "io/mcap/mcap_types.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// Adds Msg's schema (ros2msg or ros1msg text) and a channel on `topic` with the matching
/// message encoding ("cdr" or "ros1"). Returns the channel id for McapWriter::write.
template <class Msg>
std::uint16_t add_channel(mcap::McapWriter& writer, std::string_view topic,
                          Encoding encoding = Encoding::kCdr) {
  const std::uint16_t schema_id = writer.add_schema(
      type_name<Msg>(encoding), schema_encoding_name(encoding), schema_text<Msg>(encoding));
  return writer.add_channel(topic, schema_id, message_encoding_name(encoding));
}

/// Encodes `msg` into `scratch` (reused between calls) and writes it on `channel_id`.
/// publish time = log time.
template <class Msg>
void write_message(mcap::McapWriter& writer, std::uint16_t channel_id, std::uint64_t log_time_ns,
                   const Msg& msg, std::vector<std::uint8_t>& scratch,
                   Encoding encoding = Encoding::kCdr) {
  encode(msg, encoding, scratch);
  writer.write(channel_id, log_time_ns, log_time_ns, scratch);
}

/// The Encoding of a message read from MCAP ("cdr" or "ros1"), or nullopt for others.
std::optional<Encoding> encoding_of(const mcap::MessageView& message);

/// Decodes `message` into `out` if its schema names Msg (either ROS form) and its encoding is
/// cdr or ros1; returns false (out untouched) otherwise. Throws DecodeError on bad bytes.
template <class Msg>
bool decode_message(const mcap::MessageView& message, Msg& out) {
  if (message.schema == nullptr || !is_type<Msg>(message.schema->name)) return false;
  const std::optional<Encoding> encoding = encoding_of(message);
  if (!encoding) return false;
  decode(message.data, *encoding, out);
  return true;
}

}  // namespace vigs::io::ros_msgs
