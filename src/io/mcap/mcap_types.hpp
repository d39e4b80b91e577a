#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace vigs::io::mcap {

/// Record opcodes of the MCAP format, major version 0 (https://mcap.dev/spec).
enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// The 8 magic bytes at the start and end of every MCAP file.
inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

/// Well-known encodings used by this project.
inline constexpr const char* kSchemaEncodingRos2Msg = "ros2msg";
inline constexpr const char* kSchemaEncodingRos1Msg = "ros1msg";
inline constexpr const char* kMessageEncodingCdr = "cdr";
inline constexpr const char* kMessageEncodingRos1 = "ros1";

/// A Schema record: how the messages of one or more channels are laid out.
struct Schema {
  std::uint16_t id = 0;            ///< never 0 for a real schema
  std::string name;                ///< e.g. "sensor_msgs/msg/Image"
  std::string encoding;            ///< e.g. "ros2msg"
  std::vector<std::uint8_t> data;  ///< schema text (for ros2msg / ros1msg)
  std::string text() const { return std::string(data.begin(), data.end()); }
};

/// A Channel record: one topic with its message encoding.
struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;   ///< 0 = no schema
  std::string topic;             ///< e.g. "/tesse/imu/clean/imu"
  std::string message_encoding;  ///< e.g. "cdr" or "ros1"
  std::map<std::string, std::string> metadata;
};

/// The Statistics record of a file's summary.
struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_time_ns = 0;  ///< earliest log time
  std::uint64_t message_end_time_ns = 0;    ///< latest log time
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

/// One message as handed out by McapReader. `data` points into the reader's buffers and stays
/// valid only until the next call to McapReader::next().
struct MessageView {
  const Channel* channel = nullptr;  ///< never null
  const Schema* schema = nullptr;    ///< null when the channel has no schema
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::span<const std::uint8_t> data;
  std::uint64_t record_offset = 0;  ///< file offset of the message's chunk (or record)
};

}  // namespace vigs::io::mcap
