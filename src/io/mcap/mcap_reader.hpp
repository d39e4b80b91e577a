#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "io/mcap/mcap_types.hpp"

namespace vigs::io::mcap {

/// A problem found while reading. Reading goes on past problems where it safely can.
struct ReadIssue {
  enum class Kind : std::uint8_t {
    kTruncated,    ///< the file ends inside a record, or before Data End / Footer
    kCorrupt,      ///< malformed record, bad magic, bad length, undecodable field
    kCrcMismatch,  ///< a chunk, data-section or summary CRC does not match
    kUnsupported,  ///< e.g. lz4 chunk compression; the chunk is skipped
  };
  Kind kind = Kind::kCorrupt;
  std::uint64_t offset = 0;  ///< byte offset in the file where the problem was found
  std::string message;       ///< names the file, record and offset
};

const char* to_string(ReadIssue::Kind kind);

struct McapReaderOptions {
  /// Only messages on these topics are returned (empty = all). With an intact summary, chunks
  /// holding none of these topics are skipped without decompression.
  std::set<std::string> topics;
  /// Check chunk CRCs (uncompressed_crc) and the data-section CRC in Data End.
  bool verify_crcs = true;
};

/// Reads an MCAP file (memory-mapped) message by message in file order.
///
/// Robustness contract: any byte sequence may be given. open() fails only if the file cannot
/// be opened or mapped. Damage never crashes the reader: it is recorded in issues() with its
/// byte offset, and every message in a complete, CRC-valid chunk (or unchunked Message record)
/// before the damage is returned. A missing or damaged summary (truncated recording, bad summary
/// CRC) makes the reader fall back to a linear scan of the data section; an intact summary lets
/// the reader resume at the next indexed chunk after damage in the data section.
///
/// Accepts any message encoding; ros_msgs/ decodes "cdr" and "ros1".
class McapReader {
 public:
  /// Opens and maps `path`, reads the footer and summary (if intact). Throws IoError only when
  /// the file cannot be opened or mapped; format problems go to issues().
  explicit McapReader(const std::string& path, McapReaderOptions options = {});
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  /// Next message in file order, or false at the end (or when nothing more is recoverable).
  bool next(MessageView& out);

  /// Rewinds to the first message.
  void rewind();

  /// True if the file has a valid footer and a summary whose CRC checks.
  bool has_summary() const;
  /// Statistics from the summary, if present and intact.
  const std::optional<Statistics>& statistics() const;
  /// Every schema and channel known so far (from the summary, else as found while reading).
  std::vector<const Schema*> schemas() const;
  std::vector<const Channel*> channels() const;
  const Channel* find_channel(const std::string& topic) const;

  /// Problems found so far. After next() returned false the list is complete: an empty list
  /// then means the whole file checked out (magic, framing, all CRCs, footer).
  const std::vector<ReadIssue>& issues() const;
  /// Header profile and library strings ("" if the Header record is missing or damaged).
  const std::string& profile() const;
  const std::string& library() const;
  const std::string& path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vigs::io::mcap
