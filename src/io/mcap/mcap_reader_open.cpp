#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

#include "io/io_error.hpp"
#include "io/mcap/reader_impl.hpp"

namespace vigs::io::mcap {

using detail::kFooterRecord;
using detail::kRecordHeader;

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

void McapReader::Impl::open_summary() {
  if (size < 8 || std::memcmp(base, kMagic, 8) != 0) {
    issue(ReadIssue::Kind::kCorrupt, 0, "bad leading magic (not an MCAP file or damaged start)");
  }
  // The Header's profile and library are known before the first next() (the scan re-reads them).
  std::uint64_t header_len = 0;
  if (size >= 8 + kRecordHeader && base[8] == static_cast<std::uint8_t>(Opcode::kHeader)) {
    std::memcpy(&header_len, base + 9, 8);
    if (header_len <= size - 8 - kRecordHeader &&
        !detail::parse_header(file.subspan(8 + kRecordHeader, header_len), profile, library)) {
      profile.clear();
      library.clear();
    }
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
    // Mapped without access first, then unlocked, then made readable: in a process that has
    // locked its memory (mlockall MCL_FUTURE, rt.lock_memory) a readable mapping would be read
    // in whole and pinned at once (a 3-minute 720x480 recording is 4 GB). The recording is
    // read by a source thread, never on a real-time path, so its pages fault in as they are
    // read and leave again (release_pages_before). Outside a locked process munlock does
    // nothing.
    void* p = ::mmap(nullptr, m.size, PROT_NONE, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED || ::munlock(p, m.size) != 0 || ::mprotect(p, m.size, PROT_READ) != 0) {
      const int err = errno;
      if (p != MAP_FAILED) ::munmap(p, m.size);
      ::close(fd);
      throw IoError("MCAP reader: cannot map " + path + ": " + std::strerror(err));
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

bool McapReader::has_summary() const {
  return impl_->summary_ok;
}
const std::optional<Statistics>& McapReader::statistics() const {
  return impl_->statistics;
}
std::vector<const Schema*> McapReader::schemas() const {
  std::vector<const Schema*> out;
  for (const auto& [id, s] : impl_->schemas) out.push_back(s.get());
  return out;
}
std::vector<const Channel*> McapReader::channels() const {
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
