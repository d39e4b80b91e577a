// Damaged recordings: random corruption, truncation at many offsets, and a writer killed with
// SIGKILL. The reader must never crash, must report the damage with its offset, must return every
// message of the chunks before the damage, and must never return a message that was not written.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "mcap_test_util.hpp"

namespace vigs::io {
namespace {

using ros_msgs::Encoding;

struct Layout {
  std::vector<std::uint64_t> chunk_offsets;         // in file order
  std::vector<std::size_t> first_message_of_chunk;  // index into the written list
  std::uint64_t data_end = 0;
};

// Where the chunks of an intact file are (from the reader itself, verified clean).
Layout layout_of(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  Layout l;
  mcap::McapReader r(path);
  mcap::MessageView m;
  std::size_t i = 0;
  while (r.next(m)) {
    if (l.chunk_offsets.empty() || l.chunk_offsets.back() != m.record_offset) {
      l.chunk_offsets.push_back(m.record_offset);
      l.first_message_of_chunk.push_back(i);
    }
    ++i;
  }
  EXPECT_TRUE(r.issues().empty());
  std::uint64_t summary_start = 0;
  std::memcpy(&summary_start, bytes.data() + bytes.size() - 8 - 20, 8);
  l.data_end = summary_start - 13;
  return l;
}

// Number of leading written messages that lie in chunks wholly before `offset` (chunk and its
// message indexes end at the next chunk, or at Data End).
std::size_t messages_before(const Layout& l, std::size_t total, std::uint64_t offset) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < l.chunk_offsets.size(); ++k) {
    const std::uint64_t end = k + 1 < l.chunk_offsets.size() ? l.chunk_offsets[k + 1] : l.data_end;
    if (end > offset) break;
    n = k + 1 < l.first_message_of_chunk.size() ? l.first_message_of_chunk[k + 1] : total;
  }
  return n;
}

bool is_subsequence(const std::vector<test::Written>& got, const std::vector<test::Written>& all) {
  std::size_t j = 0;
  for (const auto& g : got) {
    while (j < all.size() && !(all[j] == g)) ++j;
    if (j == all.size()) return false;
    ++j;
  }
  return true;
}

class McapDamage : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = test::temp_path("pristine.mcap");
    mcap::McapWriterOptions options;
    options.chunk_size_bytes = 1500;  // many small chunks
    written_ = test::write_all_types(path_, Encoding::kCdr, 40, options);
    bytes_ = test::load(path_);
    layout_ = layout_of(path_, bytes_);
    ASSERT_GT(layout_.chunk_offsets.size(), 20u);
  }
  std::string path_;
  std::vector<test::Written> written_;
  std::vector<std::uint8_t> bytes_;
  Layout layout_;
};

TEST_F(McapDamage, RandomCorruptionIsReportedAndEverythingBeforeItIsRecovered) {
  const std::string bad = test::temp_path("corrupt.mcap");
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto rnd = [&] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (int trial = 0; trial < 400; ++trial) {
    auto damaged = bytes_;
    const std::uint64_t offset = rnd() % damaged.size();
    const int span = 1 + static_cast<int>(rnd() % 4);
    for (int k = 0; k < span && offset + k < damaged.size(); ++k) {
      damaged[offset + k] ^= static_cast<std::uint8_t>(1 + rnd() % 255);
    }
    test::save(bad, damaged);
    mcap::McapReader r(bad);
    const auto got = test::read_all(r);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", corrupted byte " + std::to_string(offset));
    EXPECT_FALSE(r.issues().empty());
    for (const auto& issue : r.issues()) {
      EXPECT_NE(issue.message.find("byte "), std::string::npos);
      EXPECT_LE(issue.offset, damaged.size());
    }
    EXPECT_TRUE(is_subsequence(got, written_));
    const std::size_t must = messages_before(layout_, written_.size(), offset);
    ASSERT_GE(got.size(), must);
    EXPECT_TRUE(
        std::equal(written_.begin(), written_.begin() + static_cast<long>(must), got.begin()));
  }
}

