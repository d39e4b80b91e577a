// MCAP writer/reader: round trip of every message type (CDR and ros1, zstd and uncompressed),
// file structure (summary, statistics, CRCs), topic filtering.
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "io/byte_buffer.hpp"
#include "io/io_error.hpp"
#include "io/mcap/crc32.hpp"
#include "mcap_test_util.hpp"

namespace vigs::io {
namespace {

using ros_msgs::Encoding;

TEST(Crc32, MatchesZlibCheckValue) {
  const char* s = "123456789";
  const auto bytes = std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s), 9);
  EXPECT_EQ(mcap::crc32(bytes), 0xCBF43926u);
  EXPECT_EQ(mcap::crc32_update(mcap::crc32(bytes.first(4)), bytes.subspan(4)), 0xCBF43926u);
  std::vector<std::uint8_t> big(1000);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 31);
  std::uint32_t bytewise = 0;
  for (std::uint8_t b : big) bytewise = mcap::crc32_update(bytewise, std::span(&b, 1));
  EXPECT_EQ(mcap::crc32(big), bytewise);
}

struct Case {
  Encoding encoding;
  mcap::Compression compression;
  std::size_t chunk_size;
};

class McapRoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(McapRoundTrip, EveryMessageAndFieldComesBack) {
  const Case c = GetParam();
  const std::string path = test::temp_path("roundtrip.mcap");
  mcap::McapWriterOptions options;
  options.compression = c.compression;
  options.chunk_size_bytes = c.chunk_size;
  const auto written = test::write_all_types(path, c.encoding, 20, options);

  mcap::McapReader r(path);
  EXPECT_TRUE(r.has_summary());
  EXPECT_EQ(r.profile(), c.encoding == Encoding::kCdr ? "ros2" : "ros1");  // before next()
  mcap::MessageView m;
  std::size_t i = 0;
  while (r.next(m)) {
    ASSERT_LT(i, written.size());
    EXPECT_EQ(m.channel->topic, written[i].topic);
    EXPECT_EQ(m.log_time_ns, written[i].log_time_ns);
    EXPECT_EQ(m.publish_time_ns, written[i].log_time_ns);
    EXPECT_EQ(std::vector<std::uint8_t>(m.data.begin(), m.data.end()), written[i].data);
    ASSERT_NE(m.schema, nullptr);
    EXPECT_EQ(m.channel->message_encoding, c.encoding == Encoding::kCdr ? "cdr" : "ros1");
    EXPECT_EQ(m.schema->encoding, c.encoding == Encoding::kCdr ? "ros2msg" : "ros1msg");
    const int round = static_cast<int>(i / 6);
    EXPECT_EQ(m.sequence, static_cast<std::uint32_t>(round));
    // Typed decode gives back the sample (seq only survives in ROS 1).
    auto fix = [&](auto msg) {
      if constexpr (requires { msg.header.seq; }) {
        if (c.encoding == Encoding::kCdr) msg.header.seq = 0;
      }
      return msg;
    };
    switch (i % 6) {
      case 0:
      case 1: {
        ros_msgs::Image img;
        ASSERT_TRUE(ros_msgs::decode_message(m, img));
        EXPECT_EQ(img, fix(test::sample_image(round, i % 6 == 1)));
        break;
      }
      case 2: {
        ros_msgs::Imu imu;
        ASSERT_TRUE(ros_msgs::decode_message(m, imu));
        EXPECT_EQ(imu, fix(test::sample_imu(round)));
        ros_msgs::Image wrong;
        EXPECT_FALSE(ros_msgs::decode_message(m, wrong));
        break;
      }
      case 3: {
        ros_msgs::CameraInfo info;
        ASSERT_TRUE(ros_msgs::decode_message(m, info));
        EXPECT_EQ(info, fix(test::sample_camera_info(round)));
        break;
      }
      case 4: {
        ros_msgs::PoseStamped pose;
        ASSERT_TRUE(ros_msgs::decode_message(m, pose));
        EXPECT_EQ(pose, fix(test::sample_pose(round)));
        break;
      }
      case 5: {
        ros_msgs::SerialChunk s;
        ASSERT_TRUE(ros_msgs::decode_message(m, s));
        EXPECT_EQ(s, test::sample_serial(round));
        break;
      }
    }
    ++i;
  }
  EXPECT_EQ(i, written.size());
  EXPECT_TRUE(r.issues().empty()) << r.issues().front().message;
  EXPECT_EQ(r.profile(), c.encoding == Encoding::kCdr ? "ros2" : "ros1");
  EXPECT_EQ(r.library(), "vigs");
  ASSERT_TRUE(r.statistics().has_value());
  const mcap::Statistics& s = *r.statistics();
  EXPECT_EQ(s.message_count, written.size());
  EXPECT_EQ(s.channel_count, 6u);
  EXPECT_EQ(s.schema_count, 5u);  // two image channels share one schema
  EXPECT_EQ(s.message_start_time_ns, written.front().log_time_ns);
  EXPECT_EQ(s.message_end_time_ns, written.back().log_time_ns);
  EXPECT_EQ(s.channel_message_counts.size(), 6u);
  for (const auto& [id, n] : s.channel_message_counts) EXPECT_EQ(n, 20u);
  if (c.chunk_size < 4096) {
    EXPECT_GT(s.chunk_count, 5u);
  }

