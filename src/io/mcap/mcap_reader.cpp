#include "io/mcap/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>

#include "io/io_error.hpp"
#include "io/mcap/crc32.hpp"
#include "io/mcap/record_parse.hpp"

namespace vigs::io::mcap {
namespace {

constexpr std::uint64_t kRecordHeader = 9;  // opcode + uint64 length
constexpr std::uint64_t kFooterRecord = kRecordHeader + 20;
constexpr std::uint64_t kMaxUnknownSizeChunk = 1ull << 30;

std::string hex(unsigned v) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%02x", v);
  return buf;
}

}  // namespace

const char* to_string(ReadIssue::Kind kind) {
  switch (kind) {
    case ReadIssue::Kind::kTruncated:
      return "truncated";
    case ReadIssue::Kind::kCorrupt:
      return "corrupt";
    case ReadIssue::Kind::kCrcMismatch:
      return "crc mismatch";
    case ReadIssue::Kind::kUnsupported:
      return "unsupported";
  }
  return "?";
}

struct McapReader::Impl {
  std::string path;
  McapReaderOptions options;
  const std::uint8_t* base = nullptr;
  std::uint64_t size = 0;
  std::span<const std::uint8_t> file;

  std::string profile, library;
  std::map<std::uint16_t, std::unique_ptr<Schema>> schemas;
  std::map<std::uint16_t, std::unique_ptr<Channel>> channels;
  std::optional<Statistics> statistics;
  bool summary_ok = false;
  std::vector<detail::ChunkIndexRecord> chunk_indexes;  // sorted by chunk offset
  std::vector<ReadIssue> issues;
  std::size_t open_issue_count = 0;

  // Iteration state.
  std::uint64_t pos = 8;
  bool done = false;
  std::uint32_t data_crc = 0;
  std::uint64_t crc_pos = 0;  // bytes [0, crc_pos) are in data_crc
  bool crc_valid = true;
  std::vector<std::uint8_t> chunk_buf;
  std::span<const std::uint8_t> chunk_records;
  std::uint64_t chunk_pos = 0, chunk_offset = 0;
  bool in_chunk = false;
  ZSTD_DCtx* zstd = nullptr;

  void issue(ReadIssue::Kind kind, std::uint64_t offset, const std::string& what) {
    issues.push_back({kind, offset, path + ": byte " + std::to_string(offset) + ": " + what});
  }

  void open_summary();
  void add_schema(const Schema& s) {
    if (s.id != 0 && !schemas.contains(s.id)) schemas[s.id] = std::make_unique<Schema>(s);
  }
  void add_channel(const Channel& c) {
    if (!channels.contains(c.id)) channels[c.id] = std::make_unique<Channel>(c);
  }
  bool wanted(std::uint16_t channel_id) const {
    if (options.topics.empty()) return true;
    auto it = channels.find(channel_id);
    return it != channels.end() && options.topics.contains(it->second->topic);
  }
  void crc_to(std::uint64_t end) {
    if (crc_valid && options.verify_crcs && end > crc_pos) {
      data_crc = crc32_update(data_crc, file.subspan(crc_pos, end - crc_pos));
    }
    crc_pos = std::max(crc_pos, end);
  }
  bool resync(std::uint64_t damaged_at);
  bool is_indexed_chunk(std::uint64_t offset) const {
    auto it = std::lower_bound(chunk_indexes.begin(), chunk_indexes.end(), offset,
                               [](const auto& ci, std::uint64_t o) { return ci.chunk_offset < o; });
    return it != chunk_indexes.end() && it->chunk_offset == offset;
  }
  bool fill(const detail::MessageRecord& m, std::uint64_t offset, MessageView& out);
  bool next_in_chunk(MessageView& out);
  bool open_chunk(std::uint64_t offset, std::span<const std::uint8_t> body);
  // Returns true when `out` holds a message.
  bool step(MessageView& out);
};