TEST_F(McapDamage, IntactSummaryLetsTheReaderSkipADamagedChunk) {
  auto damaged = bytes_;
  const std::size_t k = layout_.chunk_offsets.size() / 2;
  damaged[layout_.chunk_offsets[k] + 6] ^= 0x40;  // chunk length now runs past the end
  const std::string bad = test::temp_path("skip.mcap");
  test::save(bad, damaged);
  mcap::McapReader r(bad);
  const auto got = test::read_all(r);
  EXPECT_TRUE(r.has_summary());
  ASSERT_FALSE(r.issues().empty());
  EXPECT_EQ(r.issues().front().offset, layout_.chunk_offsets[k]);
  // Only chunk k is lost.
  const std::size_t lost =
      layout_.first_message_of_chunk[k + 1] - layout_.first_message_of_chunk[k];
  EXPECT_EQ(got.size(), written_.size() - lost);
  EXPECT_TRUE(is_subsequence(got, written_));
}

TEST_F(McapDamage, TruncationKeepsEveryCompleteChunk) {
  const std::string cut = test::temp_path("truncated.mcap");
  for (std::uint64_t size = 0; size < bytes_.size(); size += 97) {
    test::save(cut,
               std::vector<std::uint8_t>(bytes_.begin(), bytes_.begin() + static_cast<long>(size)));
    mcap::McapReader r(cut);
    const auto got = test::read_all(r);
    SCOPED_TRACE("cut at " + std::to_string(size));
    EXPECT_FALSE(r.issues().empty());
    ASSERT_LE(got.size(), written_.size());
    EXPECT_TRUE(std::equal(got.begin(), got.end(), written_.begin()));  // a prefix, no gaps
    EXPECT_GE(got.size(), messages_before(layout_, written_.size(), size));
  }
}

// Counts Chunk records that lie completely inside the file (a linear walk of the framing).
std::size_t complete_chunks(const std::vector<std::uint8_t>& b) {
  std::size_t n = 0;
  for (std::uint64_t p = 8; p + 9 <= b.size();) {
    std::uint64_t len = 0;
    std::memcpy(&len, b.data() + p + 1, 8);
    if (len > b.size() - p - 9) break;
    if (b[p] == 0x06) ++n;
    p += 9 + len;
  }
  return n;
}

TEST(McapCrash, SigkilledWriterLeavesAFileReadableUpToTheLastCompleteChunk) {
  const std::string path = test::temp_path("killed.mcap");
  std::filesystem::remove(path);
  constexpr std::size_t kChunk = 16 << 10;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    mcap::McapWriterOptions options;
    options.chunk_size_bytes = kChunk;
    mcap::McapWriter w(path, options);
    const auto ch = ros_msgs::add_channel<ros_msgs::Imu>(w, "/imu");
    std::vector<std::uint8_t> buf;
    for (std::int64_t i = 0;; ++i) {
      ros_msgs::Imu imu = test::sample_imu(0);
      imu.header.stamp = ros_msgs::Time::from_ns(i);
      ros_msgs::write_message(w, ch, static_cast<std::uint64_t>(i), imu, buf);
      if (w.stats().bytes_written > (64u << 20)) ::pause();  // never runs away with the disk
    }
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) > (1u << 20) && !ec) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_EQ(WTERMSIG(status), SIGKILL);

  const auto bytes = test::load(path);
  mcap::McapReader r(path);
  mcap::MessageView m;
  std::int64_t expected = 0;
  while (r.next(m)) {
    ros_msgs::Imu imu;
    ASSERT_TRUE(ros_msgs::decode_message(m, imu));
    ASSERT_EQ(imu.header.stamp.to_ns(), expected);  // consecutive from 0: no gaps
    ASSERT_EQ(m.log_time_ns, static_cast<std::uint64_t>(expected));
    ++expected;
  }
  ASSERT_FALSE(r.issues().empty());
  EXPECT_EQ(r.issues().back().kind, mcap::ReadIssue::Kind::kTruncated);
  // Every complete chunk in the file was read: each holds ceil(kChunk / record) messages.
  std::vector<std::uint8_t> payload;
  ros_msgs::encode(test::sample_imu(0), ros_msgs::Encoding::kCdr, payload);
  const std::size_t record = 9 + 22 + payload.size();
  const std::size_t per_chunk = (kChunk + record - 1) / record;
  const std::size_t chunks = complete_chunks(bytes);
  EXPECT_GE(chunks, 10u);
  EXPECT_EQ(static_cast<std::size_t>(expected), chunks * per_chunk);
}

}  // namespace
}  // namespace vigs::io