  // Rewind gives the same again.
  r.rewind();
  EXPECT_EQ(test::read_all(r), written);
}

// Readable parameter names and printouts (the default prints the struct's bytes, padding
// included, which differ between runs and end up in ctest's discovered test names).
std::string describe(const Case& c) {
  return std::string(c.encoding == Encoding::kCdr ? "cdr" : "ros1") +
         (c.compression == mcap::Compression::kZstd ? "_zstd_" : "_uncompressed_") + "chunk" +
         std::to_string(c.chunk_size);
}
void PrintTo(const Case& c, std::ostream* os) {
  *os << describe(c);
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return describe(info.param);
}

INSTANTIATE_TEST_SUITE_P(Formats, McapRoundTrip,
                         ::testing::Values(Case{Encoding::kCdr, mcap::Compression::kZstd, 4u << 20},
                                           Case{Encoding::kCdr, mcap::Compression::kZstd, 1000},
                                           Case{Encoding::kCdr, mcap::Compression::kNone, 1000},
                                           Case{Encoding::kRos1, mcap::Compression::kZstd, 1000},
                                           Case{Encoding::kRos1, mcap::Compression::kNone,
                                                4u << 20}),
                         case_name);

TEST(Mcap, FileStartsAndEndsWithMagicAndChecksSummaryCrc) {
  const std::string path = test::temp_path("magic.mcap");
  test::write_all_types(path, Encoding::kCdr, 3);
  auto bytes = test::load(path);
  ASSERT_GT(bytes.size(), 16u);
  EXPECT_EQ(std::memcmp(bytes.data(), mcap::kMagic, 8), 0);
  EXPECT_EQ(std::memcmp(bytes.data() + bytes.size() - 8, mcap::kMagic, 8), 0);
  // Footer: summary_start, summary_offset_start, summary_crc over [summary_start, crc field).
  const std::size_t footer = bytes.size() - 8 - 29;
  ASSERT_EQ(bytes[footer], 0x02);
  std::uint64_t summary_start = 0;
  std::uint32_t summary_crc = 0;
  std::memcpy(&summary_start, bytes.data() + footer + 9, 8);
  std::memcpy(&summary_crc, bytes.data() + footer + 25, 4);
  ASSERT_LT(summary_start, footer);
  EXPECT_EQ(mcap::crc32(std::span(bytes.data() + summary_start, footer + 25 - summary_start)),
            summary_crc);
  // Data End sits right before the summary and holds the CRC of everything before it.
  const std::size_t data_end = summary_start - 13;
  ASSERT_EQ(bytes[data_end], 0x0F);
  std::uint32_t data_crc = 0;
  std::memcpy(&data_crc, bytes.data() + data_end + 9, 4);
  EXPECT_EQ(mcap::crc32(std::span(bytes.data(), data_end)), data_crc);
}

