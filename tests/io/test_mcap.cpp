// MCAP writer/reader: round trip of every message type (CDR and ros1, zstd and uncompressed),
// file structure (summary, statistics, CRCs), topic filtering.
#include <gtest/gtest.h>

#include <cstring>

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

INSTANTIATE_TEST_SUITE_P(Formats, McapRoundTrip,
                         ::testing::Values(Case{Encoding::kCdr, mcap::Compression::kZstd, 4u << 20},
                                           Case{Encoding::kCdr, mcap::Compression::kZstd, 1000},
                                           Case{Encoding::kCdr, mcap::Compression::kNone, 1000},
                                           Case{Encoding::kRos1, mcap::Compression::kZstd, 1000},
                                           Case{Encoding::kRos1, mcap::Compression::kNone,
                                                4u << 20}));

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
