#pragma once
// sensor_msgs/Image read without copying its pixels: ImageMeta stops before `data` (stamps,
// sizes and encodings of a recording without touching a pixel byte), ImageView views `data` in
// the message bytes. Both decode messages whose schema names Image (decode_message).
#include <cstdint>
#include <span>
#include <string>

#include "io/ros_msgs/image.hpp"

namespace vigs::io::ros_msgs {

/// An Image's fields before `data` (see Image for their meaning).
struct ImageMeta {
  Header header;
  std::uint32_t height = 0;  ///< rows, px
  std::uint32_t width = 0;   ///< columns, px
  std::string encoding;
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;  ///< row length, bytes
};

/// An Image whose `data` views the decoded message bytes: valid while they are (for an MCAP
/// message, until the reader's next next()).
struct ImageView : ImageMeta {
  std::span<const std::uint8_t> data;
};

template <>
struct MessageTraits<ImageMeta> : MessageTraits<Image> {};
template <>
struct MessageTraits<ImageView> : MessageTraits<Image> {};

/// Decodes the fields before `data` only: the pixel bytes are neither read nor checked (a
/// message whose pixel payload is cut short decodes). Throws DecodeError on bad header bytes.
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, ImageMeta& out);
/// Decodes the whole message as decode(..., Image&) does, with `data` viewed in place.
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, ImageView& out);

}  // namespace vigs::io::ros_msgs