TEST(Mcap, SameInputGivesByteIdenticalFiles) {  // replay and simulator determinism
  const std::string a = test::temp_path("det_a.mcap"), b = test::temp_path("det_b.mcap");
  mcap::McapWriterOptions options;
  options.chunk_size_bytes = 3000;
  test::write_all_types(a, Encoding::kCdr, 10, options);
  test::write_all_types(b, Encoding::kCdr, 10, options);
  EXPECT_EQ(test::load(a), test::load(b));
}

TEST(Mcap, TopicFilterSkipsOtherChannels) {
  const std::string path = test::temp_path("filter.mcap");
  mcap::McapWriterOptions options;
  options.chunk_size_bytes = 600;
  const auto written = test::write_all_types(path, Encoding::kCdr, 10, options);
  mcap::McapReaderOptions ro;
  ro.topics = {"/tesse/imu/clean/imu", "/vigs/ground_truth"};
  mcap::McapReader r(path, ro);
  const auto got = test::read_all(r);
  std::vector<test::Written> expected;
  for (const auto& w : written) {
    if (ro.topics.contains(w.topic)) expected.push_back(w);
  }
  EXPECT_EQ(got, expected);
  EXPECT_TRUE(r.issues().empty());
  ASSERT_NE(r.find_channel("/vigs/ground_truth"), nullptr);
  EXPECT_EQ(r.find_channel("/nope"), nullptr);
}

// Resident set size of this process, bytes (/proc/self/statm's second field, in pages).
std::uint64_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  unsigned long long size = 0, resident = 0;
  const int n = f != nullptr ? std::fscanf(f, "%llu %llu", &size, &resident) : 0;
  if (f != nullptr) std::fclose(f);
  return n == 2 ? resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE)) : 0;
}

TEST(Mcap, ReadingALongRecordingFrontToBackKeepsAWindowResidentNotTheFile) {
  // 256 MiB of uncompressed 1 MiB messages (a recording's images): the mapped file's pages the
  // reader is done with leave the resident set, so reading it costs a window (64 MiB steps).
  const std::string path = test::temp_path("long.mcap");
  constexpr int kMessages = 256;
  std::vector<std::uint8_t> payload(1u << 20);
  {
    mcap::McapWriterOptions options;
    options.compression = mcap::Compression::kNone;
    mcap::McapWriter w(path, options);
    const std::uint16_t ch = w.add_channel("/blob", 0, "cdr");
    for (int i = 0; i < kMessages; ++i) {
      std::memset(payload.data(), i, payload.size());
      w.write(ch, 1000ull * i, 1000ull * i, payload);
    }
    w.close();
  }
  const std::uint64_t before = resident_bytes();
  std::uint64_t peak = before;
  int read = 0, intact = 0;
  {
    mcap::McapReader r(path);
    mcap::MessageView m;
    while (r.next(m)) {
      intact += m.data.size() == payload.size() &&
                m.data.front() == static_cast<std::uint8_t>(read) &&
                m.data.back() == static_cast<std::uint8_t>(read);
      ++read;
      peak = std::max(peak, resident_bytes());
    }
    EXPECT_TRUE(r.issues().empty());
  }
  std::remove(path.c_str());
  EXPECT_EQ(read, kMessages);
  EXPECT_EQ(intact, kMessages);
  ASSERT_GT(before, 0u);
  EXPECT_LT(peak - before, 128ull << 20) << "the whole 256 MiB file stayed resident";
}