void McapReader::Impl::open_summary() {
  if (size < 8 || std::memcmp(base, kMagic, 8) != 0) {
    issue(ReadIssue::Kind::kCorrupt, 0, "bad leading magic (not an MCAP file or damaged start)");
  }
  if (size < 8 + kFooterRecord + 8 || std::memcmp(base + size - 8, kMagic, 8) != 0) {
    issue(ReadIssue::Kind::kTruncated, size,
          "no trailing magic / footer (file cut off?); reading the data section linearly");
    return;
  }
  const std::uint64_t footer_at = size - 8 - kFooterRecord;
  detail::FooterRecord footer;
  std::uint64_t len = 0;
  std::memcpy(&len, base + footer_at + 1, 8);
  if (base[footer_at] != static_cast<std::uint8_t>(Opcode::kFooter) || len != 20 ||
      !detail::parse_footer(file.subspan(footer_at + kRecordHeader, 20), footer)) {
    issue(ReadIssue::Kind::kCorrupt, footer_at, "malformed footer record");
    return;
  }
  if (footer.summary_start == 0) {  // valid file without a summary; the CRC covers the footer
    if (options.verify_crcs && footer.summary_crc != 0 &&
        crc32(file.subspan(footer_at, kRecordHeader + 16)) != footer.summary_crc) {
      issue(ReadIssue::Kind::kCrcMismatch, footer_at, "footer CRC mismatch");
    }
    return;
  }
  if (footer.summary_start < 8 || footer.summary_start > footer_at ||
      (footer.summary_offset_start != 0 && (footer.summary_offset_start < footer.summary_start ||
                                            footer.summary_offset_start > footer_at))) {
    issue(ReadIssue::Kind::kCorrupt, footer_at, "footer points outside the file");
    return;
  }
  if (options.verify_crcs && footer.summary_crc != 0) {
    const std::uint64_t end = footer_at + kRecordHeader + 16;
    const std::uint32_t crc = crc32(file.subspan(footer.summary_start, end - footer.summary_start));
    if (crc != footer.summary_crc) {
      issue(ReadIssue::Kind::kCrcMismatch, footer.summary_start,
            "summary CRC mismatch; ignoring the summary and reading linearly");
      return;
    }
  }
  const std::uint64_t end =
      footer.summary_offset_start != 0 ? footer.summary_offset_start : footer_at;
  std::vector<Schema> new_schemas;
  std::vector<Channel> new_channels;
  std::vector<detail::ChunkIndexRecord> indexes;
  std::optional<Statistics> stats;
  for (std::uint64_t p = footer.summary_start; p < end;) {
    std::uint64_t n = 0;
    if (end - p < kRecordHeader) break;
    std::memcpy(&n, base + p + 1, 8);
    if (n > end - p - kRecordHeader) {
      issue(ReadIssue::Kind::kCorrupt, p, "summary record overruns the summary; ignoring it");
      return;
    }
    const auto body = file.subspan(p + kRecordHeader, n);
    bool ok = true;
    switch (static_cast<Opcode>(base[p])) {
      case Opcode::kSchema:
        ok = detail::parse_schema(body, new_schemas.emplace_back());
        break;
      case Opcode::kChannel:
        ok = detail::parse_channel(body, new_channels.emplace_back());
        break;
      case Opcode::kChunkIndex: {
        ok = detail::parse_chunk_index(body, indexes.emplace_back());
        ok = ok && indexes.back().chunk_offset >= 8 && indexes.back().chunk_offset < size;
        break;
      }
      case Opcode::kStatistics:
        ok = detail::parse_statistics(body, stats.emplace());
        break;
      default:
        break;
    }
    if (!ok) {
      issue(ReadIssue::Kind::kCorrupt, p, "malformed summary record; ignoring the summary");
      return;
    }
    p += kRecordHeader + n;
  }
  for (const Schema& s : new_schemas) add_schema(s);
  for (const Channel& c : new_channels) add_channel(c);
  std::sort(indexes.begin(), indexes.end(),
            [](const auto& a, const auto& b) { return a.chunk_offset < b.chunk_offset; });
  chunk_indexes = std::move(indexes);
  statistics = std::move(stats);
  summary_ok = true;
}

