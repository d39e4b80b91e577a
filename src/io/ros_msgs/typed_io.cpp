#include "io/ros_msgs/typed_io.hpp"

namespace vigs::io::ros_msgs {

std::optional<Encoding> encoding_of(const mcap::MessageView& message) {
  if (message.channel == nullptr) return std::nullopt;
  if (message.channel->message_encoding == "cdr") return Encoding::kCdr;
  if (message.channel->message_encoding == "ros1") return Encoding::kRos1;
  return std::nullopt;
}

}  // namespace vigs::io::ros_msgs