TEST(Mcap, ALockedProcessDoesNotPinTheWholeRecording) {
  // vigs run locks its memory (mlockall MCL_CURRENT | MCL_FUTURE) before its sources open the
  // recording: the mapping must not be read in whole and pinned. In a child process, since
  // the lock is for the whole process.
  const std::string path = test::temp_path("locked.mcap");
  constexpr int kMessages = 256;
  std::vector<std::uint8_t> payload(1u << 20, 7);
  {
    mcap::McapWriterOptions options;
    options.compression = mcap::Compression::kNone;
    mcap::McapWriter w(path, options);
    const std::uint16_t ch = w.add_channel("/blob", 0, "cdr");
    for (int i = 0; i < kMessages; ++i) w.write(ch, 1000ull * i, 1000ull * i, payload);
    w.close();
  }
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::mlockall(MCL_CURRENT | MCL_FUTURE) != 0) ::_exit(2);  // no permission: skipped
    const std::uint64_t before = resident_bytes();
    std::uint64_t peak = before;
    int read = 0;
    {
      mcap::McapReader r(path);
      peak = std::max(peak, resident_bytes());
      mcap::MessageView m;
      while (r.next(m)) {
        read += m.data.size() == payload.size() && m.data[12345] == 7;
        peak = std::max(peak, resident_bytes());
      }
    }
    ::_exit(read == kMessages && peak - before < (128ull << 20) ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  std::remove(path.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 2) GTEST_SKIP() << "mlockall refused (no CAP_IPC_LOCK)";
  EXPECT_EQ(WEXITSTATUS(status), 0)
      << "under mlockall the 256 MiB recording was pinned whole (or misread)";
}

TEST(Mcap, ChunksCloseAfterTheirTimeSpanSoSlowStreamsLoseLittleInACrash) {
  const std::string path = test::temp_path("span.mcap");
  mcap::McapWriterOptions options;
  options.chunk_max_span_ns = 500'000'000;  // 0.5 s; the 4 MiB size limit is never reached
  std::vector<std::uint8_t> buf;
  {
    mcap::McapWriter w(path, options);
    const auto ch = ros_msgs::add_channel<ros_msgs::Imu>(w, "/imu");
    for (int i = 0; i < 1000; ++i) {  // 5 s at 200 Hz
      ros_msgs::write_message(w, ch, 5'000'000ull * i, test::sample_imu(i), buf);
    }
    EXPECT_EQ(w.stats().chunk_count, 9u);  // each chunk holds 0.5 s (101 samples) before closing
    w.close();
  }
  mcap::McapReader r(path);
  EXPECT_EQ(test::read_all(r).size(), 1000u);
  ASSERT_TRUE(r.statistics().has_value());
  EXPECT_EQ(r.statistics()->chunk_count, 10u);
  EXPECT_TRUE(r.issues().empty());
}

TEST(Mcap, WriterRejectsUnknownIdsAndUnwritablePaths) {
  const std::string path = test::temp_path("bad_ids.mcap");
  mcap::McapWriter w(path);
  EXPECT_THROW(w.add_channel("/x", 3, "cdr"), IoError);
  const std::uint8_t b[1] = {1};
  EXPECT_THROW(w.write(7, 0, 0, b), IoError);
  w.close();
  EXPECT_THROW(w.write(1, 0, 0, b), IoError);
  EXPECT_THROW(mcap::McapWriter("/nonexistent_dir/x.mcap"), IoError);
  EXPECT_THROW(mcap::McapReader("/nonexistent_dir/x.mcap"), IoError);
}

TEST(Mcap, EmptyRecordingIsValid) {
  const std::string path = test::temp_path("empty.mcap");
  {
    mcap::McapWriter w(path);
    w.close();
  }
  mcap::McapReader r(path);
  mcap::MessageView m;
  EXPECT_FALSE(r.next(m));
  EXPECT_TRUE(r.issues().empty());
  ASSERT_TRUE(r.statistics().has_value());
  EXPECT_EQ(r.statistics()->message_count, 0u);
}

}  // namespace
}  // namespace vigs::io