bool McapReader::Impl::resync(std::uint64_t damaged_at) {
  crc_valid = false;
  if (summary_ok) {
    for (const auto& ci : chunk_indexes) {
      if (ci.chunk_offset > damaged_at) {
        issue(ReadIssue::Kind::kCorrupt, damaged_at,
              "resuming at the next indexed chunk, byte " + std::to_string(ci.chunk_offset));
        pos = ci.chunk_offset;
        return true;
      }
    }
  }
  done = true;
  return false;
}

bool McapReader::Impl::fill(const detail::MessageRecord& m, std::uint64_t offset,
                            MessageView& out) {
  auto it = channels.find(m.channel_id);
  if (it == channels.end()) {
    issue(ReadIssue::Kind::kCorrupt, offset,
          "message on unknown channel " + std::to_string(m.channel_id));
    return false;
  }
  if (!wanted(m.channel_id)) return false;
  out.channel = it->second.get();
  auto s = schemas.find(it->second->schema_id);
  out.schema = s == schemas.end() ? nullptr : s->second.get();
  out.sequence = m.sequence;
  out.log_time_ns = m.log_time;
  out.publish_time_ns = m.publish_time;
  out.data = m.data;
  out.record_offset = offset;
  return true;
}

bool McapReader::Impl::next_in_chunk(MessageView& out) {
  while (chunk_pos < chunk_records.size()) {
    const std::uint64_t left = chunk_records.size() - chunk_pos;
    std::uint64_t n = 0;
    if (left < kRecordHeader) break;
    std::memcpy(&n, chunk_records.data() + chunk_pos + 1, 8);
    if (n > left - kRecordHeader) break;
    const std::uint8_t op = chunk_records[chunk_pos];
    const auto body = chunk_records.subspan(chunk_pos + kRecordHeader, n);
    chunk_pos += kRecordHeader + n;
    bool ok = true;
    if (op == static_cast<std::uint8_t>(Opcode::kSchema)) {
      Schema s;
      ok = detail::parse_schema(body, s);
      if (ok) add_schema(s);
    } else if (op == static_cast<std::uint8_t>(Opcode::kChannel)) {
      Channel c;
      ok = detail::parse_channel(body, c);
      if (ok) add_channel(c);
    } else if (op == static_cast<std::uint8_t>(Opcode::kMessage)) {
      detail::MessageRecord m;
      ok = detail::parse_message(body, m);
      if (ok && fill(m, chunk_offset, out)) return true;
    }
    if (!ok) break;
  }
  if (chunk_pos < chunk_records.size()) {
    issue(ReadIssue::Kind::kCorrupt, chunk_offset,
          "malformed record inside chunk at chunk byte " + std::to_string(chunk_pos));
  }
  in_chunk = false;
  return false;
}

