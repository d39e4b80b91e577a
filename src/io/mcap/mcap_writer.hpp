#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "io/mcap/mcap_types.hpp"

namespace vigs::io::mcap {

/// Chunk compression. zstd is the project default (libzstd).
enum class Compression : std::uint8_t { kNone = 0, kZstd = 1 };

struct McapWriterOptions {
  /// A chunk is compressed and written once its uncompressed records reach this size, bytes.
  std::size_t chunk_size_bytes = 4u << 20;
  /// A chunk is also written once its messages span this much log time, ns (0 = no limit). This
  /// bounds what a crash can lose on slow streams (an IMU alone fills 4 MiB in about a minute).
  std::uint64_t chunk_max_span_ns = 1'000'000'000;
  Compression compression = Compression::kZstd;
  int zstd_level = 3;  ///< 1 (fast) .. 19 (small)
  /// Header profile ("ros2" for CDR/ros2msg files, "ros1" for ros1 files, "" for none).
  std::string profile = "ros2";
  std::string library = "vigs";
  /// fsync(2) after every chunk: survives power loss, not only a killed process. Slower.
  bool fsync_each_chunk = false;
};

/// What the writer has written so far.
struct McapWriterStats {
  std::uint64_t message_count = 0;
  std::uint64_t chunk_count = 0;
  std::uint64_t bytes_uncompressed = 0;  ///< chunk records before compression
  std::uint64_t bytes_written = 0;       ///< file size so far
};

/// Writes an indexed, zstd-chunked MCAP file (https://mcap.dev/spec): Header, Schema and
/// Channel records in the data section, Chunks each followed by their Message Index records,
/// Data End with the data-section CRC, then a summary (Schemas, Channels, Chunk Indexes,
/// Statistics), Summary Offsets and the Footer with the summary CRC.
///
/// Crash safety: Schema/Channel records are written to the file as soon as they are added and
/// every chunk as soon as it is full, so a process killed at any point (SIGKILL) leaves a file
/// that McapReader (and other MCAP readers' linear scans) read up to the last complete chunk.
/// The file is written in place at `path` (not temp-then-rename) precisely for that reason.
///
/// Not thread-safe: one thread writes. Errors (disk full, bad ids) throw IoError naming the file.
class McapWriter {
 public:
  /// Creates (truncates) `path` and writes the magic and Header. Throws IoError.
  explicit McapWriter(const std::string& path, McapWriterOptions options = {});
  /// Closes the file (as close()) if still open; errors are swallowed here, so call close().
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Adds a schema, returns its id (1, 2, ...). Identical (name, encoding, data) returns the
  /// existing id. `data` is the schema text for ros2msg / ros1msg.
  std::uint16_t add_schema(std::string_view name, std::string_view encoding,
                           std::span<const std::uint8_t> data);
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view text);

  /// Adds a channel on `topic` with `schema_id` (0 = none) and `message_encoding` ("cdr",
  /// "ros1", ...), returns its id (1, 2, ...). Throws IoError on an unknown schema id.
  std::uint16_t add_channel(std::string_view topic, std::uint16_t schema_id,
                            std::string_view message_encoding,
                            const std::map<std::string, std::string>& metadata = {});

  /// Appends one message (`data` is the already-encoded payload, e.g. from ros_msgs encode_cdr).
  /// The sequence number is the channel's running count. Throws IoError on an unknown channel.
  void write(std::uint16_t channel_id, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
             std::span<const std::uint8_t> data);

  /// Writes the current partial chunk now (e.g. before a long pause), so that it survives a
  /// crash. Messages written later go into a new chunk.
  void flush();

  /// Writes the last chunk, Data End, summary and Footer, and closes the file. Idempotent.
  void close();

  bool is_open() const;
  const std::string& path() const;
  const McapWriterStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vigs::io::mcap