namespace vigs::io {
namespace {

// Hand-built files in forms our writer never produces: Message records outside chunks, no
// summary (footer summary_start 0), and an lz4 chunk.
std::vector<std::uint8_t> record(mcap::Opcode op, const std::vector<std::uint8_t>& body) {
  std::vector<std::uint8_t> out;
  ByteWriter w(out);
  w.put(static_cast<std::uint8_t>(op));
  w.put<std::uint64_t>(body.size());
  w.put_bytes(body);
  return out;
}

std::vector<std::uint8_t> unchunked_file(bool with_lz4_chunk) {
  std::vector<std::uint8_t> file(std::begin(mcap::kMagic), std::end(mcap::kMagic));
  auto append = [&](const std::vector<std::uint8_t>& r) {
    file.insert(file.end(), r.begin(), r.end());
  };
  std::vector<std::uint8_t> b;
  ByteWriter w(b);
  w.put_string("ros1");
  w.put_string("hand-built");
  append(record(mcap::Opcode::kHeader, b));
  b.clear();
  w.put<std::uint16_t>(1);
  w.put_string("geometry_msgs/PoseStamped");
  w.put_string("ros1msg");
  const auto text = ros_msgs::schema_text<ros_msgs::PoseStamped>(ros_msgs::Encoding::kRos1);
  w.put(static_cast<std::uint32_t>(text.size()));
  w.put_bytes(text);
  append(record(mcap::Opcode::kSchema, b));
  b.clear();
  w.put<std::uint16_t>(3);
  w.put<std::uint16_t>(1);
  w.put_string("/pose");
  w.put_string("ros1");
  w.put<std::uint32_t>(0);
  append(record(mcap::Opcode::kChannel, b));
  for (int i = 0; i < 2; ++i) {
    if (with_lz4_chunk && i == 1) {
      b.clear();
      w.put<std::uint64_t>(0);
      w.put<std::uint64_t>(0);
      w.put<std::uint64_t>(4);
      w.put<std::uint32_t>(0);
      w.put_string("lz4");
      w.put<std::uint64_t>(4);
      w.put<std::uint32_t>(0x12345678);
      append(record(mcap::Opcode::kChunk, b));
    }
    std::vector<std::uint8_t> payload;
    ros_msgs::encode(test::sample_pose(i), ros_msgs::Encoding::kRos1, payload);
    b.clear();
    w.put<std::uint16_t>(3);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(i));
    w.put<std::uint64_t>(100u + i);
    w.put<std::uint64_t>(90u + i);
    w.put_bytes(payload);
    append(record(mcap::Opcode::kMessage, b));
  }
  b.clear();
  w.put(mcap::crc32(file));
  append(record(mcap::Opcode::kDataEnd, b));
  b.clear();
  w.put<std::uint64_t>(0);
  w.put<std::uint64_t>(0);
  w.put<std::uint32_t>(0);
  append(record(mcap::Opcode::kFooter, b));
  file.insert(file.end(), std::begin(mcap::kMagic), std::end(mcap::kMagic));
  return file;
}

TEST(McapForeign, UnchunkedMessagesWithoutSummaryAreRead) {
  const std::string path = test::temp_path("unchunked.mcap");
  test::save(path, unchunked_file(false));
  mcap::McapReader r(path);
  mcap::MessageView m;
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(r.next(m));
    EXPECT_EQ(m.channel->topic, "/pose");
    EXPECT_EQ(m.log_time_ns, 100u + i);
    EXPECT_EQ(m.publish_time_ns, 90u + i);
    ros_msgs::PoseStamped pose;
    ASSERT_TRUE(ros_msgs::decode_message(m, pose));
    EXPECT_EQ(pose, test::sample_pose(i));  // ROS 1 keeps seq
  }
  EXPECT_FALSE(r.next(m));
  EXPECT_FALSE(r.has_summary());
  EXPECT_TRUE(r.issues().empty()) << r.issues().front().message;
  EXPECT_EQ(r.profile(), "ros1");
  EXPECT_EQ(r.library(), "hand-built");
}

TEST(McapForeign, Lz4ChunkIsReportedAndSkipped) {
  const std::string path = test::temp_path("lz4.mcap");
  test::save(path, unchunked_file(true));
  mcap::McapReader r(path);
  const auto got = test::read_all(r);
  EXPECT_EQ(got.size(), 2u);  // the messages around the chunk
  ASSERT_EQ(r.issues().size(), 1u);
  EXPECT_EQ(r.issues()[0].kind, mcap::ReadIssue::Kind::kUnsupported);
  EXPECT_NE(r.issues()[0].message.find("lz4"), std::string::npos);
}

}  // namespace
}  // namespace vigs::io