bool McapReader::Impl::open_chunk(std::uint64_t offset, std::span<const std::uint8_t> body) {
  detail::ChunkRecord c;
  if (!detail::parse_chunk(body, c)) {
    issue(ReadIssue::Kind::kCorrupt, offset, "malformed chunk record; chunk skipped");
    return false;
  }
  if (!options.topics.empty() && summary_ok) {
    auto it = std::lower_bound(chunk_indexes.begin(), chunk_indexes.end(), offset,
                               [](const auto& ci, std::uint64_t o) { return ci.chunk_offset < o; });
    if (it != chunk_indexes.end() && it->chunk_offset == offset &&
        std::none_of(it->message_index_offsets.begin(), it->message_index_offsets.end(),
                     [&](const auto& kv) { return wanted(kv.first); })) {
      return false;  // no wanted topic in this chunk
    }
  }
  if (c.compression.empty()) {
    chunk_records = c.records;
  } else if (c.compression == "zstd") {
    const unsigned long long frame = ZSTD_getFrameContentSize(c.records.data(), c.records.size());
    const bool known = frame != ZSTD_CONTENTSIZE_UNKNOWN && frame != ZSTD_CONTENTSIZE_ERROR;
    if ((known && frame != c.uncompressed_size) ||
        (!known && c.uncompressed_size > kMaxUnknownSizeChunk)) {
      issue(ReadIssue::Kind::kCorrupt, offset, "chunk size fields disagree; chunk skipped");
      return false;
    }
    if (zstd == nullptr) zstd = ZSTD_createDCtx();
    chunk_buf.resize(static_cast<std::size_t>(c.uncompressed_size));
    const std::size_t n = ZSTD_decompressDCtx(zstd, chunk_buf.data(), chunk_buf.size(),
                                              c.records.data(), c.records.size());
    if (ZSTD_isError(n) || n != c.uncompressed_size) {
      issue(ReadIssue::Kind::kCorrupt, offset,
            std::string("zstd chunk does not decompress (") +
                (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "size differs") + "); chunk skipped");
      return false;
    }
    chunk_records = chunk_buf;
  } else {
    issue(ReadIssue::Kind::kUnsupported, offset,
          "chunk compression '" + c.compression + "' not supported; chunk skipped");
    return false;
  }
  if (chunk_records.size() != c.uncompressed_size) {
    issue(ReadIssue::Kind::kCorrupt, offset, "chunk uncompressed_size mismatch; chunk skipped");
    return false;
  }
  if (options.verify_crcs && c.uncompressed_crc != 0 &&
      crc32(chunk_records) != c.uncompressed_crc) {
    issue(ReadIssue::Kind::kCrcMismatch, offset, "chunk CRC mismatch; chunk skipped");
    return false;
  }
  chunk_pos = 0;
  chunk_offset = offset;
  in_chunk = true;
  return true;
}

bool McapReader::Impl::step(MessageView& out) {
  if (pos >= size || size - pos < kRecordHeader) {
    issue(ReadIssue::Kind::kTruncated, pos, "file ends before the Data End record");
    done = true;
    return false;
  }
  const std::uint8_t op = base[pos];
  std::uint64_t n = 0;
  std::memcpy(&n, base + pos + 1, 8);
  if (n > size - pos - kRecordHeader) {
    issue(ReadIssue::Kind::kTruncated, pos,
          "record (opcode " + hex(op) + ") of " + std::to_string(n) + " bytes runs past the end (" +
              std::to_string(size) + " bytes); everything before it was read");
    resync(pos);
    return false;
  }
  if (op == 0 || (op > static_cast<std::uint8_t>(Opcode::kDataEnd) && op < 0x80)) {
    issue(ReadIssue::Kind::kCorrupt, pos, "invalid record opcode " + hex(op));
    resync(pos);
    return false;
  }
  const std::uint64_t at = pos;
  const auto body = file.subspan(pos + kRecordHeader, n);
  if (summary_ok && op != static_cast<std::uint8_t>(Opcode::kChunk) && is_indexed_chunk(at)) {
    issue(ReadIssue::Kind::kCorrupt, at, "the index has a chunk here but the record is " + hex(op));
    crc_valid = false;
    pos = at + kRecordHeader + n;
    return false;
  }
  if (op == static_cast<std::uint8_t>(Opcode::kDataEnd)) {
    crc_to(at);
    std::uint32_t expected = 0;
    if (n >= 4) std::memcpy(&expected, body.data(), 4);
    if (options.verify_crcs && crc_valid && expected != 0 && expected != data_crc) {
      issue(ReadIssue::Kind::kCrcMismatch, at, "data section CRC mismatch");
    }
    done = true;
    return false;
  }
  crc_to(at + kRecordHeader + n);
  pos = at + kRecordHeader + n;
  bool ok = true;
  switch (static_cast<Opcode>(op)) {
    case Opcode::kHeader:
      ok = at == 8 && detail::parse_header(body, profile, library);
      break;
    case Opcode::kFooter:
      issue(ReadIssue::Kind::kCorrupt, at, "footer before Data End");
      done = true;
      return false;
    case Opcode::kSchema: {
      Schema s;
      ok = detail::parse_schema(body, s);
      if (ok) add_schema(s);
      break;
    }
    case Opcode::kChannel: {
      Channel c;
      ok = detail::parse_channel(body, c);
      if (ok) add_channel(c);
      break;
    }
    case Opcode::kMessage: {
      detail::MessageRecord m;
      ok = detail::parse_message(body, m);
      if (ok) return fill(m, at, out);
      break;
    }
    case Opcode::kChunk:
      open_chunk(at, body);
      return false;
    default:
      break;  // indexes, attachments, metadata: not needed for reading messages
  }
  if (!ok) issue(ReadIssue::Kind::kCorrupt, at, "malformed record (opcode " + hex(op) + ")");
  return false;
}

McapReader::McapReader(const std::string& path, McapReaderOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.options = std::move(options);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError("MCAP reader: cannot open " + path + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    throw IoError("MCAP reader: cannot stat " + path);
  }
  m.size = static_cast<std::uint64_t>(st.st_size);
  if (m.size > 0) {
    void* p = ::mmap(nullptr, m.size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      throw IoError("MCAP reader: cannot map " + path + ": " + std::strerror(errno));
    }
    m.base = static_cast<const std::uint8_t*>(p);
  }
  ::close(fd);
  m.file = std::span<const std::uint8_t>(m.base, m.size);
  m.open_summary();
  m.open_issue_count = m.issues.size();
  rewind();
}

McapReader::~McapReader() {
  if (impl_->base != nullptr) ::munmap(const_cast<std::uint8_t*>(impl_->base), impl_->size);
  if (impl_->zstd != nullptr) ZSTD_freeDCtx(impl_->zstd);
}

void McapReader::rewind() {
  Impl& m = *impl_;
  m.issues.resize(m.open_issue_count);
  m.pos = 8;
  m.done = m.size < 8;
  m.data_crc = 0;
  m.crc_pos = 0;
  m.crc_valid = true;
  m.in_chunk = false;
}

bool McapReader::next(MessageView& out) {
  Impl& m = *impl_;
  for (;;) {
    if (m.in_chunk) {
      if (m.next_in_chunk(out)) return true;
      continue;
    }
    if (m.done) return false;
    if (m.step(out)) return true;
  }
}

bool McapReader::has_summary() const {
  return impl_->summary_ok;
}
const std::optional<Statistics>& McapReader::statistics() const {
  return impl_->statistics;
}
const std::vector<const Schema*> McapReader::schemas() const {
  std::vector<const Schema*> out;
  for (const auto& [id, s] : impl_->schemas) out.push_back(s.get());
  return out;
}
const std::vector<const Channel*> McapReader::channels() const {
  std::vector<const Channel*> out;
  for (const auto& [id, c] : impl_->channels) out.push_back(c.get());
  return out;
}
const Channel* McapReader::find_channel(const std::string& topic) const {
  for (const auto& [id, c] : impl_->channels) {
    if (c->topic == topic) return c.get();
  }
  return nullptr;
}
const std::vector<ReadIssue>& McapReader::issues() const {
  return impl_->issues;
}
const std::string& McapReader::profile() const {
  return impl_->profile;
}
const std::string& McapReader::library() const {
  return impl_->library;
}
const std::string& McapReader::path() const {
  return impl_->path;
}

}  // namespace vigs::io::mcap
